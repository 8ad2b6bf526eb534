// Restart state of a solve (OUT/checkpoint.h5): everything the time loop needs to continue as
// if it had never stopped. With the same thread count a restarted run gives the same frames,
// bit for bit, as an uninterrupted one (the solver's sums are ordered by the thread count:
// parallel.hpp).
//
// The file holds the particles in the solver's current (sorted) order with every checkpointed
// field of the registry (particles.hpp), the simulation's time and step count, the loop's own
// state (next output and checkpoint times, the peak kinetic energy, the rest timer, the energy
// budget), how far results.h5 had been written, the model's fingerprints, and the static
// reactions of absorbing boundaries once recorded (absorbing_reaction [R, 2], absent before;
// solver/boundary/absorbing.hpp). It is written to checkpoint.h5.tmp and renamed, so a
// checkpoint is either the previous one or the new one, never half of either.
#pragma once
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "common/model/model.hpp"
#include "solver/io/results.hpp"
#include "solver/step/simulation.hpp"

namespace talus::solver {

inline constexpr int kCheckpointFormatVersion = 3;

// The time loop's state besides the simulation's.
struct LoopState {
  double next_output = 0;      // s, time of the next frame
  double next_checkpoint = 0;  // s, time of the next periodic checkpoint (infinity: none)
  double peak_kinetic = 0;     // J/m, largest grid kinetic energy so far
  double peak_time = 0;        // s, when it was reached
  double rest_since = -1;      // s, start of the current spell below the rest ratio (-1: none)
  double budget = 0;           // J/m, the most energy the run can have (blow-up test)
  double budget_limit = 0;     // J/m, the threshold derived from it
  double budget_supply = std::numeric_limits<double>::infinity();  // J/m, the initial sources of the second test (infinite: none kept)
  double start_potential = 0;      // J/m, the potential energy at the start (the second test)
};

// Fingerprints of the model a checkpoint belongs to, one per section (mesh, boundary
// conditions, particles, initial stress, bodies, each material, contact, run settings): a
// restart on a model that differs in any of them is refused, naming the sections.
std::vector<std::pair<std::string, int64_t>> model_fingerprints(const Model& model);

std::string checkpoint_path(const std::string& out_dir);

void write_checkpoint(const std::string& out_dir, const Model& model, const Simulation& sim, const LoopState& loop,
                      const ResultsPosition& results);
// The same with the model's fingerprints taken before (the model may have given up its particles).
using Fingerprints = std::vector<std::pair<std::string, int64_t>>;
void write_checkpoint(const std::string& out_dir, const Fingerprints& fingerprints, const Simulation& sim,
                      const LoopState& loop, const ResultsPosition& results);
// The same from particles gathered off several ranks (domain.hpp, gather_particles): a
// checkpoint of N ranks restarts on any number of ranks.
void write_checkpoint(const std::string& out_dir, const Fingerprints& fingerprints, const Particles& particles,
                      double time, long steps, const LoopState& loop, const ResultsPosition& results,
                      const std::vector<Vec2>& absorbing_reaction = {});

// Overwrites the particles, time and step count of `sim` (built by make_simulation from the
// same model) with the checkpoint's, and fills `loop` and `results`. Throws talus::Error when
// the file is missing, damaged, of another format version, or of another model.
void read_checkpoint(const std::string& out_dir, const Model& model, Simulation& sim, LoopState& loop,
                     ResultsPosition& results);

}  // namespace talus::solver
