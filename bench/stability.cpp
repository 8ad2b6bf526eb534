// Stability of the explicit solver: how far the CFL number can go on each scene, stress cases
// (stiffness contrast, very soft material, high-velocity impact, grid crossing, a 1e5-step
// energy record), and random perturbations of the box scene. Every run's results.h5 is scanned
// for non-finite values, and a run that stops must stop with a reported error (solve throws,
// `complete` = 0), never silently.
//
//   talus_bench_stability                 everything (about 15 minutes on 2 busy cores)
//   talus_bench_stability --quick         fewer CFL values, 10 perturbed runs, granular at CFL 0.5 and 1
//   talus_bench_stability --only cfl|stress|perturb|granular [--runs N] [--seed S] [--out DIR]
//
// Writes to DIR (default out/bench): stability_cfl.csv, stability_stress.csv,
// stability_perturbation.csv, stability_energy.csv, stability_granular.csv, stability.md and
// bench_stability_energy.png (bench/plot_benchmarks.py). The helpers and the stress cases are in
// stability_support.cpp, stability_stress.cpp and stability_granular.cpp (stability.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_support.hpp"
#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/scene/scene.hpp"
#include "postproc/output.hpp"
#include "postproc/validation.hpp"
#include "preproc/preproc.hpp"
#include "stability.hpp"

namespace {

using namespace talus;
using namespace talus::bench::stability;
using bench::fixed;
using bench::general;

// ---------------------------------------------------------------------------------------------
// CFL sweep: raise run.cfl (set on the Model, past the scene parser's cap of 1) until the run
// blows up, then bisect twice between the last stable and the first unstable value.

struct CflScene {
  std::string name;
  std::vector<std::string> overrides;  // kept short so that each run takes seconds
  std::string note;
};

struct CflRow {
  std::string scene;
  double cfl = 0;
  Outcome outcome;
};

std::string cfl_sweep(const Options& options, std::vector<CflRow>& rows) {
  const std::vector<CflScene> scenes = {
      {"spring_mass", {}, "scene as is (0.13 s, two periods)"},
      {"box_incline", {"mesh.size=0.05", "run.end_time=0.5"}, "mesh.size 0.05 m, 0.5 s"},
      {"slope", {"mesh.size=0.5", "run.end_time=1.5"}, "mesh.size 0.5 m, first 1.5 s of the failure"},
  };
  const std::vector<double> ladder =
      options.quick ? std::vector<double>{0.5, 1.0, 1.5, 2.0, 3.0} : std::vector<double>{0.5, 0.8, 1.0, 1.2, 1.5, 2.0, 3.0, 4.0};
  std::ostringstream md;
  md << "## CFL limit\n\n"
     << "run.cfl raised on the built Model (past the scene's cap of 1) until the run blows up, then bisected "
     << (options.quick ? "once" : "twice")
     << " between the last stable and the first unstable value. `consistent`: a stopped run threw a message "
        "and left `complete` = 0, a finished one `complete` = 1, and no frame or history record of either holds "
        "a non-finite value.\n\n"
     << "| scene | runs | largest stable CFL | first unstable CFL | how it stopped | detection consistent |\n"
     << "|---|---|---:|---:|---|---|\n";
  for (const CflScene& scene : scenes) {
    const Model base = build_scene(scene.name, scene.overrides);
    std::optional<double> stable, unstable;
    std::optional<CflRow> first_failure;
    auto attempt = [&](double cfl) {
      Model model = base;
      model.run.cfl = cfl;
      bench::Scratch scratch("stability-cfl");
      std::fprintf(stderr, "cfl: %s at CFL %.3g ...", scene.name.c_str(), cfl);
      std::fflush(stderr);
      CflRow row{scene.name, cfl, run_and_scan(model, scratch.path().string(), options.threads)};
      std::fprintf(stderr, " %s after %ld steps (%.1f s)%s\n", row.outcome.kind.c_str(), row.outcome.steps,
                   row.outcome.wall_seconds, row.outcome.consistent() ? "" : "  INCONSISTENT");
      rows.push_back(row);
      const bool ok = row.outcome.kind == "completed";
      if (ok) stable = std::max(stable.value_or(0.0), cfl);
      else {
        unstable = std::min(unstable.value_or(1e9), cfl);
        if (!first_failure || cfl < first_failure->cfl) first_failure = row;
      }
      return ok;
    };
    for (double cfl : ladder)
      if (!attempt(cfl)) break;
    for (int round = 0; round < (options.quick ? 1 : 2) && stable && unstable; ++round)
      attempt(0.5 * (*stable + *unstable));
    bool consistent = true;
    int count = 0;
    for (const CflRow& row : rows)
      if (row.scene == scene.name) consistent = consistent && row.outcome.consistent(), ++count;
    md << "| " << scene.name << " (" << scene.note << ") | " << count << " | "
       << (stable ? general(*stable) : std::string("none")) << " | "
       << (unstable ? general(*unstable) : std::string("none up to " + general(ladder.back()))) << " | "
       << (first_failure ? first_failure->outcome.kind + ": " + short_message(first_failure->outcome.message)
                         : std::string("-"))
       << " | " << (consistent ? "yes" : "**no**") << " |\n";
  }
  std::vector<std::vector<std::string>> table;
  for (const CflRow& r : rows)
    table.push_back({r.scene, general(r.cfl, 4), r.outcome.kind, std::to_string(r.outcome.steps),
                     fixed(r.outcome.wall_seconds, 2), std::to_string(r.outcome.scan.complete),
                     std::to_string(r.outcome.scan.frames), std::to_string(r.outcome.scan.nonfinite),
                     r.outcome.consistent() ? "1" : "0", r.outcome.message});
  write_table((std::filesystem::path(options.out) / "stability_cfl.csv").string(),
              {"scene", "cfl", "outcome", "steps", "wall_seconds", "complete", "frames", "nonfinite_values",
               "consistent", "message"},
              table);
  return md.str() + "\n";
}

// ---------------------------------------------------------------------------------------------
// Random perturbations of the box scene.

struct PerturbRow {
  int run = 0;
  double friction = 0, youngs_modulus = 0, density = 0, poisson_ratio = 0;
  std::size_t moved = 0, particles = 0;
  Outcome outcome;
  long outside = -1;        // final particles outside the mesh (-1: not checked)
  double displacement = 0;  // box, along the slope at the end (m)
  double exact = 0;         // 0.5 g (sin 30 - mu cos 30)+ t^2 at the end (m)
  bool ok() const {
    const bool reported = outcome.kind != "completed" && !outcome.message.empty();
    return outcome.consistent() && (outcome.kind == "completed" ? outside == 0 : reported);
  }
};

std::string perturbations(const Options& options, std::vector<PerturbRow>& rows) {
  const int runs = options.quick ? std::min(options.runs, 10) : options.runs;
  const double end_time = 0.5, fraction = 0.5;
  const std::vector<std::string> base_overrides = {"mesh.size=0.05", "bodies.surface.particles_per_cell=4",
                                                   "bodies.box.particles_per_cell=4",
                                                   "run.end_time=" + std::to_string(end_time)};
  std::mt19937 random(options.seed);
  std::uniform_real_distribution<double> unit(0, 1);
  const Model base = build_scene("box_incline", base_overrides);
  const Eigen::Vector2d downhill(std::cos(M_PI / 6), -std::sin(M_PI / 6));
  for (int k = 0; k < runs; ++k) {
    PerturbRow row;
    row.run = k + 1;
    row.friction = 0.8 * unit(random);
    row.youngs_modulus = std::pow(10.0, 5 + 2 * unit(random));  // 1e5 - 1e7 Pa, log-uniform
    row.density = 100 + 2900 * unit(random);                    // kg/m^3
    row.poisson_ratio = 0.45 * unit(random);
    Model model = base;
    for (Material& m : model.materials)
      m.youngs_modulus = row.youngs_modulus, m.density = row.density, m.poisson_ratio = row.poisson_ratio;
    for (std::size_t p = 0; p < model.particle_count(); ++p) model.mass[p] = row.density * model.volume[p];
    model.contact.friction = row.friction;
    model.contact.pairs.clear();
    row.moved = perturb_positions(model, random, fraction);
    row.particles = model.particle_count();
    std::fprintf(stderr, "perturb %d/%d: mu %.2f, E %.3g Pa, rho %.0f, nu %.2f ...", k + 1, runs, row.friction,
                 row.youngs_modulus, row.density, row.poisson_ratio);
    std::fflush(stderr);
    bench::Scratch scratch("stability-perturb");
    row.outcome = run_and_scan(model, scratch.path().string(), options.threads);
    if (row.outcome.kind == "completed") {
      const h5::File file = h5::File::open_read(scratch.file("results.h5"));
      h5::Dims dims;
      const auto position = h5::read_doubles(file, "frames/position", &dims);
      const std::size_t last = dims[0] - 1, n = dims[1];
      row.outside = n == model.particle_count() ? 0 : static_cast<long>(model.particle_count());
      for (std::size_t p = 0; p < n; ++p)
        if (!inside_mesh(model, {position[(last * n + p) * 2], position[(last * n + p) * 2 + 1]})) ++row.outside;
      const bench::BodyTrack track = bench::track_body(scratch.file("results.h5"), "box");
      row.displacement = (track.centre.back() - track.initial).dot(downhill);
      const double a = std::max(10 * (0.5 - row.friction * std::cos(M_PI / 6)), 0.0);
      row.exact = 0.5 * a * track.time.back() * track.time.back();
    }
    std::fprintf(stderr, " %s, %ld steps (%.1f s), box moved %.3f m (exact %.3f)%s\n", row.outcome.kind.c_str(),
                 row.outcome.steps, row.outcome.wall_seconds, row.displacement, row.exact,
                 row.ok() ? "" : "  NOT OK");
    rows.push_back(row);
  }
  std::vector<std::vector<std::string>> table;
  int completed = 0, reported = 0, bad = 0, nonfinite = 0, outside = 0;
  double worst_error = 0;  // |moved - exact| over 0.5 g t^2 (the scale of a free slide)
  long fewest_steps = -1, most_steps = 0;
  for (const PerturbRow& r : rows) {
    table.push_back({std::to_string(r.run), general(r.friction, 4), general(r.youngs_modulus, 4), general(r.density, 4),
                     general(r.poisson_ratio, 4), std::to_string(r.particles), std::to_string(r.moved), r.outcome.kind,
                     std::to_string(r.outcome.steps), fixed(r.outcome.wall_seconds, 2),
                     std::to_string(r.outcome.scan.nonfinite), std::to_string(r.outside), general(r.displacement, 5),
                     general(r.exact, 5), r.ok() ? "1" : "0", r.outcome.message});
    completed += r.outcome.kind == "completed";
    reported += r.outcome.kind != "completed" && !r.outcome.message.empty();
    bad += !r.ok();
    nonfinite += r.outcome.scan.nonfinite > 0;
    outside += r.outside > 0;
    if (r.outcome.kind == "completed") {
      worst_error = std::max(worst_error, std::abs(r.displacement - r.exact) / (0.5 * 10 * end_time * end_time));
      fewest_steps = fewest_steps < 0 ? r.outcome.steps : std::min(fewest_steps, r.outcome.steps);
      most_steps = std::max(most_steps, r.outcome.steps);
    }
  }
  write_table((std::filesystem::path(options.out) / "stability_perturbation.csv").string(),
              {"run", "friction", "youngs_modulus_Pa", "density_kg_m3", "poisson_ratio", "particles",
               "particles_moved", "outcome", "steps", "wall_seconds", "nonfinite_values", "particles_outside_mesh",
               "box_displacement_m", "exact_displacement_m", "ok", "message"},
              table);
  std::ostringstream md;
  md << "## Random perturbations (box scene)\n\n"
     << runs << " runs of the box scene (mesh.size 0.05 m, 4 particles per cell, " << end_time
     << " s, seed " << options.seed << "). Each particle moved towards a random point of its own element by a "
        "random fraction up to " << fraction << " of the way (so it stays in its element and body); friction "
        "uniform in [0, 0.8], E log-uniform in [1e5, 1e7] Pa, density uniform in [100, 3000] kg/m^3, Poisson "
        "ratio uniform in [0, 0.45] (both bodies).\n\n"
     << "| runs | completed | stopped with a reported error | any non-finite value | completed with a particle "
        "outside the mesh | not OK | steps (completed) | worst |x - x_exact| / (g t^2 / 2) |\n"
     << "|---:|---:|---:|---:|---:|---:|---|---:|\n"
     << "| " << runs << " | " << completed << " | " << reported << " | " << nonfinite << " | " << outside << " | " << bad
     << " | " << fewest_steps << " - " << most_steps << " | " << fixed(100 * worst_error, 2) << "% |\n\n";
  for (const PerturbRow& r : rows)
    if (r.outcome.kind != "completed" || !r.ok())
      md << "- run " << r.run << " (mu " << general(r.friction) << ", E " << general(r.youngs_modulus) << " Pa, rho "
         << general(r.density) << ", nu " << general(r.poisson_ratio) << "): " << r.outcome.kind << ": "
         << short_message(r.outcome.message) << (r.ok() ? "" : " **not OK**") << "\n";
  return md.str() + "\n";
}

int usage(const char* self, int status) {
  std::fprintf(status ? stderr : stdout,
               "usage: %s [--quick] [--only cfl|stress|perturb|granular] [--runs N] [--seed S] [--out DIR] [--threads N]\n"
               "  --quick      fewer CFL values, 2e4 steps in the long run, at most 10 perturbed runs\n"
               "  --runs N     perturbed runs of the box scene (default 50)\n"
               "  --out DIR    output folder (default out/bench)\n"
               "  --threads N  OpenMP threads per run (default 1)\n",
               self);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  std::string command = "talus bench stability";
  for (int i = 1; i < argc; ++i) command += std::string(" ") + argv[i];
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--quick") options.quick = true;
    else if (arg == "--only" && has_value) options.only = argv[++i];
    else if (arg == "--runs" && has_value) options.runs = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--seed" && has_value) options.seed = static_cast<unsigned>(std::atol(argv[++i]));
    else if (arg == "--out" && has_value) options.out = argv[++i];
    else if (arg == "--threads" && has_value) options.threads = std::max(1, std::atoi(argv[++i]));
    else return usage(argv[0], arg == "--help" || arg == "-h" ? 0 : 1);
  }
  if (!options.only.empty() && options.only != "cfl" && options.only != "stress" && options.only != "perturb" &&
      options.only != "granular")
    return usage(argv[0], 1);
  std::filesystem::create_directories(options.out);
  const double start = bench::now_seconds();
  std::ostringstream md;
  md << "# Stability benchmark\n\n";
  try {
    std::vector<CflRow> cfl_rows;
    std::vector<StressRow> stress_rows;
    std::vector<PerturbRow> perturb_rows;
    std::vector<GranularRow> granular_rows;
    if (options.only.empty() || options.only == "cfl") md << cfl_sweep(options, cfl_rows);
    if (options.only.empty() || options.only == "stress") md << stress_cases(options, stress_rows);
    if (options.only.empty() || options.only == "perturb") md << perturbations(options, perturb_rows);
    if (options.only.empty() || options.only == "granular") md << granular_cases(options, granular_rows);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "talus_bench_stability: %s\n", error.what());
    return 1;
  }
  md << "Made by `" << command << "` (" << options.threads << (options.threads == 1 ? " thread" : " threads") << " per run) on " << bench::machine_line() << "; took "
     << fixed(bench::now_seconds() - start, 0) << " s.\n";
  const std::string md_path = (std::filesystem::path(options.out) / "stability.md").string();
  postproc::write_file_atomically(md_path, md.str());
  std::printf("%s", md.str().c_str());
  std::fprintf(stderr, "wrote %s and the CSVs\n", md_path.c_str());
  if (bench::run_plot_script({"stability", options.out}) != 0) {
    std::fprintf(stderr, "talus_bench_stability: the plot failed\n");
    return 1;
  }
  return 0;
}
