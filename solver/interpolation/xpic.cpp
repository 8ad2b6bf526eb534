// The grid velocity that XPIC and APIC hand to the particles (docs/transfer.md).
//
// FLIP adds the grid acceleration to each particle velocity and so keeps every particle
// velocity component the grid cannot see: with S the particle-from-node interpolation
// (S v)_p = sum_i N_ip v_i and S+ the lumped-mass projection (S+ u)_i = sum_p m_p N_ip u_p / m_i,
// the component (I - S S+) v_p is never touched. PIC replaces v_p by S (v_i + dt a_i) and so
// drops it, with whatever real motion it held. XPIC(m) (Hammerquist and Nairn 2017, CMAME 318)
// drops only its m-th power:
//   v_p <- v_p - (I - S S+)^m v_p + dt S a,
// which the identity S (I - S+S)^k S+ = (I - S S+)^k S S+ turns into grid work alone:
//   v_p <- S v*,  v* = v_i + dt a_i + sum_{k=1}^{m-1} (I - S+S)^k v_i,  v_i = S+ v_p (P2G's).
// Each power of S+S is one particle pass that gathers S u and scatters m_p N_ip (S u)_p; m = 1
// is PIC, and m -> infinity is FLIP less its null-space noise.
#include <omp.h>

#include "solver/interpolation/interpolation.hpp"

namespace talus::solver {

void add_xpic_terms(const Particles& P, const Stencil& S, const Constraints& constraints, int order, Grids& grids,
                    ThreadBuffers& buffers, int threads) {
  const auto& active = grids.active;
  const long count = static_cast<long>(active.size());
  const long moving = static_cast<long>(P.moving_count);
  const int W = S.width;
  // The series starts from P2G's velocity v_i = p_i / m_i.
  for (Grid& grid : grids.fields) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long k = 0; k < count; ++k) {
      const int32_t i = active[k];
      grid.xpic_term[i] = grid.m[i] > 0 ? Vec2(grid.p[i] / grid.m[i]) : Vec2::Zero();
    }
  }
  for (int power = 1; power < order; ++power) {
#pragma omp parallel num_threads(threads)
    {
      // S+S applied to the latest term, scattered into the per-thread momentum buffers (empty
      // between phases: each reduction clears what it reads).
      auto& mine = buffers[omp_get_thread_num()];
#pragma omp for schedule(static)
      for (long p = 0; p < moving; ++p) {
        const double* N = S.weights(p);
        const int32_t* nodes = S.nodes(p);
        const int field = grids.field_of(P.body[p]);
        const Grid& grid = grids.fields[field];
        Vec2 u = Vec2::Zero();
        for (int k = 0; k < W; ++k) u += N[k] * grid.xpic_term[nodes[k]];
        const Vec2 mu = P.m[p] * u;
        NodeBuffer& b = mine[field];
        for (int k = 0; k < W; ++k) b.p[nodes[k]] += N[k] * mu;
      }
      // term <- (I - S+S) term, added to v*; in thread order, as every reduction.
#pragma omp for schedule(static)
      for (long k = 0; k < count; ++k) {
        const int32_t i = active[k];
        for (std::size_t field = 0; field < grids.fields.size(); ++field) {
          Grid& grid = grids.fields[field];
          const Vec2 projected = take_thread_sum(buffers, field, &NodeBuffer::p, i);
          if (!(grid.m[i] > 0)) continue;
          grid.xpic_term[i] -= projected / grid.m[i];
          grid.v[i] += grid.xpic_term[i];
        }
      }
    }
  }
  // v_i + dt a_i already obeys the constraints; the series must too.
  for (Grid& grid : grids.fields) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long k = 0; k < count; ++k) constrain(constraints, active[k], grid.v[active[k]]);
  }
}

}  // namespace talus::solver
