// Stability of the explicit solver: how far the CFL number can go on each scene, stress cases
// (stiffness contrast, very soft material, high-velocity impact, grid crossing, a 1e5-step
// energy record), and random perturbations of the box scene. Every run's results.h5 is scanned
// for non-finite values, and a run that stops must stop with a reported error (solve throws,
// `complete` = 0), never silently.
//
//   talus_bench_stability                 everything (about 15 minutes on 2 busy cores)
//   talus_bench_stability --quick         fewer CFL values and 10 perturbed runs
//   talus_bench_stability --only cfl|stress|perturb [--runs N] [--seed S] [--out DIR]
//
// Writes to DIR (default out/bench): stability_cfl.csv, stability_stress.csv,
// stability_perturbation.csv, stability_energy.csv, stability.md and
// bench_stability_energy.png (bench/plot_benchmarks.py).
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
#include "common/scene.hpp"
#include "postproc/output.hpp"
#include "postproc/validation.hpp"
#include "preproc/preproc.hpp"

namespace {

using namespace talus;
using bench::fixed;
using bench::general;

struct Options {
  bool quick = false;
  std::string only;  // "", "cfl", "stress" or "perturb"
  int runs = 50;
  unsigned seed = 20240611;
  int threads = 1;
  std::string out = "out/bench";
};

// What results.h5 holds after a run.
struct FileScan {
  bool exists = false;
  int64_t complete = -1;
  long frames = 0;
  long nonfinite = 0;  // non-finite numbers in /frames/* and /history/*
};

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

// One solve of a model and what became of it.
struct Outcome {
  std::string kind;     // "completed", "blow-up", "left the domain", "error"
  std::string message;  // the solver's error message
  long steps = 0;
  double wall_seconds = 0;
  FileScan scan;
  // Completed runs leave complete = 1, stopped ones complete = 0 and a message; no run writes a
  // non-finite value.
  bool consistent() const {
    const bool flag_ok = kind == "completed" ? scan.complete == 1 : (scan.complete == 0 && !message.empty());
    return scan.exists && flag_ok && scan.nonfinite == 0;
  }
};

Outcome run(const Model& model, const std::string& folder, int threads) {
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

Model build(const std::string& scene, const std::vector<std::string>& overrides) {
  return preproc::build_model(load_scene(bench::scene_path(scene), overrides));
}

int body_index(const Model& model, const std::string& name) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].name == name) return static_cast<int>(b);
  throw Error("no body named '" + name + "'");
}

// A CSV cell: quoted when it holds a comma or a quote.
std::string cell(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
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
    const Model base = build(scene.name, scene.overrides);
    std::optional<double> stable, unstable;
    std::optional<CflRow> first_failure;
    auto attempt = [&](double cfl) {
      Model model = base;
      model.run.cfl = cfl;
      bench::Scratch scratch("stability-cfl");
      std::fprintf(stderr, "cfl: %s at CFL %.3g ...", scene.name.c_str(), cfl);
      std::fflush(stderr);
      CflRow row{scene.name, cfl, run(model, scratch.path().string(), options.threads)};
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
// Stress cases.

struct StressRow {
  std::string name, measures, figure;
  Outcome outcome;
};

// The box scene's check against 0.5 g (sin 30 - mu cos 30) t^2: the relative error at the last
// check time inside the record.
double box_error(const std::string& results, double friction) {
  const bench::BodyTrack track = bench::track_body(results, "box");
  std::vector<Eigen::Vector2d> displacement;
  for (const auto& c : track.centre) displacement.push_back(c - track.initial);
  const auto check = postproc::box_incline_check(track.time, displacement, 30, 10, friction);
  if (check.relative_error.empty() || !check.relative_error.back()) return NAN;
  return *check.relative_error.back();
}

double spring_error(const std::string& results) {
  const bench::BodyTrack track = bench::track_body(results, "mass");
  std::vector<double> height;
  for (const auto& c : track.centre) height.push_back(c.y());
  return postproc::spring_mass_check(track.time, height, track.initial.y(), 1e-3, 100).max_error_over_amplitude;
}

// Gives a body its own copy of its material, changed by `change`.
template <typename Change>
void own_material(Model& model, int body, Change change) {
  Material material = model.materials[model.bodies[body].material];
  material.name += "_" + model.bodies[body].name;
  change(material);
  model.materials.push_back(material);
  model.bodies[body].material = static_cast<int>(model.materials.size()) - 1;
}

void set_body_velocity(Model& model, int body, const Eigen::Vector2d& v) {
  for (std::size_t p = 0; p < model.particle_count(); ++p)
    if (model.body[p] == body) model.velocity[p] = v;
}

struct EnergyRecord {
  std::vector<double> time, total_grid, total_particle, strain;
};

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

std::string stress_cases(const Options& options, std::vector<StressRow>& rows) {
  const Eigen::Vector2d downhill(std::cos(M_PI / 6), -std::sin(M_PI / 6));
  auto record = [&](StressRow row) {
    std::fprintf(stderr, " %s (%.1f s): %s\n", row.outcome.kind.c_str(), row.outcome.wall_seconds, row.figure.c_str());
    rows.push_back(row);
  };
  auto start = [](const char* name) {
    std::fprintf(stderr, "stress: %s ...", name);
    std::fflush(stderr);
  };

  {  // 1. Stiffness contrast 1e4 between bonded bodies: the spring-mass block 1e4 x stiffer than the spring.
    start("stiffness contrast");
    Model model = build("spring_mass", {"materials.block.youngs_modulus=5e9"});
    bench::Scratch scratch("stability-stress");
    StressRow row{"stiffness contrast 1e4",
                  "spring-mass scene with the block's E raised to 5e9 Pa (1e4 x the spring's 5e5 Pa), bonded: the "
                  "error against y(t) = 1e-3 (1 - cos 100t) over two periods",
                  "", run(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed")
      row.figure = "max |y - y_exact| / A = " + fixed(100 * spring_error(scratch.file("results.h5")), 2) + "% in " +
                   std::to_string(row.outcome.steps) + " steps";
    record(row);
  }
  {  // 2. Very soft material under gravity: the box at E = 1e4 Pa sliding on the incline.
    start("soft material");
    Model model = build("box_incline", {});
    const int box = body_index(model, "box");
    own_material(model, box, [](Material& m) { m.youngs_modulus = 1e4; });
    bench::Scratch scratch("stability-stress");
    StressRow row{"very soft material",
                  "box scene with the box at E = 1e4 Pa (static strain rho g H / E = 0.2): sliding error at 1 s "
                  "against 0.5 g (sin 30 - 0.3 cos 30) t^2, and the box's lowest-to-highest height change",
                  "", run(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed")
      row.figure = "relative error at 1 s " + fixed(100 * box_error(scratch.file("results.h5"), 0.3), 2) + "% in " +
                   std::to_string(row.outcome.steps) + " steps";
    record(row);
  }
  {  // 3. High-velocity impact: the box thrown at 20 m/s down the slope into the wall.
    start("impact");
    Model model = build("box_incline", {"run.end_time=0.3", "run.output_interval=0.01"});
    const double speed = 20;
    set_body_velocity(model, body_index(model, "box"), speed * downhill);
    bench::Scratch scratch("stability-stress");
    StressRow row{"high-velocity impact",
                  "box scene, box launched at 20 m/s down the slope (about 0.25 x its P-wave speed) into the wall "
                  "at the lower end: total energy afterwards against before (contact and impact may only dissipate)",
                  "", run(model, scratch.path().string(), options.threads)};
    if (row.outcome.scan.exists) {
      const EnergyRecord e = read_energy(scratch.file("results.h5"));
      const double initial = e.total_particle.front();
      const double largest_gain = *std::max_element(e.total_particle.begin(), e.total_particle.end()) - initial;
      const auto kinetic = h5::read_doubles(h5::File::open_read(scratch.file("results.h5")),
                                            "history/particle_kinetic_energy");
      row.figure = "initial kinetic energy " + general(kinetic.front()) + " J/m; largest rise of the total energy " +
                   general(largest_gain) + " J/m (" + fixed(100 * largest_gain / kinetic.front(), 2) +
                   "% of it); total energy at the end " +
                   fixed(100 * (e.total_particle.back() - initial) / kinetic.front(), 1) + "% of it";
    }
    record(row);
  }
  {  // 4. Grid crossing: the box sliding frictionless across 36 elements under its own weight.
    start("grid crossing");
    const double duration = 0.6, acceleration = 10 * 0.5;  // g sin 30
    Model model = build("box_incline", {"contact.friction=0.0", "run.end_time=" + std::to_string(duration),
                                        "run.output_interval=0.02"});
    bench::Scratch scratch("stability-stress");
    StressRow row{"grid crossing",
                  "box scene without friction: the box slides 0.5 (g sin 30) t^2 = 0.9 m in 0.6 s, across 36 element "
                  "widths of 0.025 m, carrying its self-weight stress from element to element (linear elements: "
                  "a particle's stress jumps as it crosses). Figures: the slide against the exact one, and the "
                  "ripple of the strain energy over the last half (its std over its mean)",
                  "", run(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed") {
      const bench::BodyTrack track = bench::track_body(scratch.file("results.h5"), "box");
      const double travelled = (track.centre.back() - track.initial).dot(downhill);
      const double expected = 0.5 * acceleration * track.time.back() * track.time.back();
      const EnergyRecord e = read_energy(scratch.file("results.h5"));
      double sum = 0, sum2 = 0;
      int count = 0;
      for (std::size_t k = 0; k < e.time.size(); ++k)
        if (e.time[k] >= 0.5 * duration) sum += e.strain[k], sum2 += e.strain[k] * e.strain[k], ++count;
      const double mean = sum / count, deviation = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
      row.figure = "slid " + fixed(travelled, 4) + " m against " + fixed(expected, 4) + " m (" +
                   fixed(100 * (travelled - expected) / expected, 2) + "%); strain-energy ripple " +
                   fixed(100 * deviation / mean, 1) + "% of its mean";
    }
    record(row);
  }
  {  // 5. A long run: 1e5 steps of the spring-mass scene, total energy drift.
    start("1e5 steps");
    const long steps = options.quick ? 20000 : 100000;
    Model model = build("spring_mass", {"run.end_time=100.0", "run.output_interval=0.05"});
    model.run.max_steps = steps;
    bench::Scratch scratch("stability-stress");
    StressRow row{"long run",
                  "spring-mass scene for " + std::to_string(steps) +
                      " steps: drift of the total energy (kinetic + potential + strain) from its start, over the "
                      "largest strain energy (the energy the oscillation exchanges)",
                  "", run(model, scratch.path().string(), options.threads)};
    if (row.outcome.kind == "completed") {
      const EnergyRecord e = read_energy(scratch.file("results.h5"));
      const double swing = *std::max_element(e.strain.begin(), e.strain.end());
      std::vector<double> drift_grid, drift_particle;
      double worst_grid = 0, worst_particle = 0;
      for (std::size_t k = 0; k < e.time.size(); ++k) {
        drift_grid.push_back((e.total_grid[k] - e.total_grid.front()) / swing);
        drift_particle.push_back((e.total_particle[k] - e.total_particle.front()) / swing);
        worst_grid = std::max(worst_grid, std::abs(drift_grid.back()));
        worst_particle = std::max(worst_particle, std::abs(drift_particle.back()));
      }
      postproc::write_csv((std::filesystem::path(options.out) / "stability_energy.csv").string(),
                          {"time_s", "total_particle_J", "total_grid_J", "drift_particle", "drift_grid"},
                          {e.time, e.total_particle, e.total_grid, drift_particle, drift_grid});
      row.figure = std::to_string(row.outcome.steps) + " steps to t = " + fixed(e.time.back(), 3) +
                   " s; with the particle kinetic energy the total ends " + fixed(100 * drift_particle.back(), 2) +
                   "% (largest " + fixed(100 * worst_particle, 2) + "%) of the swing from its start; with the grid " +
                   "kinetic energy " + fixed(100 * drift_grid.back(), 2) + "% (largest " + fixed(100 * worst_grid, 2) + "%)";
    }
    record(row);
  }

  std::vector<std::vector<std::string>> table;
  std::ostringstream md;
  md << "## Stress cases\n\n| case | what it measures | outcome | figure |\n|---|---|---|---|\n";
  for (const StressRow& r : rows) {
    table.push_back({r.name, r.outcome.kind, std::to_string(r.outcome.steps), fixed(r.outcome.wall_seconds, 2),
                     std::to_string(r.outcome.scan.nonfinite), r.outcome.consistent() ? "1" : "0", r.figure,
                     r.outcome.message, r.measures});
    md << "| " << r.name << " | " << r.measures << " | " << r.outcome.kind
       << (r.outcome.message.empty() ? "" : ": " + short_message(r.outcome.message))
       << (r.outcome.consistent() ? "" : " (**inconsistent results file**)") << " | " << r.figure << " |\n";
  }
  write_table((std::filesystem::path(options.out) / "stability_stress.csv").string(),
              {"case", "outcome", "steps", "wall_seconds", "nonfinite_values", "consistent", "figure", "message",
               "measures"},
              table);
  return md.str() + "\n";
}

// ---------------------------------------------------------------------------------------------
// Random perturbations of the box scene.

// Even-odd rule over the body's loops.
bool inside_loops(const std::vector<std::vector<Eigen::Vector2d>>& loops, const Eigen::Vector2d& x) {
  bool inside = false;
  for (const auto& loop : loops)
    for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
      const Eigen::Vector2d& a = loop[i];
      const Eigen::Vector2d& b = loop[j];
      if ((a.y() > x.y()) != (b.y() > x.y()) && x.x() < a.x() + (x.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
        inside = !inside;
    }
  return inside;
}

// Moves each particle towards a random point of its own element by a random fraction (up to
// `fraction`) of the way: a convex combination, so it stays in its element; a move that would
// leave its body's outline is not made. Returns the number of particles moved.
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

// Whether x lies in a triangle of the mesh (with a small tolerance).
bool inside_mesh(const Model& model, const Eigen::Vector2d& x) {
  for (const auto& t : model.triangles) {
    const Eigen::Vector2d a = model.nodes[t[0]], b = model.nodes[t[1]], c = model.nodes[t[2]];
    auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
    const double area = cross(b - a, c - a), tol = -1e-9 * std::abs(area);
    if (cross(b - a, x - a) >= tol && cross(c - b, x - b) >= tol && cross(a - c, x - c) >= tol) return true;
  }
  return false;
}

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
  const Model base = build("box_incline", base_overrides);
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
    row.outcome = run(model, scratch.path().string(), options.threads);
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
               "usage: %s [--quick] [--only cfl|stress|perturb] [--runs N] [--seed S] [--out DIR] [--threads N]\n"
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
  if (!options.only.empty() && options.only != "cfl" && options.only != "stress" && options.only != "perturb")
    return usage(argv[0], 1);
  std::filesystem::create_directories(options.out);
  const double start = bench::now_seconds();
  std::ostringstream md;
  md << "# Stability benchmark\n\n";
  try {
    std::vector<CflRow> cfl_rows;
    std::vector<StressRow> stress_rows;
    std::vector<PerturbRow> perturb_rows;
    if (options.only.empty() || options.only == "cfl") md << cfl_sweep(options, cfl_rows);
    if (options.only.empty() || options.only == "stress") md << stress_cases(options, stress_rows);
    if (options.only.empty() || options.only == "perturb") md << perturbations(options, perturb_rows);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "talus_bench_stability: %s\n", error.what());
    return 1;
  }
  md << "Made by `" << command << "` (" << options.threads << " thread per run) on " << bench::machine_line() << "; took "
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
