// The stability benchmark (bench/stability.cpp): its options, the scan of a run's results.h5,
// and the helpers and the stress cases (bench/stability_stress.cpp) its studies share.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "common/model/model.hpp"

namespace talus::bench::stability {

struct Options {
  bool quick = false;
  std::string only;  // "", "cfl", "stress", "perturb" or "granular"
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

FileScan scan_results(const std::string& path);

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

// Solves `model` into `folder` and scans the results.h5 it leaves.
Outcome run_and_scan(const Model& model, const std::string& folder, int threads);

// geometries/SCENE.toml with `overrides`, built into a model.
Model build_scene(const std::string& scene, const std::vector<std::string>& overrides);
// Index of the named body; throws talus::Error when there is none.
int body_index(const Model& model, const std::string& name);

// A CSV table of text cells (quoted where needed), written atomically.
void write_table(const std::string& path, const std::vector<std::string>& header,
                 const std::vector<std::vector<std::string>>& rows);
// The message cut to 160 characters.
std::string short_message(const std::string& message);

// The box scene's check against 0.5 g (sin 30 - mu cos 30) t^2: the relative error at the last
// check time inside the record.
double box_error(const std::string& results, double friction);
// The spring-mass scene's largest error over the amplitude.
double spring_error(const std::string& results);

// Gives a body its own copy of its material, changed by `change`.
template <typename Change>
void own_material(Model& model, int body, Change change) {
  Material material = model.materials[model.bodies[body].material];
  material.name += "_" + model.bodies[body].name;
  change(material);
  model.materials.push_back(material);
  model.bodies[body].material = static_cast<int>(model.materials.size()) - 1;
}

void set_body_velocity(Model& model, int body, const Eigen::Vector2d& v);

struct EnergyRecord {
  std::vector<double> time, total_grid, total_particle, strain;
};

EnergyRecord read_energy(const std::string& results);

// Moves each particle towards a random point of its own element by a random fraction (up to
// `fraction`) of the way: a convex combination, so it stays in its element; a move that would
// leave its body's outline (common/geometry.hpp's inside_loops) is not made. Returns the number
// of particles moved.
std::size_t perturb_positions(Model& model, std::mt19937& random, double fraction);
// Whether x lies in a triangle of the mesh (with a small tolerance).
bool inside_mesh(const Model& model, const Eigen::Vector2d& x);

// The stress cases (bench/stability_stress.cpp): one row each, and their Markdown section.
struct StressRow {
  std::string name, measures, figure;
  Outcome outcome;
};
std::string stress_cases(const Options& options, std::vector<StressRow>& rows);

// The granular-flow cases (bench/stability_granular.cpp): cohesionless column and slope at
// several CFL numbers, one row per run, and their Markdown section.
struct GranularRow {
  std::string scene, note;
  double cfl = 0;
  Outcome outcome;
  double front_advance = 0;  // m: the farthest particle's x, last frame minus first
  bool left_domain = false;
};
std::string granular_cases(const Options& options, std::vector<GranularRow>& rows);

}  // namespace talus::bench::stability
