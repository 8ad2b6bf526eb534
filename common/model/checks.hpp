// Checks of a model read from a file that need the whole model (common/model/model.cpp checks each
// dataset on its own): what the solver would otherwise find later, or not at all.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "common/h5.hpp"

namespace talus {

// Bounds of settings whose extremes pass as finite numbers and fail later: gravity beyond
// 100 g (its energy overflows), a k0 beyond 10 (no soil; 1e308 gave infinite stresses).
constexpr double kMaxGravity = 1000.0;  // m/s^2
constexpr double kMaxK0 = 10.0;

// The first run setting out of range, "settings/run@NAME: expected ..."; empty when all are in
// range.
std::string run_settings_problem(const RunSettings& run);

// What is wrong with a surface load read from a file (one of pressure and traction, finite
// values, a finite ramp >= 0); empty when nothing is.
std::string load_problem(const SurfaceLoad& load);

// The particles' load datasets: load indices in [-1, loads), lengths >= 0, and normal sums no
// longer than the lengths. Throws talus::Error naming `path` and the dataset.
void check_particle_loads(const Model& model, const std::string& path);

// Every triangle counter-clockwise with a positive area, every roller and friction normal non-zero, every
// particle inside (or on the edge of) its element, and the initial state within the bounds of
// initial_state_problem. Throws talus::Error naming `path` and the dataset.
void check_model_geometry(const Model& model, const std::string& path);

// Bounds of an initial state that passes as finite numbers and fails at the first steps:
//  - a speed whose CFL step, cfl h_min / |v| (h_min the smallest element height), is too small
//    for the time to pass run.end_time: below end_time x 2^-52, t + dt == t ("non-finite time
//    step" at step 0 for 1e308 m/s);
//  - a stress component beyond kMaxInitialStrain times the Young's modulus of the particle's
//    material: an elastic strain no soil or rock takes (1e308 Pa failed at step 1, "try a
//    smaller run.cfl").
constexpr double kMaxInitialStrain = 1.0;
struct InitialStateProblem {
  std::size_t particle = 0;
  bool speed = false;   // the speed (else the stress) is out of bounds
  std::string message;  // what and the bound, without the item
};
std::optional<InitialStateProblem> initial_state_problem(const Model& model);

// The root attribute `particles` of a model or results file equals `count`, the rows of its
// particle datasets.
void check_particle_count(const h5::File& file, std::size_t count);

// frames/time of a results file: finite, not negative, never going back.
void check_frame_times(const std::vector<double>& time, const std::string& path);

}  // namespace talus
