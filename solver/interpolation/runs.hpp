// Runs of particles. Particles sorted by element come in runs that share a stencil row: the
// same nodes and the same gradients (stencil.hpp). A phase that scatters to a particle's nodes
// sums a run's particles first and touches each node once per run (P2G, the remap's momentum);
// one that gathers from the nodes reads them once per run (the velocity update, the
// kinematics). A run also keeps to one velocity field (a body or a group of bonded bodies under
// contact) and, in P2G, to moving or fixed particles. A family with a row per particle has runs
// of one, which is the particle-by-particle loop.
#pragma once
#include <cstdint>

namespace talus::solver {

struct RunKey {
  int32_t row = -1;    // the stencil row
  int field = 0;       // the velocity field (Grids::field_index)
  bool fixed = false;  // a fixed body's particles (P2G only)
  bool operator==(const RunKey&) const = default;
};

// Follows one thread's particles, in order: where each new run starts, and which run is open.
//   if (runs.starts(key)) { finish the open run; runs.open(key); start the new one; }
class Runs {
 public:
  // Whether the particle with this key starts a new run (the first one always does).
  bool starts(const RunKey& key) const { return !(key == current_); }
  void open(const RunKey& key) { current_ = key; }
  // Whether a run is open (so that it is to be finished).
  bool any() const { return current_.row >= 0; }
  const RunKey& current() const { return current_; }

 private:
  RunKey current_;
};

}  // namespace talus::solver
