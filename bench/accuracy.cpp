// Accuracy against cost: sweeps element size (mesh.size), particles per cell and CFL number over
// the validation scenes and measures the error against their analytical solutions, the steps,
// particles and time of each run; for the slope (no analytical solution) it reports the runout
// and slip circle against element size and their observed convergence.
//
//   talus_bench_accuracy                    the full sweep (long: tens of minutes on 2 cores)
//   talus_bench_accuracy --quick            a reduced grid, a few minutes
//   talus_bench_accuracy --smallest         one (the cheapest) setting per analytical scene, seconds
//   talus_bench_accuracy --quick --scenes spring_mass,slope --out DIR --threads 2
//   talus_bench_accuracy --quick --set run.integration=mixed   every run with the scene override
//   talus_bench_accuracy --quick --family bspline   quadratic B-splines (box_incline as its level
//                                           variant, box_incline_level.toml)
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
// The settings and the measuring of one run are in accuracy_support.cpp (accuracy.hpp).
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

#include "accuracy.hpp"
#include "bench_support.hpp"
#include "common/error.hpp"
#include "common/scene/scene.hpp"
#include "postproc/output.hpp"
#include "postproc/postproc.hpp"
#include "postproc/validation.hpp"

namespace {

using namespace talus;
using namespace talus::bench::accuracy;
using bench::fixed;
using bench::general;

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
       "loop_seconds", "wall_seconds", "error", "error_at_1s", "pareto", "threads"},
      with_setting_columns(done, {column(done, [](const Row& r) { return r.particle_updates(); }),
                                  column(done, [](const Row& r) { return r.loop_seconds; }), wall, error,
                                  column(done, [](const Row& r) { return r.error_at_1s; }), flags,
                                  std::vector<double>(done.size(), options.threads)}));

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
                       "slip_radius_difference_to_finest_m", "threads"},
                      with_setting_columns(done, {column(done, [](const Row& r) { return r.loop_seconds; }),
                       column(done, [](const Row& r) { return r.wall_seconds; }),
                       column(done, [](const Row& r) { return r.runout; }),
                       column(done, [](const Row& r) { return r.has_circle ? r.circle_x : NAN; }),
                       column(done, [](const Row& r) { return r.has_circle ? r.circle_y : NAN; }),
                       column(done, [](const Row& r) { return r.has_circle ? r.circle_r : NAN; }), runout_difference,
                       centre_difference, radius_difference, std::vector<double>(done.size(), options.threads)}));
  md << "The scene's settings otherwise (4 particles per cell, CFL 0.5, run to rest). Differences are to the "
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
               "usage: %s [--quick] [--smallest] [--scenes LIST] [--family F] [--set KEY=VALUE]... [--out DIR] [--threads N]\n"
               "          [--no-plots]\n"
               "  --quick      a reduced grid (a few minutes on 2 cores)\n"
               "  --smallest   only the cheapest setting of spring_mass and box_incline (seconds; for the test suite)\n"
               "  --scenes     comma-separated subset of spring_mass,box_incline,slope\n"
               "  --set        a scene override for every run, e.g. run.integration=mixed\n"
               "  --family F   linear (the scenes' own) or bspline (quadratic B-splines on a lattice,\n"
               "               integration at the particles; box_incline as box_incline_level.toml, level\n"
               "               under tilted gravity, since its rotated domain cannot take the lattice)\n"
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
    else if (arg == "--set" && has_value) options.overrides.push_back(argv[++i]);
    else if (arg == "--threads" && has_value) options.threads = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--family" && has_value) {
      const std::string family = argv[++i];
      if (family != "linear" && family != "bspline") {
        std::fprintf(stderr, "talus_bench_accuracy: --family: expected linear or bspline, got '%s'\n", family.c_str());
        return 1;
      }
      options.bspline = family == "bspline";
    } else if (arg == "--scenes" && has_value) {
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
  std::string family_note;
  if (options.bspline &&
      std::find(options.scenes.begin(), options.scenes.end(), "box_incline") != options.scenes.end())
    family_note = "box_incline runs as geometries/box_incline_level.toml with B-splines: the same slide on a level slab "
              "under gravity tilted by 30 degrees, since the lattice needs an axis-aligned rectangle and "
              "box_incline.geo's domain is rotated with the incline.\n\n";
  if (options.smallest)  // the slope needs several runs to say anything
    options.scenes.erase(std::remove(options.scenes.begin(), options.scenes.end(), "slope"), options.scenes.end());
  std::filesystem::create_directories(options.out);

  std::ostringstream md;
  md << "# Accuracy benchmark" << (options.bspline ? " (quadratic B-splines)" : "") << "\n\n" << family_note;
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
  md << "Made by `" << command << "` (" << options.threads << (options.threads == 1 ? " thread" : " threads") << " per run) on " << bench::machine_line()
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
