// The stability benchmark's helpers (bench/stability.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "common/error.hpp"
#include "common/geometry.hpp"
#include "common/h5.hpp"
#include "common/scene/scene.hpp"
#include "postproc/output.hpp"
#include "preproc/preproc.hpp"
#include "stability.hpp"

namespace talus::bench::stability {
namespace {

// A CSV cell: quoted when it holds a comma or a quote.
std::string cell(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

FileScan scan_results(const std::string& path) {
  FileScan scan;
  if (!std::filesystem::exists(path)) return scan;
  scan.exists = true;
  const h5::File file = h5::File::open_read(path);
  scan.complete = h5::get_int(file, "/", "complete");
  for (const std::string group : {"frames", "history"})
    for (const std::string& name : h5::list(file, group)) {
      const auto values = h5::read_doubles(file, group + "/" + name);
      scan.nonfinite += std::count_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); });
      if (group == "frames" && name == "time") scan.frames = static_cast<long>(values.size());
    }
  return scan;
}

Outcome run_and_scan(const Model& model, const std::string& folder, int threads) {
  Outcome outcome;
  const double start = bench::now_seconds();
  try {
    const bench::TimedRun timed = bench::run_model(model, folder, threads);
    outcome.kind = "completed";
    outcome.steps = timed.summary.steps;
  } catch (const Error& error) {
    outcome.message = error.what();
    outcome.kind = outcome.message.find("blow-up") != std::string::npos         ? "blow-up"
                   : outcome.message.find("left the domain") != std::string::npos ? "left the domain"
                                                                                  : "error";
  }
  outcome.wall_seconds = bench::now_seconds() - start;
  outcome.scan = scan_results(folder + "/results.h5");
  if (outcome.kind != "completed" && outcome.scan.exists)
    outcome.steps = h5::get_int(h5::File::open_read(folder + "/results.h5"), "/", "steps");
  return outcome;
}

Model build_scene(const std::string& scene, const std::vector<std::string>& overrides) {
  return preproc::build_model(load_scene(bench::scene_path(scene), overrides));
}

int body_index(const Model& model, const std::string& name) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].name == name) return static_cast<int>(b);
  throw Error("no body named '" + name + "'");
}

void write_table(const std::string& path, const std::vector<std::string>& header,
                 const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream text;
  for (std::size_t i = 0; i < header.size(); ++i) text << (i ? "," : "") << header[i];
  text << "\n";
  for (const auto& row : rows) {
    for (std::size_t i = 0; i < row.size(); ++i) text << (i ? "," : "") << cell(row[i]);
    text << "\n";
  }
  postproc::write_file_atomically(path, text.str());
}

std::string short_message(const std::string& message) {
  return message.size() > 160 ? message.substr(0, 157) + "..." : message;
}

double box_error(const std::string& results, double friction) {
  const auto check = bench::box_incline_check(results, "box", 30, Eigen::Vector2d(0, -10), friction, 0.0);
  if (check.relative_error.empty() || !check.relative_error.back()) return NAN;
  return *check.relative_error.back();
}

double spring_error(const std::string& results) {
  return bench::spring_mass_check(results, "mass", 1e-3, 100).max_error_over_amplitude;
}

void set_body_velocity(Model& model, int body, const Eigen::Vector2d& v) {
  for (std::size_t p = 0; p < model.particle_count(); ++p)
    if (model.body[p] == body) model.velocity[p] = v;
}

EnergyRecord read_energy(const std::string& results) {
  const h5::File file = h5::File::open_read(results);
  EnergyRecord record;
  record.time = h5::read_doubles(file, "history/time");
  const auto grid = h5::read_doubles(file, "history/kinetic_energy");
  const auto particle = h5::read_doubles(file, "history/particle_kinetic_energy");
  const auto potential = h5::read_doubles(file, "history/potential_energy");
  record.strain = h5::read_doubles(file, "history/strain_energy");
  for (std::size_t k = 0; k < record.time.size(); ++k) {
    record.total_grid.push_back(grid[k] + potential[k] + record.strain[k]);
    record.total_particle.push_back(particle[k] + potential[k] + record.strain[k]);
  }
  return record;
}

std::size_t perturb_positions(Model& model, std::mt19937& random, double fraction) {
  std::uniform_real_distribution<double> unit(0, 1);
  std::size_t moved = 0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const auto& tri = model.triangles[model.element[p]];
    double r1 = unit(random), r2 = unit(random);
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;  // uniform in the triangle
    const Eigen::Vector2d target = model.nodes[tri[0]] + r1 * (model.nodes[tri[1]] - model.nodes[tri[0]]) +
                                   r2 * (model.nodes[tri[2]] - model.nodes[tri[0]]);
    const Eigen::Vector2d x = model.position[p] + fraction * unit(random) * (target - model.position[p]);
    if (inside_loops(model.bodies[model.body[p]].loops, x)) model.position[p] = x, ++moved;
  }
  return moved;
}

bool inside_mesh(const Model& model, const Eigen::Vector2d& x) {
  for (const auto& t : model.triangles) {
    const Eigen::Vector2d a = model.nodes[t[0]], b = model.nodes[t[1]], c = model.nodes[t[2]];
    auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
    const double area = cross(b - a, c - a), tol = -1e-9 * std::abs(area);
    if (cross(b - a, x - a) >= tol && cross(c - b, x - b) >= tol && cross(a - c, x - c) >= tol) return true;
  }
  return false;
}

}  // namespace talus::bench::stability
