// The accuracy benchmark's settings and measurements (bench/accuracy.hpp).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "accuracy.hpp"
#include "bench_support.hpp"
#include "common/error.hpp"
#include "common/scene/scene.hpp"
#include "postproc/postproc.hpp"
#include "solver/solver.hpp"

namespace talus::bench::accuracy {

namespace {

std::vector<Setting> grid(const std::vector<double>& sizes, const std::vector<int>& counts,
                          const std::vector<double>& cfls) {
  std::vector<Setting> settings;
  for (double h : sizes)
    for (int n : counts)
      for (double cfl : cfls) settings.push_back({h, n, cfl});
  return settings;
}

}  // namespace

std::vector<Setting> settings_for(const std::string& scene, const Options& options) {
  if (scene == "spring_mass") {
    if (options.smallest) return {{0.1, 1, 1.0}};
    if (options.quick) return grid({0.1, 0.05}, {1, 4, 10}, {0.5, 1.0});
    return grid({0.1, 0.05, 0.025}, {1, 3, 4, 6, 10}, {0.25, 0.5, 1.0});
  }
  if (scene == "box_incline") {
    if (options.smallest) return {{0.05, 1, 1.0}};
    if (options.quick) return grid({0.05, 0.025}, {1, 4, 10}, {0.5, 1.0});
    return grid({0.05, 0.035, 0.025}, {1, 3, 4, 6, 10}, {0.25, 0.5, 1.0});
  }
  // The slope at the scene's own 4 particles per cell and CFL 0.5, refined.
  if (options.quick) return grid({1.0, 0.7, 0.5}, {4}, {0.5});
  return grid({1.0, 0.7, 0.5, 0.35, 0.25}, {4}, {0.5});
}

std::string describe(const Setting& s) {
  char text[96];
  std::snprintf(text, sizeof text, "size %.4g m, %d per cell, CFL %.2g", s.size, s.particles_per_cell, s.cfl);
  return text;
}

Row measure(const std::string& scene, const Setting& setting, const Options& options) {
  Row row;
  row.setting = setting;
  // The lattice needs an axis-aligned domain: with B-splines the box slides on the level slab of
  // box_incline_level.toml under tilted gravity, the same exact answer.
  const std::string file =
      bench::scene_path(options.bspline && scene == "box_incline" ? std::string("box_incline_level") : scene);
  std::vector<std::string> overrides = options.overrides;
  if (options.bspline) {  // the spring-mass scene's mixed integration is for linear triangles
    for (const char* o : {"run.shape_functions=bspline", "mesh.pattern=grid", "run.integration=material_points"})
      overrides.push_back(o);
  }
  for (std::string& o : bench::particles_per_cell_overrides(file, setting.particles_per_cell))
    overrides.push_back(std::move(o));
  char value[64];
  std::snprintf(value, sizeof value, "mesh.size=%.17g", setting.size);
  overrides.push_back(value);
  std::snprintf(value, sizeof value, "run.cfl=%.17g", setting.cfl);
  overrides.push_back(value);
  bench::Scratch scratch("accuracy");
  try {
    const bench::TimedRun run = bench::run_scene(file, overrides, scratch.path().string(), options.threads);
    row.elements = run.elements;
    row.particles = run.summary.particles;
    row.steps = run.summary.steps;
    row.loop_seconds = run.summary.loop_seconds;
    row.wall_seconds = run.wall_seconds;
    const Scene parsed = load_scene(file, overrides);
    const PostSettings& post = parsed.post;
    const std::string results = scratch.file("results.h5");
    if (scene == "spring_mass") {
      row.error = bench::spring_mass_check(results, post.body, post.spring_amplitude, post.spring_omega)
                      .max_error_over_amplitude;
      row.error_at_1s = row.error;
    } else if (scene == "box_incline") {
      std::string other;
      for (const Body& b : parsed.bodies)
        if (b.name != post.body) other = b.name;
      const auto check = bench::box_incline_check(results, post.body, post.incline_angle, parsed.run.gravity,
                                                  pair_friction(parsed.contact, post.body, other), parsed.run.gravity_ramp);
      if (check.relative_error.size() != 4 || !check.relative_error.back())
        throw Error("box_incline: the run does not reach the four check times");
      row.error = 0;
      for (const auto& e : check.relative_error) row.error = std::max(row.error, e.value());
      row.error_at_1s = check.relative_error.back().value();
    } else {
      postproc::PostOptions post_options;
      post_options.figures = false;
      std::ostringstream log;
      postproc::run_post(results, scratch.path().string(), log, post_options);
      std::ifstream in(scratch.file("metrics.json"));
      std::stringstream json;
      json << in.rdbuf();
      const auto runout = bench::json_number(json.str(), "runout_distance_m");
      if (!runout) throw Error("slope: no runout in metrics.json (no deposit found)");
      row.runout = *runout;
      const auto x = bench::json_number(json.str(), "xc_m", "slip_circle");
      const auto y = bench::json_number(json.str(), "yc_m", "slip_circle");
      const auto r = bench::json_number(json.str(), "r_m", "slip_circle");
      row.has_circle = x && y && r;
      if (row.has_circle) row.circle_x = *x, row.circle_y = *y, row.circle_r = *r;
    }
  } catch (const solver::Interrupted&) {
    throw;  // Ctrl-C or SIGTERM stops the sweep, not just this run
  } catch (const std::exception& error) {
    row.failure = error.what();
  }
  return row;
}

std::vector<double> column(const std::vector<Row>& rows, const std::function<double(const Row&)>& get) {
  std::vector<double> values;
  for (const Row& row : rows) values.push_back(get(row));
  return values;
}

std::vector<std::vector<double>> with_setting_columns(const std::vector<Row>& done,
                                                      std::vector<std::vector<double>> rest) {
  std::vector<std::vector<double>> columns = {
      column(done, [](const Row& r) { return r.setting.size; }),
      column(done, [](const Row& r) { return double(r.setting.particles_per_cell); }),
      column(done, [](const Row& r) { return r.setting.cfl; }),
      column(done, [](const Row& r) { return double(r.elements); }),
      column(done, [](const Row& r) { return double(r.particles); }),
      column(done, [](const Row& r) { return double(r.steps); })};
  columns.insert(columns.end(), rest.begin(), rest.end());
  return columns;
}

std::optional<double> observed_order(const std::vector<double>& size, const std::vector<double>& difference) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < size.size(); ++i)
    if (difference[i] > 0) {
      const double x = std::log(size[i]), y = std::log(difference[i]);
      sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
    }
  if (n < 2 || !(n * sxx - sx * sx > 0)) return std::nullopt;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace talus::bench::accuracy
