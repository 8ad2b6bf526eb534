// The accuracy benchmark (bench/accuracy.cpp): its settings and options, and the measuring of
// one run (bench/accuracy_support.cpp) that its reports are made from.
#pragma once
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace talus::bench::accuracy {

struct Setting {
  double size = 0;  // m
  int particles_per_cell = 0;
  double cfl = 0;
};

// One run of one setting; `failure` is non-empty when the run threw.
struct Row {
  Setting setting;
  std::size_t elements = 0, particles = 0;
  long steps = 0;
  double loop_seconds = 0, wall_seconds = 0;
  double error = 0, error_at_1s = 0;  // analytical scenes
  double runout = 0, circle_x = 0, circle_y = 0, circle_r = 0;  // slope
  bool has_circle = false;
  std::string failure;
  double particle_updates() const { return static_cast<double>(particles) * steps; }
};

struct Options {
  bool quick = false, smallest = false, plots = true;
  int threads = 1;
  std::string out = "out/bench";
  std::vector<std::string> scenes = {"spring_mass", "box_incline", "slope"};
  std::vector<std::string> overrides;  // --set KEY=VALUE, for every run (before the setting's own)
  bool bspline = false;  // --family bspline: quadratic B-splines on the lattice, particle integration
};

// The settings of each scene, cheapest first in each mode.
std::vector<Setting> settings_for(const std::string& scene, const Options& options);

// "size 0.05 m, 4 per cell, CFL 0.5".
std::string describe(const Setting& s);

// Runs one setting of a scene and measures it; a run that throws gives a row with `failure`
// (an interrupt, Ctrl-C or SIGTERM, passes on and stops the sweep).
Row measure(const std::string& scene, const Setting& setting, const Options& options);

std::vector<double> column(const std::vector<Row>& rows, const std::function<double(const Row&)>& get);

// The columns every CSV starts with (mesh_size_m, particles_per_cell, cfl, elements, particles,
// steps), then `rest`.
std::vector<std::vector<double>> with_setting_columns(const std::vector<Row>& done,
                                                      std::vector<std::vector<double>> rest);

// Least-squares slope of log(difference) against log(size): the observed order of convergence
// towards the finest run. Needs at least two non-zero differences.
std::optional<double> observed_order(const std::vector<double>& size, const std::vector<double>& difference);

}  // namespace talus::bench::accuracy
