// Node fields. Without contact one velocity field serves every body; with contact each group
// of bonded bodies (each body, without bonded pairs) has its own (Bardenhagen et al. 2000) and
// nothing else: the centre of mass is formed where contact needs it. Fields are reset each
// step only where active.
#pragma once
#include <cstdint>
#include <type_traits>
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
  std::vector<Vec2> xpic_term;      // XPIC(m > 1) only: the latest term of its series (xpic.cpp)
};

struct Grids {
  std::vector<int32_t> active;  // nodes touched by a particle's stencil this step
  std::vector<int32_t> active_offsets;  // [thread + 1]: where each thread's share of `active` starts
  std::vector<Grid> fields;     // per field group with contact (fields[field_index[b]] is body b's), else fields[0]
  bool per_body = false;        // contact: a field per group of bonded bodies
  // [body] -> its field: with contact its group's (ContactGroups; body b's own without bonded
  // pairs), else 0.
  std::vector<int32_t> field_index;
  // One load, no branch: P2G's loop over the fixed particles does little else per particle.
  int field_of(int32_t body) const { return field_index[body]; }
};

// Per-thread scatter targets for one velocity field, so that P2G needs no locks.
struct NodeBuffer {
  std::vector<double> m;
  std::vector<Vec2> p, f, mass_gradient;
};

using ThreadBuffers = std::vector<std::vector<NodeBuffer>>;  // [thread][field]

// The threads' scatters at node i of one field's `member` (m, p, f or mass_gradient), added in
// thread order so that the sum does not depend on the schedule, each entry cleared as it is
// read: between the phases every buffer is zero. Every per-thread buffer of the step is reduced
// by this one function (P2G, the remap, XPIC's projections).
template <class T>
T take_thread_sum(ThreadBuffers& buffers, std::size_t field, std::vector<T> NodeBuffer::*member, int32_t i) {
  T zero;
  if constexpr (std::is_arithmetic_v<T>) zero = 0;
  else zero.setZero();
  T sum = zero;
  for (auto& mine : buffers) {
    T& value = (mine[field].*member)[i];
    sum += value;
    value = zero;
  }
  return sum;
}

}  // namespace talus::solver
