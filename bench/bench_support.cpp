#include "bench_support.hpp"

#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/error.hpp"
#include "common/scene/scene.hpp"
#include "postproc/results.hpp"
#include "preproc/preproc.hpp"

namespace talus::bench {

std::string scene_path(const std::string& name) {
  return std::string(TALUS_SOURCE_DIR) + "/geometries/" + name + ".toml";
}

Scratch::Scratch(const std::string& tag) {
  static int counter = 0;
  path_ = std::filesystem::temp_directory_path() /
          ("talus-bench-" + tag + "-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

Scratch::~Scratch() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::vector<std::string> particles_per_cell_overrides(const std::string& scene_file, int particles_per_cell) {
  std::vector<std::string> overrides;
  for (const Body& body : load_scene(scene_file).bodies)
    overrides.push_back("bodies." + body.name + ".particles_per_cell=" + std::to_string(particles_per_cell));
  return overrides;
}

double now_seconds() {
  using clock = std::chrono::steady_clock;
  return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

TimedRun run_model(const Model& model, const std::string& out_dir, int threads) {
  solver::SolveOptions options;
  options.out_dir = out_dir;
  options.progress = false;
  options.threads = threads;
  std::ostringstream log;
  TimedRun run;
  const double start = now_seconds();
  run.summary = solver::solve(model, options, log);
  run.wall_seconds = now_seconds() - start;
  run.elements = model.triangles.size();
  return run;
}

TimedRun run_scene(const std::string& scene_file, const std::vector<std::string>& overrides,
                   const std::string& out_dir, int threads) {
  const double start = now_seconds();
  const Scene scene = load_scene(scene_file, overrides);
  const Model model = preproc::build_model(scene);
  const double meshed = now_seconds();
  TimedRun run = run_model(model, out_dir, threads);
  run.mesh_seconds = meshed - start;
  run.wall_seconds += run.mesh_seconds;
  return run;
}

BodyTrack track_body(const std::string& results_file, const std::string& body) {
  const postproc::Results results = postproc::read_results(results_file);
  const auto& bodies = results.metadata.bodies;
  const auto found = std::find_if(bodies.begin(), bodies.end(), [&](const BodyInfo& b) { return b.name == body; });
  if (found == bodies.end()) throw Error(located(results_file, "bodies", "no body named '" + body + "'"));
  const int index = static_cast<int>(found - bodies.begin());
  auto centre = [&](const std::vector<Eigen::Vector2d>& x_p) {
    Eigen::Vector2d moment = Eigen::Vector2d::Zero();
    double mass = 0;
    for (std::size_t p = 0; p < results.particles(); ++p)
      if (results.body[p] == index) moment += results.mass[p] * x_p[p], mass += results.mass[p];
    return Eigen::Vector2d(moment / mass);
  };
  BodyTrack track;
  track.time = results.frame_time;
  for (const auto& frame : results.position) track.centre.push_back(centre(frame));
  track.initial = centre(results.initial_position);
  return track;
}

postproc::SpringMassCheck spring_mass_check(const std::string& results_file, const std::string& body,
                                            double amplitude, double omega) {
  const BodyTrack track = track_body(results_file, body);
  std::vector<double> height;
  for (const auto& c : track.centre) height.push_back(c.y());
  return postproc::spring_mass_check(track.time, height, track.initial.y(), amplitude, omega);
}

postproc::BoxInclineCheck box_incline_check(const std::string& results_file, const std::string& body,
                                            double angle_deg, const Eigen::Vector2d& gravity, double friction,
                                            double gravity_ramp) {
  const BodyTrack track = track_body(results_file, body);
  std::vector<Eigen::Vector2d> displacement;
  for (const auto& c : track.centre) displacement.push_back(c - track.initial);
  return postproc::box_incline_check(track.time, displacement, angle_deg, gravity, friction, gravity_ramp);
}

std::optional<double> json_number(const std::string& json, const std::string& key, const std::string& after) {
  std::size_t from = 0;
  if (!after.empty()) {
    from = json.find("\"" + after + "\"");
    if (from == std::string::npos) return std::nullopt;
  }
  const std::size_t at = json.find("\"" + key + "\"", from);
  if (at == std::string::npos) return std::nullopt;
  const std::size_t colon = json.find(':', at);
  if (colon == std::string::npos) return std::nullopt;
  const char* text = json.c_str() + colon + 1;
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text) return std::nullopt;  // null or not a number
  return value;
}

std::vector<bool> pareto_front(const std::vector<double>& cost, const std::vector<double>& error) {
  std::vector<bool> front(cost.size(), true);
  for (std::size_t i = 0; i < cost.size(); ++i)
    for (std::size_t j = 0; j < cost.size() && front[i]; ++j)
      if (j != i && cost[j] <= cost[i] && error[j] <= error[i] && (cost[j] < cost[i] || error[j] < error[i]))
        front[i] = false;
  return front;
}

std::string fixed(double value, int digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

std::string general(double value, int digits) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

std::string machine_line() {
  utsname name{};
  uname(&name);
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  double load[3] = {0, 0, 0};
  getloadavg(load, 3);
  return cpu + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores, " + name.sysname + " " +
         name.release + "; load average at the end " + fixed(load[0], 2);
}

int run_plot_script(const std::vector<std::string>& args) {
  std::string command = "/usr/bin/python3 '" + std::string(TALUS_SOURCE_DIR) + "/bench/plot_benchmarks.py'";
  for (const auto& arg : args) command += " '" + arg + "'";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

}  // namespace talus::bench
