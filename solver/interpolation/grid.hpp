// Node fields. Without contact one velocity field serves every body; with contact each group
// of bonded bodies (each body, without bonded pairs) has its own (Bardenhagen et al. 2000) and
// nothing else: the centre of mass is formed where contact needs it. Fields are reset each
// step only where active.
#pragma once
#include <cstdint>
#include <vector>

#include "solver/interpolation/mesh.hpp"

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
  std::vector<int32_t> active_offsets;  // [thread + 1]: where each thread's share of `active` starts
  std::vector<Grid> fields;     // per field group with contact (fields[field_index[b]] is body b's), else fields[0]
  bool per_body = false;        // contact: a field per group of bonded bodies
  // [body] -> its field: with contact its group's (ContactGroups; body b's own without bonded
  // pairs), else 0.
  std::vector<int32_t> field_index;
  // Contact (contact.cpp), rebuilt each step. For each listed contact node k and field b:
  // whether b takes part in the contact there, and b's outward unit normal (zero for a fixed
  // field). While listing: each candidate node's index (else -1), and per thread the extents of
  // the fields along each normal.
  std::vector<uint8_t> touching;             // [k * bodies + b]
  std::vector<Vec2> contact_normal;          // [k * bodies + b]
  std::vector<int32_t> contact_slot;         // [node]
  std::vector<std::vector<double>> extents;  // [thread][(k * bodies + b) * bodies + c], m
  // The fixed particles [moving_count, size) in runs that share a stencil row, each run's first
  // particle and a final end: fixed particles never move and keep their order.
  std::vector<std::size_t> fixed_runs;

  // One load, no branch: P2G's loop over the fixed particles does little else per particle.
  int field_of(int32_t body) const { return field_index[body]; }
};

// Per-thread scatter targets for one velocity field, so that P2G needs no locks.
struct NodeBuffer {
  std::vector<double> m;
  std::vector<Vec2> p, f, mass_gradient;
};

using ThreadBuffers = std::vector<std::vector<NodeBuffer>>;  // [thread][field]

}  // namespace talus::solver
