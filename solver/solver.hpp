// `talus solve`: runs the explicit time loop on a model and writes results.h5 (+ results.xdmf
// for ParaView). The results layout is documented in docs/results-format.md.
#pragma once
#include <iosfwd>
#include <stdexcept>
#include <string>

#include "common/model/model.hpp"

namespace talus::solver {

struct PhaseTimes;  // simulation.hpp

struct SolveOptions {
  std::string out_dir;   // results.h5 and results.xdmf go here
  bool progress = true;  // progress on stderr: a rewritten line on a terminal, else a line a minute
  int threads = 0;       // 0: chosen from the particle count and the cores (choose_threads, parallel.hpp)
  // Simulated seconds between checkpoints (OUT/checkpoint.h5, see checkpoint.hpp); 0: none,
  // except the one written when SIGINT or SIGTERM stops the run.
  double checkpoint_interval = 0;
  bool restart = false;  // continue from OUT/checkpoint.h5 and OUT/results.h5
  PhaseTimes* phase_times = nullptr;  // when given: wall time per step phase, added to it
};

// Thrown by solve() when SIGINT or SIGTERM stopped it: after the current step, a checkpoint,
// a last frame and the closing of results.h5 (complete = 0). The driver exits with 128 + signal.
struct Interrupted : std::runtime_error {
  Interrupted(int signal_number, const std::string& message) : std::runtime_error(message), signal(signal_number) {}
  int signal;
};

// Thrown by solve() when memory ran out during the time loop (std::bad_alloc), after closing
// results.h5 with the frames written so far (complete = 0); the message says when and what was
// kept. The driver exits with status 3 (docs/robustness.md).
struct OutOfMemory : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SolveSummary {
  long steps = 0;
  std::size_t particles = 0;
  int threads = 1;            // OpenMP threads of the time loop
  std::string thread_choice;  // how they were chosen: "auto: 48,812 particles, 2 cores" or "--threads"
  double simulated_time = 0;  // s
  double setup_seconds = 0;   // wall time before the loop: the simulation, results.h5 and its first frame
  double loop_seconds = 0;    // wall time of the time loop
  double frame_seconds = 0;   // of which writing the frames (results.h5) after the first
  long frames = 0;
  bool stopped_at_rest = false;
  int ranks = 1;                   // MPI ranks (domain.hpp)
  double halo_bytes_per_step = 0;  // bytes sent at shared nodes per step, all ranks together
  long migrated = 0;               // particles that moved to another rank, all ranks together
  long repartitions = 0;
  bool frames_by_ranks = false;    // every rank wrote its rows of the frames (results_parallel.hpp)
  double particle_updates_per_second() const {
    return loop_seconds > 0 ? static_cast<double>(particles) * steps / loop_seconds : 0;
  }
};

// Runs the model to run.end_time (or to rest, or to max_steps). Throws talus::Error, after
// closing results.h5 with the frames written so far, when the run blows up (non-finite state
// or kinetic energy beyond what gravity and the initial state can supply) or a particle
// leaves the domain; the message says when and where. SIGINT and SIGTERM stop it cleanly
// (Interrupted). A run that completes removes its checkpoint.
SolveSummary solve(const Model& model, const SolveOptions& options, std::ostream& log);
// The same on a model its owner gives up: on a fresh run its particle columns move into the
// solver's state instead of being copied, so the model and the simulation are not both held
// (at 10M particles that is 88 bytes per particle less).
SolveSummary solve(Model&& model, const SolveOptions& options, std::ostream& log);

void print_summary(const SolveSummary& summary, std::ostream& out);

}  // namespace talus::solver
