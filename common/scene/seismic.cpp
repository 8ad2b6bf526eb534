// Earthquakes in a scene (common/scene/seismic.hpp): the ground motion's kinematics, the motion
// CSV, and the readers of [seismic] and [base_motion] (docs/scenes.md, docs/seismic.md).
#include "common/scene/seismic.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "common/scene/reader.hpp"

namespace talus {
namespace {

using Vec2 = Eigen::Vector2d;

// The record's sample k, corrected.
Vec2 corrected(const BaseMotion& m, std::size_t k, const Vec2& c) { return m.acceleration[k] - c; }

// Velocity and displacement gained over the first `tau` seconds of the piecewise-linear
// acceleration a0 -> a1 over h (exact for the linear interpolant).
void advance(const Vec2& a0, const Vec2& a1, double h, double tau, Vec2& v, Vec2& u) {
  const Vec2 slope = (a1 - a0) / h;
  u += v * tau + a0 * (tau * tau / 2) + slope * (tau * tau * tau / 6);
  v += a0 * tau + slope * (tau * tau / 2);
}

// Velocity and displacement of the corrected record at record time tau (clamped to its span).
void record_state(const BaseMotion& m, double tau, Vec2& v, Vec2& u) {
  v.setZero();
  u.setZero();
  const Vec2 c = m.baseline();
  for (std::size_t k = 0; k + 1 < m.time.size() && tau > m.time[k]; ++k) {
    const double h = m.time[k + 1] - m.time[k];
    advance(corrected(m, k, c), corrected(m, k + 1, c), h, std::min(tau, m.time[k + 1]) - m.time[k], v, u);
  }
}

}  // namespace

double BaseMotion::duration() const {
  if (type == MotionType::Sine) return frequency > 0 ? cycles / frequency : 0.0;
  return time.empty() ? 0.0 : time.back();
}

Eigen::Vector2d BaseMotion::baseline() const {
  if (type == MotionType::Sine || time.size() < 2) return Vec2::Zero();
  Vec2 v = Vec2::Zero();
  for (std::size_t k = 0; k + 1 < time.size(); ++k) v += 0.5 * (acceleration[k] + acceleration[k + 1]) * (time[k + 1] - time[k]);
  return v / (time.back() - time.front());
}

Eigen::Vector2d BaseMotion::ground_acceleration(double t) const {
  const double tau = t - start;
  if (type == MotionType::Sine) {
    if (tau < 0 || tau > duration()) return Vec2::Zero();
    return Vec2(amplitude * std::sin(2 * M_PI * frequency * tau), 0);
  }
  if (time.size() < 2 || tau < time.front() || tau > time.back()) return Vec2::Zero();
  const std::size_t k = std::min<std::size_t>(
      std::upper_bound(time.begin(), time.end(), tau) - time.begin() - 1, time.size() - 2);
  const double s = (tau - time[k]) / (time[k + 1] - time[k]);
  return (1 - s) * acceleration[k] + s * acceleration[k + 1] - baseline();
}

Eigen::Vector2d BaseMotion::ground_velocity(double t) const {
  const double tau = std::min(t - start, duration());
  if (tau <= 0) return Vec2::Zero();
  if (type == MotionType::Sine) {
    const double omega = 2 * M_PI * frequency;
    return Vec2(amplitude / omega * (1 - std::cos(omega * tau)), 0);
  }
  Vec2 v, u;
  record_state(*this, tau, v, u);
  return v;
}

Eigen::Vector2d BaseMotion::ground_displacement(double t) const {
  const double tau = std::min(t - start, duration());
  if (tau <= 0) return Vec2::Zero();
  if (type == MotionType::Sine) {
    const double omega = 2 * M_PI * frequency;
    return Vec2(amplitude / omega * (tau - std::sin(omega * tau) / omega), 0);
  }
  Vec2 v, u;
  record_state(*this, tau, v, u);
  return u;
}

double BaseMotion::peak_acceleration() const {
  if (type == MotionType::Sine) return std::abs(amplitude);
  double peak = 0;
  const Vec2 c = baseline();
  for (std::size_t k = 0; k < time.size(); ++k) peak = std::max(peak, (acceleration[k] - c).norm());
  return peak;
}

std::string motion_record_problem(const std::vector<double>& time, const std::vector<Eigen::Vector2d>& acceleration) {
  if (time.size() != acceleration.size()) return "times and accelerations differ in number";
  for (std::size_t k = 0; k < time.size(); ++k) {
    const std::string row = "row " + std::to_string(k + 1) + ": ";
    if (!std::isfinite(time[k]) || !std::isfinite(acceleration[k].x()) || !std::isfinite(acceleration[k].y()))
      return row + "not a finite number";
    if (k == 0 && time[k] < 0) return row + "the time is negative (a record starts at t >= 0)";
    if (k > 0 && !(time[k] > time[k - 1])) {
      std::ostringstream message;
      message << row << "time " << time[k] << " s is not after " << time[k - 1]
              << " s of the row before: times must increase strictly";
      return message.str();
    }
  }
  if (time.size() < 2) return "expected at least two rows (t, a_x[, a_y]), got " + std::to_string(time.size());
  return "";
}

void read_motion_csv(const std::string& path, const std::string& scene_file, const std::string& item,
                     std::vector<double>& time, std::vector<Eigen::Vector2d>& acceleration) {
  const std::string where = "'" + path + "'";
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw Error(located(scene_file, item, "no such motion file " + where + " (expected a CSV of t, a_x[, a_y])"));
  std::ifstream in(path);
  if (!in) throw Error(located(scene_file, item, "cannot read " + where));
  time.clear();
  acceleration.clear();
  std::string line;
  long number = 0;
  bool header_allowed = true;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream stream(line);
    for (std::string cell; std::getline(stream, cell, ',');) cells.push_back(cell);
    std::vector<double> values;
    bool numeric = true;
    for (const auto& cell : cells) {
      std::size_t used = 0;
      double value = 0;
      try {
        value = std::stod(cell, &used);
      } catch (...) {
        numeric = false;
        break;
      }
      if (cell.find_first_not_of(" \t", used) != std::string::npos) {
        numeric = false;
        break;
      }
      values.push_back(value);
    }
    const std::string at = where + ", line " + std::to_string(number) + ": ";
    if (!numeric && header_allowed) {  // a header of column names
      header_allowed = false;
      continue;
    }
    header_allowed = false;
    if (!numeric || values.size() < 2 || values.size() > 3)
      throw Error(located(scene_file, item, at + "expected two or three numbers t, a_x[, a_y], got '" +
                                                escaped(line.substr(0, 80)) + "'"));
    for (double v : values)
      if (!std::isfinite(v)) throw Error(located(scene_file, item, at + "not a finite number"));
    if (time.empty() && values[0] < 0)
      throw Error(located(scene_file, item, at + "the time is negative (a record starts at t >= 0)"));
    if (!time.empty() && !(values[0] > time.back())) {
      std::ostringstream message;
      message << at << "time " << values[0] << " s is not after " << time.back()
              << " s of the row before: times must increase strictly";
      throw Error(located(scene_file, item, message.str()));
    }
    time.push_back(values[0]);
    acceleration.emplace_back(values[1], values.size() == 3 ? values[2] : 0.0);
  }
  if (const std::string problem = motion_record_problem(time, acceleration); !problem.empty())
    throw Error(located(scene_file, item, where + ": " + problem));
}

namespace scene_reader {

void read_seismic(TableReader& top, Scene& scene) {
  const toml::table* table = top.table("seismic");
  if (!table) return;
  TableReader r = top.child(table, "seismic");
  scene.seismic.k_h = r.number("k_h", 0.0, 0, 2);
  scene.seismic.k_v = r.number("k_v", 0.0, -1, 1, false, false);
  r.finish();
}

void read_absorbing(TableReader& r, const Scene& scene, Boundary& boundary) {
  boundary.material = r.text("material", std::nullopt);
  if (scene.material_index(boundary.material) < 0)
    r.fail("material", "no material named '" + echoed(boundary.material) + "' in [materials]");
  if (r.has("normal")) r.fail("normal", "an absorbing boundary takes its normals from the mesh");
}

void read_base_motion(TableReader& top, Scene& scene) {
  const toml::table* table = top.table("base_motion");
  if (!table) return;
  TableReader r = top.child(table, "base_motion");
  BaseMotion& m = scene.base_motion;
  m.boundaries = r.strings("boundaries");
  m.bodies = r.strings("bodies");
  for (const auto& name : m.boundaries)
    if (std::none_of(scene.boundaries.begin(), scene.boundaries.end(), [&](const Boundary& b) { return b.name == name; }))
      r.fail("boundaries", "no boundary named '" + echoed(name) + "' ([boundaries." + echoed(name) + "])");
  for (const auto& name : m.bodies) {
    const int index = scene.body_index(name);
    if (index < 0) r.fail("bodies", "no body named '" + echoed(name) + "' ([bodies." + echoed(name) + "])");
    if (!scene.bodies[index].fixed) r.fail("bodies", "body '" + echoed(name) + "' is not fixed (fixed = true)");
  }
  const std::string base = r.text("base", "rigid");
  if (base == "compliant") {
    // The motion enters as a stress through the listed absorbing boundaries (seismic.hpp).
    m.compliant = true;
    if (m.boundaries.empty()) r.fail("boundaries", "a compliant base needs at least one absorbing boundary");
    for (const auto& name : m.boundaries)
      for (const auto& b : scene.boundaries)
        if (b.name == name && b.type != BoundaryType::Absorbing)
          r.fail("boundaries", "boundary '" + name + "' is not absorbing: a compliant base inputs the motion through "
                               "absorbing boundaries (type = \"absorbing\")");
    if (!m.bodies.empty()) r.fail("bodies", "a compliant base moves no fixed body");
  } else if (base == "rigid") {
    // The whole base moves: the model is solved in the ground's frame (seismic.hpp).
    const std::string whole = ": the ground moves as one (the model is solved in its frame), so every boundary "
                              "and every fixed body moves with it; list it";
    for (const auto& b : scene.boundaries)
      if (std::find(m.boundaries.begin(), m.boundaries.end(), b.name) == m.boundaries.end())
        r.fail("boundaries", "boundary '" + b.name + "' is not listed" + whole);
    for (const auto& b : scene.bodies)
      if (b.fixed && std::find(m.bodies.begin(), m.bodies.end(), b.name) == m.bodies.end())
        r.fail("bodies", "fixed body '" + b.name + "' is not listed" + whole);
  } else {
    r.fail("base", "unknown base '" + echoed(base) + "' (expected rigid or compliant)");
  }
  const bool file = r.has("acceleration");
  const std::string type = r.text("type", file ? "record" : "");
  if (type == "sine") {
    if (file) r.fail("acceleration", "type = \"sine\" is a built-in record: no acceleration file with it");
    m.type = MotionType::Sine;
    m.amplitude = r.number("amplitude", std::nullopt, 0, 100 * 9.81, false);
    m.frequency = r.number("frequency", std::nullopt, 0, 1e4, false);
    m.cycles = static_cast<int>(r.integer("cycles", 1, 1, 100000));
  } else if (type == "record") {
    if (!file) r.fail("acceleration", "missing: a CSV file of t (s), a_x[, a_y] (m/s^2), or type = \"sine\"");
    m.type = MotionType::Record;
    m.file = r.text("acceleration", std::nullopt);
    const std::string path =
        (std::filesystem::path(top.file()).parent_path() / m.file).lexically_normal().string();
    read_motion_csv(path, top.file(), "base_motion.acceleration", m.time, m.acceleration);
  } else if (type.empty()) {
    r.fail("acceleration", "missing: a CSV file of t (s), a_x[, a_y] (m/s^2), or type = \"sine\"");
  } else {
    r.fail("type", "unknown type '" + echoed(type) + "' (expected sine, or record with acceleration = FILE)");
  }
  m.start = r.number("start", 0.0, 0, kInf);
  if (m.compliant && m.start < scene.run.gravity_ramp) {
    std::ostringstream message;
    message << "a compliant base's motion must start at or after the end of run.gravity_ramp (" << scene.run.gravity_ramp
            << " s): until then its absorbing boundaries are held fixed while gravity rises";
    r.fail("start", message.str());
  }
  r.finish();
}

}  // namespace scene_reader
}  // namespace talus
