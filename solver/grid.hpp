// Node fields. Without contact one velocity field serves every body; with contact each body
// has its own (Bardenhagen et al. 2000) and nothing else: the centre of mass is formed where
// contact needs it. Fields are reset each step only where active.
#pragma once
#include <cstdint>
#include <vector>

#include "solver/mesh.hpp"

namespace talus::solver {

struct Grid {
  std::vector<double> m;   // lumped mass (A.6)
  std::vector<Vec2> p;     // momentum
  std::vector<Vec2> f;     // total force, internal (A.8) plus external (A.7)
  std::vector<Vec2> a;     // acceleration
  std::vector<Vec2> v;     // velocity after the remap (A.11)
  std::vector<Vec2> mass_gradient;  // sum m_p grad N_ip: the outward normal (contact only)
  std::vector<Vec2> xpic_term;      // XPIC(m > 1) only: the latest term of its series (transfer.cpp)
};

struct Grids {
  std::vector<int32_t> active;  // nodes touched by a particle's stencil this step
  std::vector<Grid> fields;     // per body with contact (fields[b] is body b's), else fields[0]
  bool per_body = false;

  int field_of(int32_t body) const { return per_body ? body : 0; }
};

// Per-thread scatter targets for one velocity field, so that P2G needs no locks.
struct NodeBuffer {
  std::vector<double> m;
  std::vector<Vec2> p, f, mass_gradient;
};

using ThreadBuffers = std::vector<std::vector<NodeBuffer>>;  // [thread][field]

}  // namespace talus::solver
