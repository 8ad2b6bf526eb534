// Accuracy against cost: sweeps element size (mesh.size), particles per cell and CFL number over
// the validation scenes and measures the error against their analytical solutions, the steps,
// particles and time of each run; for the slope (no analytical solution) it reports the runout
// and slip circle against element size and their observed convergence.
//
//   talus_bench_accuracy                    the full sweep (long: tens of minutes on 2 cores)
//   talus_bench_accuracy --quick            a reduced grid, a few minutes
//   talus_bench_accuracy --smallest         one (the cheapest) setting per analytical scene, seconds
//   talus_bench_accuracy --quick --scenes spring_mass,slope --out DIR --threads 2
//
// Writes to DIR (default out/bench): accuracy_spring_mass.csv, accuracy_box_incline.csv,
// accuracy_slope.csv, accuracy.md, and bench_accuracy_*.png (drawn by bench/plot_benchmarks.py).
// Error measures (as the validation tests):
//   spring_mass  max over the frames of |y_mpm - y_exact| / A over two periods, y the settlement
//                of the mass body's centre of mass, y_exact = A (1 - cos(omega t)), A = 1e-3 m
//   box_incline  relative error of the box's centre-of-mass displacement along the slope against
//                0.5 g (sin 30 - mu cos 30) t^2 at t = 0.25, 0.5, 0.75, 1 s; `error` is the
//                largest of the four (the one plotted and used for the recommendation),
//                `error_at_1s` the last.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench_support.hpp"
#include "common/error.hpp"
#include "common/scene.hpp"
#include "postproc/output.hpp"
#include "postproc/postproc.hpp"
#include "postproc/validation.hpp"

namespace {

using namespace talus;
using bench::fixed;
using bench::general;

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
};

std::vector<Setting> grid(const std::vector<double>& sizes, const std::vector<int>& counts,
                          const std::vector<double>& cfls) {
  std::vector<Setting> settings;
  for (double h : sizes)
    for (int n : counts)
      for (double cfl : cfls) settings.push_back({h, n, cfl});
  return settings;
}

// The settings of each scene, cheapest first in each mode.
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

// Runs one setting of a scene and measures it.
Row measure(const std::string& scene, const Setting& setting, const Options& options) {
  Row row;
  row.setting = setting;
  const std::string file = bench::scene_path(scene);
  std::vector<std::string> overrides = bench::particles_per_cell_overrides(file, setting.particles_per_cell);
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
      const bench::BodyTrack track = bench::track_body(results, post.body);
      std::vector<double> height;
      for (const auto& c : track.centre) height.push_back(c.y());
      row.error = postproc::spring_mass_check(track.time, height, track.initial.y(), post.spring_amplitude,
                                              post.spring_omega)
                      .max_error_over_amplitude;
      row.error_at_1s = row.error;
    } else if (scene == "box_incline") {
      const bench::BodyTrack track = bench::track_body(results, post.body);
      std::vector<Eigen::Vector2d> displacement;
      for (const auto& c : track.centre) displacement.push_back(c - track.initial);
      std::string other;
      for (const Body& b : parsed.bodies)
        if (b.name != post.body) other = b.name;
      const auto check = postproc::box_incline_check(track.time, displacement, post.incline_angle,
                                                     parsed.run.gravity.norm(),
                                                     pair_friction(parsed.contact, post.body, other));
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

// The columns every CSV starts with (mesh_size_m, particles_per_cell, cfl, elements, particles,
// steps), then `rest`.
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

// Least-squares slope of log(difference) against log(size): the observed order of convergence
// towards the finest run. Needs at least two non-zero differences.
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

// CSV, Markdown section and recommendation of an analytical scene.
std::string report_analytical(const std::string& scene, std::vector<Row> rows, const Options& options) {
  std::vector<Row> done, failed;
  for (const Row& row : rows) (row.failure.empty() ? done : failed).push_back(row);
  std::sort(done.begin(), done.end(), [](const Row& a, const Row& b) { return a.wall_seconds < b.wall_seconds; });
  const auto wall = column(done, [](const Row& r) { return r.wall_seconds; });
  const auto error = column(done, [](const Row& r) { return r.error; });
  const std::vector<bool> front = bench::pareto_front(wall, error);
  std::vector<double> flags;
  for (bool f : front) flags.push_back(f ? 1 : 0);
  postproc::write_csv(
      (std::filesystem::path(options.out) / ("accuracy_" + scene + ".csv")).string(),
      {"mesh_size_m", "particles_per_cell", "cfl", "elements", "particles", "steps", "particle_updates",
       "loop_seconds", "wall_seconds", "error", "error_at_1s", "pareto"},
      with_setting_columns(done, {column(done, [](const Row& r) { return r.particle_updates(); }),
                                  column(done, [](const Row& r) { return r.loop_seconds; }), wall, error,
                                  column(done, [](const Row& r) { return r.error_at_1s; }), flags}));

  const Row* best = nullptr;  // the cheapest run (wall time) within 1%
  for (const Row& row : done)
    if (row.error <= 0.01 && (!best || row.wall_seconds < best->wall_seconds)) best = &row;
  const Row* lowest = nullptr;
  for (const Row& row : done)
    if (!lowest || row.error < lowest->error) lowest = &row;

  std::ostringstream md;
  md << "## " << scene << "\n\n";
  if (scene == "spring_mass")
    md << "Error: max over the frames (two periods) of |y_mpm - y_exact| / 1e-3 m, y the settlement of the "
          "mass body's centre of mass.\n\n";
  else
    md << "Error: largest relative error of the box's centre-of-mass displacement along the slope at "
          "t = 0.25, 0.5, 0.75, 1 s (`error`); `at 1 s` is the last of the four.\n\n";
  md << "| mesh size (m) | per cell | CFL | elements | particles | steps | particle-updates | loop (s) | wall (s) "
        "| error | at 1 s | |\n";
  md << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (std::size_t i = 0; i < done.size(); ++i) {
    const Row& r = done[i];
    std::string mark = front[i] ? "Pareto" : "";
    if (&r == best) mark += mark.empty() ? "**recommended**" : ", **recommended**";
    md << "| " << general(r.setting.size) << " | " << r.setting.particles_per_cell << " | " << general(r.setting.cfl)
       << " | " << r.elements << " | " << r.particles << " | " << r.steps << " | " << general(r.particle_updates())
       << " | " << fixed(r.loop_seconds, 2) << " | " << fixed(r.wall_seconds, 2) << " | "
       << fixed(100 * r.error, 2) << "% | " << fixed(100 * r.error_at_1s, 2) << "% | " << mark << " |\n";
  }
  for (const Row& r : failed) md << "\nFailed: " << describe(r.setting) << ": " << r.failure << "\n";
  md << "\n";
  if (best)
    md << "**Recommended** (cheapest wall time with error <= 1%): " << describe(best->setting) << ": error "
       << fixed(100 * best->error, 2) << "%, " << fixed(best->wall_seconds, 2) << " s, " << best->particles
       << " particles, " << best->steps << " steps.\n\n";
  else if (lowest)
    md << "**No setting meets 1% error.** The lowest is " << fixed(100 * lowest->error, 2) << "% ("
       << describe(lowest->setting) << ", " << fixed(lowest->wall_seconds, 2) << " s).\n\n";
  return md.str();
}

std::string report_slope(std::vector<Row> rows, const Options& options) {
  std::vector<Row> done, failed;
  for (const Row& row : rows) (row.failure.empty() ? done : failed).push_back(row);
  std::sort(done.begin(), done.end(), [](const Row& a, const Row& b) { return a.setting.size > b.setting.size; });
  std::ostringstream md;
  md << "## slope (no analytical solution: convergence with element size)\n\n";
  if (done.empty()) {
    for (const Row& r : failed) md << "Failed: " << describe(r.setting) << ": " << r.failure << "\n";
    return md.str() + "\n";
  }
  const Row& finest = done.back();
  std::vector<double> runout_difference, centre_difference, radius_difference;
  for (const Row& r : done) {
    runout_difference.push_back(std::abs(r.runout - finest.runout));
    const bool circles = r.has_circle && finest.has_circle;
    centre_difference.push_back(circles ? std::hypot(r.circle_x - finest.circle_x, r.circle_y - finest.circle_y) : NAN);
    radius_difference.push_back(circles ? std::abs(r.circle_r - finest.circle_r) : NAN);
  }
  postproc::write_csv((std::filesystem::path(options.out) / "accuracy_slope.csv").string(),
                      {"mesh_size_m", "particles_per_cell", "cfl", "elements", "particles", "steps", "loop_seconds",
                       "wall_seconds", "runout_m", "slip_circle_xc_m", "slip_circle_yc_m", "slip_circle_r_m",
                       "runout_difference_to_finest_m", "slip_centre_difference_to_finest_m",
                       "slip_radius_difference_to_finest_m"},
                      with_setting_columns(done, {column(done, [](const Row& r) { return r.loop_seconds; }),
                       column(done, [](const Row& r) { return r.wall_seconds; }),
                       column(done, [](const Row& r) { return r.runout; }),
                       column(done, [](const Row& r) { return r.has_circle ? r.circle_x : NAN; }),
                       column(done, [](const Row& r) { return r.has_circle ? r.circle_y : NAN; }),
                       column(done, [](const Row& r) { return r.has_circle ? r.circle_r : NAN; }), runout_difference,
                       centre_difference, radius_difference}));
  md << "Scene defaults otherwise (4 particles per cell, CFL 0.5, EVS on, run to rest). Differences are to the "
        "finest run (" << general(finest.setting.size) << " m).\n\n";
  md << "| mesh size (m) | elements | particles | steps | wall (s) | runout (m) | diff. (m) | slip circle "
        "centre, r (m) | centre diff. (m) | r diff. (m) |\n|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|\n";
  for (std::size_t i = 0; i < done.size(); ++i) {
    const Row& r = done[i];
    md << "| " << general(r.setting.size) << " | " << r.elements << " | " << r.particles << " | " << r.steps << " | "
       << fixed(r.wall_seconds, 1) << " | " << fixed(r.runout, 2) << " | " << fixed(runout_difference[i], 2) << " | "
       << (r.has_circle ? "(" + fixed(r.circle_x, 2) + ", " + fixed(r.circle_y, 2) + "), " + fixed(r.circle_r, 2)
                        : std::string("none"))
       << " | " << fixed(centre_difference[i], 2) << " | " << fixed(radius_difference[i], 2) << " |\n";
  }
  for (const Row& r : failed) md << "\nFailed: " << describe(r.setting) << ": " << r.failure << "\n";
  std::vector<double> sizes = column(done, [](const Row& r) { return r.setting.size; });
  sizes.pop_back();
  runout_difference.pop_back();
  radius_difference.pop_back();
  const auto order_runout = observed_order(sizes, runout_difference);
  const auto order_radius = observed_order(sizes, radius_difference);
  md << "\nObserved order (least-squares slope of log |q_h - q_finest| against log h, over the coarser runs): runout "
     << (order_runout ? fixed(*order_runout, 2) : std::string("n/a")) << ", slip-circle radius "
     << (order_radius ? fixed(*order_radius, 2) : std::string("n/a"))
     << ". Measured against the finest run rather than an exact value, so it overstates the order of the runs "
        "closest to it.\n\n";
  return md.str();
}

int usage(const char* self, int status) {
  std::fprintf(status ? stderr : stdout,
               "usage: %s [--quick] [--smallest] [--scenes LIST] [--out DIR] [--threads N] [--no-plots]\n"
               "  --quick      a reduced grid (a few minutes on 2 cores)\n"
               "  --smallest   only the cheapest setting of spring_mass and box_incline (seconds; for the test suite)\n"
               "  --scenes     comma-separated subset of spring_mass,box_incline,slope\n"
               "  --out DIR    output folder (default out/bench)\n"
               "  --threads N  OpenMP threads per run (default 1: steadier timings on a shared machine)\n"
               "  --no-plots   write the CSV and Markdown only\n",
               self);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::string command = "talus bench accuracy";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--quick") options.quick = true;
    else if (arg == "--smallest") options.smallest = true;
    else if (arg == "--no-plots") options.plots = false;
    else if (arg == "--out" && has_value) options.out = argv[++i];
    else if (arg == "--threads" && has_value) options.threads = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--scenes" && has_value) {
      options.scenes.clear();
      std::stringstream list(argv[++i]);
      for (std::string name; std::getline(list, name, ',');) {
        if (name != "spring_mass" && name != "box_incline" && name != "slope") {
          std::fprintf(stderr, "talus_bench_accuracy: unknown scene '%s'\n", name.c_str());
          return 1;
        }
        options.scenes.push_back(name);
      }
    } else return usage(argv[0], arg == "--help" || arg == "-h" ? 0 : 1);
  }
  if (options.smallest)  // the slope needs several runs to say anything
    options.scenes.erase(std::remove(options.scenes.begin(), options.scenes.end(), "slope"), options.scenes.end());
  std::filesystem::create_directories(options.out);

  std::ostringstream md;
  md << "# Accuracy benchmark\n\n";
  std::size_t total = 0, done = 0;
  for (const auto& scene : options.scenes) total += settings_for(scene, options).size();
  const double start = bench::now_seconds();
  try {
    for (const auto& scene : options.scenes) {
      std::vector<Row> rows;
      for (const Setting& setting : settings_for(scene, options)) {
        std::fprintf(stderr, "[%zu/%zu] %s, %s ...", ++done, total, scene.c_str(), describe(setting).c_str());
        std::fflush(stderr);
        rows.push_back(measure(scene, setting, options));
        const Row& r = rows.back();
        if (!r.failure.empty()) std::fprintf(stderr, " failed: %s\n", r.failure.c_str());
        else if (scene == "slope")
          std::fprintf(stderr, " %.1f s, runout %.2f m\n", r.wall_seconds, r.runout);
        else
          std::fprintf(stderr, " %.1f s, %zu particles, %ld steps, error %.2f%%\n", r.wall_seconds, r.particles,
                       r.steps, 100 * r.error);
      }
      md << (scene == "slope" ? report_slope(rows, options) : report_analytical(scene, rows, options));
    }
  } catch (const std::exception& error) {
    std::fprintf(stderr, "talus_bench_accuracy: %s\n", error.what());
    return 1;
  }
  md << "Made by `" << command << "` (" << options.threads << " thread per run) on " << bench::machine_line()
     << "; the sweep took " << fixed(bench::now_seconds() - start, 0)
     << " s. With a load average above the core count other jobs shared the machine, and wall times are noisy "
        "(tens of percent).\n";
  const std::string md_path = (std::filesystem::path(options.out) / "accuracy.md").string();
  postproc::write_file_atomically(md_path, md.str());
  std::printf("%s", md.str().c_str());
  std::fprintf(stderr, "wrote %s and the CSVs\n", md_path.c_str());
  if (options.plots) {
    if (bench::run_plot_script({"accuracy", options.out}) != 0) {
      std::fprintf(stderr, "talus_bench_accuracy: the plots failed\n");
      return 1;
    }
  }
  return 0;
}
