#include "common/model/checks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.hpp"

namespace talus {

std::string run_settings_problem(const RunSettings& run) {
  struct Check {
    const char* name;
    bool ok;
    const char* expected;
  };
  const Check checks[] = {
      {"end_time", run.end_time > 0 && std::isfinite(run.end_time), "a finite time > 0"},
      {"cfl", run.cfl > 0 && run.cfl <= 1, "a number in (0, 1]"},
      {"output_interval", run.output_interval > 0 && std::isfinite(run.output_interval), "a finite time > 0"},
      {"pic_fraction", run.pic_fraction >= 0 && run.pic_fraction <= 1, "a number in [0, 1]"},
      {"gravity_ramp", run.gravity_ramp >= 0 && std::isfinite(run.gravity_ramp), "a finite time >= 0"},
      {"gravity", std::hypot(run.gravity.x(), run.gravity.y()) <= kMaxGravity, "a magnitude of at most 1000 m/s^2"},
      {"history_interval", run.history_interval >= 1, "an integer >= 1"},
      {"damping", run.damping >= 0 && run.damping < 1, "a number in [0, 1)"},
      {"rest_ratio", run.rest_ratio >= 0 && run.rest_ratio < 1, "a number in [0, 1)"},
      {"rest_window", run.rest_window > 0, "a time > 0"},
      {"max_steps", run.max_steps >= 0, "an integer >= 0"},
      {"xpic_order", run.xpic_order >= 1 && run.xpic_order <= 100, "an integer in [1, 100]"},
      {"full_cell_fill", run.full_cell_fill >= 0 && run.full_cell_fill <= 1, "a number in [0, 1] (0: no mixed integration)"},
  };
  for (const auto& check : checks)
    if (!check.ok) return std::string("settings/run@") + check.name + ": out of range, expected " + check.expected;
  return "";
}

std::string load_problem(const SurfaceLoad& load) {
  if (load.pressure.has_value() == load.traction.has_value()) return "expected either a pressure or a traction";
  if (load.pressure && !std::isfinite(*load.pressure)) return "pressure: expected a finite number";
  if (load.traction && !load.traction->allFinite()) return "traction: expected two finite numbers";
  if (!(load.ramp >= 0) || !std::isfinite(load.ramp)) return "ramp: expected a finite time >= 0";
  return "";
}

void check_particle_loads(const Model& model, const std::string& path) {
  const int32_t loads = static_cast<int32_t>(model.loads.size());
  for (std::size_t p = 0; p < model.load.size(); ++p) {
    if (model.load[p] < -1 || model.load[p] >= loads)
      throw Error(located(path, "particles/load", "load index out of range for particle " + std::to_string(p)));
    const double length = model.load_length[p];
    if (!(length >= 0) || model.load_normal[p].norm() > length * (1 + 1e-9) + 1e-300)
      throw Error(located(path, "particles/load_length, particles/load_normal",
                          "particle " + std::to_string(p) +
                              " has a negative length or a normal sum longer than its length"));
  }
}

void check_model_geometry(const Model& model, const std::string& path) {
  auto twice_area = [&](const std::array<int32_t, 3>& t) {
    const Eigen::Vector2d a = model.nodes[t[1]] - model.nodes[t[0]], b = model.nodes[t[2]] - model.nodes[t[0]];
    return a.x() * b.y() - a.y() * b.x();
  };
  for (std::size_t e = 0; e < model.triangles.size(); ++e) {
    const double area2 = twice_area(model.triangles[e]);
    if (!(area2 > 0)) {
      std::ostringstream message;
      message << "element " << e << " is degenerate or clockwise (twice its area is " << area2 << ")";
      throw Error(located(path, "mesh/triangles", message.str()));
    }
  }
  for (std::size_t k = 0; k < model.roller_normals.size(); ++k)
    if (!(model.roller_normals[k].norm() > 0))
      throw Error(located(path, "boundary_conditions/roller_normals",
                          "row " + std::to_string(k) + " is [0, 0]: a roller needs the direction it is held in"));
  for (std::size_t k = 0; k < model.friction_normals.size(); ++k)
    if (!(model.friction_normals[k].norm() > 0))
      throw Error(located(path, "boundary_conditions/friction_normals",
                          "row " + std::to_string(k) + " is [0, 0]: a friction node needs its outward normal"));
  // Barycentric weights: a particle on an edge is inside, one beyond it by more than round-off
  // is not.
  constexpr double kTolerance = 1e-9;
  for (std::size_t p = 0; p < model.position.size(); ++p) {
    const auto& t = model.triangles[model.element[p]];
    const double whole = twice_area(t);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d a = model.nodes[t[(k + 1) % 3]] - model.position[p];
      const Eigen::Vector2d b = model.nodes[t[(k + 2) % 3]] - model.position[p];
      if ((a.x() * b.y() - a.y() * b.x()) / whole < -kTolerance) {
        std::ostringstream message;
        message << "particle " << p << " at (" << model.position[p].x() << ", " << model.position[p].y()
                << ") m is not inside its element " << model.element[p];
        throw Error(located(path, "particles/element", message.str()));
      }
    }
  }
  if (const auto problem = initial_state_problem(model))
    throw Error(located(path, problem->speed ? "particles/velocity" : "particles/stress", problem->message));
}

std::optional<InitialStateProblem> initial_state_problem(const Model& model) {
  // The smallest element height, as the solver takes it (twice the area over the longest edge).
  double h_min = INFINITY;
  for (const auto& t : model.triangles) {
    const Eigen::Vector2d a = model.nodes[t[0]], b = model.nodes[t[1]], c = model.nodes[t[2]];
    const double twice_area = std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    if (longest > 0) h_min = std::min(h_min, twice_area / longest);
  }
  const double fastest = model.run.cfl * h_min / (model.run.end_time * std::numeric_limits<double>::epsilon());
  std::ostringstream message;
  message.precision(3);
  for (std::size_t p = 0; p < model.position.size(); ++p) {
    const double speed = std::hypot(model.velocity[p].x(), model.velocity[p].y());  // no overflow at 1e308
    if (speed > fastest) {
      message << "particle " << p << " moves at " << speed << " m/s: its CFL time step, run.cfl x " << h_min
              << " m (the smallest element height) / " << speed << " m/s, is too small for the time to pass "
              << "run.end_time = " << model.run.end_time << " s; at most " << fastest << " m/s";
      return InitialStateProblem{p, true, message.str()};
    }
    const Material& material = model.materials.at(model.bodies.at(model.body[p]).material);
    const double stress = model.stress[p].cwiseAbs().maxCoeff();
    if (!(stress <= kMaxInitialStrain * material.youngs_modulus)) {
      message << "particle " << p << " starts with a stress of " << stress << " Pa, " << stress / material.youngs_modulus
              << " times the Young's modulus of material '" << material.name << "' (" << material.youngs_modulus
              << " Pa): an elastic strain no soil or rock takes (at most " << kMaxInitialStrain << ")";
      return InitialStateProblem{p, false, message.str()};
    }
  }
  return std::nullopt;
}

void check_particle_count(const h5::File& file, std::size_t count) {
  if (!h5::has_attribute(file, "/", "particles")) throw Error(located(file.path(), "@particles", "missing"));
  const int64_t said = h5::get_int(file, "/", "particles");
  if (said != static_cast<int64_t>(count))
    throw Error(located(file.path(), "@particles", "says " + std::to_string(said) + " particles, the particle datasets have " +
                                                       std::to_string(count) + " rows"));
}

void check_frame_times(const std::vector<double>& time, const std::string& path) {
  for (std::size_t k = 0; k < time.size(); ++k) {
    if (!std::isfinite(time[k]) || time[k] < 0)
      throw Error(located(path, "frames/time", "frame " + std::to_string(k) + " has a time that is not finite and >= 0"));
    if (k > 0 && time[k] < time[k - 1])
      throw Error(located(path, "frames/time", "frame " + std::to_string(k) + " is earlier than frame " +
                                                   std::to_string(k - 1) + " (times must not go back)"));
  }
}

}  // namespace talus
