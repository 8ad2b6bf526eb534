// Grid to particles: the particle velocities (A.10, or the grid velocity of XPIC and APIC) with
// the remap's momentum (A.11's numerator) scattered in the same pass, and the kinematics (A.12):
// positions, strain increments and the Jaumann rotation of the stress.
#include <omp.h>

#include "solver/interpolation/interpolation.hpp"
#include "solver/interpolation/runs.hpp"

namespace talus::solver {
namespace {

// APIC's C_p = B_p D_p^-1, B_p = sum N_ip v_i (x_i - x_p)^T, as (xx, xy, yx, yy), from the
// velocities v_i of particle p's W nodes. The family gives D_p^-1 (Stencil::inverse_inertia,
// diagonal): 4 / h^2 per axis for quadratic B-splines; for linear shape functions (zero)
// C_p = sum v_i grad N_ip^T, which is B_p D_p^-1 for them (Jiang et al. 2017).
template <class Width>
Vec4 affine_matrix(int W, const StencilView<Width>& S, const Vec2& inverse_inertia, const Vec4* own_inverse, long p,
                   const Vec2* v_i, const Vec2* x_i, const Vec2& x_p) {
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  if (own_inverse) {  // CPDI: B_p D_p^-1 with the particle's own D_p^-1 (stencil.hpp, fill_cpdi)
    const double* N = S.weights(p);
    const int32_t* nodes = S.nodes(p);
    Eigen::Matrix2d B = Eigen::Matrix2d::Zero(), inverse;
    for (int k = 0; k < W; ++k) B += N[k] * v_i[k] * (x_i[nodes[k]] - x_p).transpose();
    const Vec4& d = own_inverse[p];
    inverse << d[0], d[1], d[2], d[3];
    C = B * inverse;
  } else if (inverse_inertia.isZero()) {
    const Vec2* dN = S.gradients(p);
    for (int k = 0; k < W; ++k) C += v_i[k] * dN[k].transpose();
  } else {
    const double* N = S.weights(p);
    const int32_t* nodes = S.nodes(p);
    for (int k = 0; k < W; ++k)
      C += N[k] * v_i[k] * (x_i[nodes[k]] - x_p).cwiseProduct(inverse_inertia).transpose();
  }
  return Vec4(C(0, 0), C(0, 1), C(1, 0), C(1, 1));
}

// The velocity update of one transfer (docs/transfer.md). Flip and PicBlend add the grid
// acceleration (A.10); Xpic and Apic take the velocity left in grid.v; Apic also takes the affine
// matrix C_p from it and carries it into the remap's momentum, m_p (v_p + C_p (x_i - x_p))
// (Jiang et al. 2015). A run of particles (runs.hpp) reads its nodes' values once and scatters
// its momentum, A.11's numerator, once.
template <Transfer kTransfer>
void particle_velocities(Particles& P, const Stencil& stencil, const std::vector<Vec2>& x_i, double dt,
                         const Grids& grids, ThreadBuffers& buffers, int threads) {
  constexpr bool kIncrement = kTransfer == Transfer::Flip || kTransfer == Transfer::PicBlend;
  constexpr bool kAffine = kTransfer == Transfer::Apic;
  with_width(stencil, [&](auto W) {
#pragma omp parallel num_threads(threads)
  {
    NodeBuffer* const mine = buffers[omp_get_thread_num()].data();
    const StencilView S(stencil, W);  // and the rest the loop reads, taken once in the region
    const long moving = static_cast<long>(P.moving_count);
    const double step = dt;
    const Vec2 inverse_inertia = stencil.inverse_inertia;
    const Vec4* const own_inverse = stencil.own_inverse_inertia.empty() ? nullptr : stencil.own_inverse_inertia.data();
    const int32_t* const body = P.body.data();
    const int32_t* const field_index = grids.field_index.data();
    const double* const mass = P.m.data();
    const Vec2* const position = P.x.data();
    const Vec2* const node_position = x_i.data();
    Vec2* const velocity = P.v.data();
    Vec4* const affine = kAffine ? P.C.data() : nullptr;
    // The open run, in locals the compiler keeps in registers: its nodes' a_i (or v_i), and
    // sum N_ip m_p v_p over its particles.
    constexpr int kEntries = entries_for<decltype(W)>();
    Runs runs;
    const int32_t* nodes = nullptr;
    Vec2 node_value[kEntries], Nmv[kEntries];
    for (int k = 0; k < kEntries; ++k) node_value[k].setZero(), Nmv[k].setZero();
    const auto scatter_run = [&] {
      if (!runs.any()) return;
      NodeBuffer& b = mine[runs.current().field];
      for (int k = 0; k < W; ++k) b.p[nodes[k]] += Nmv[k];
    };
#pragma omp for schedule(static) nowait
    for (long p = 0; p < moving; ++p) {
      const RunKey key{S.row(p), field_index[body[p]]};
      if (runs.starts(key)) {
        scatter_run();
        runs.open(key);
        nodes = S.nodes(p);
        const Grid& grid = grids.fields[key.field];
        for (int k = 0; k < W; ++k) {
          node_value[k] = kIncrement ? grid.a[nodes[k]] : grid.v[nodes[k]];
          Nmv[k].setZero();
        }
      }
      const double* N = S.weights(p);
      if constexpr (kIncrement) {
        Vec2 a = Vec2::Zero();
        for (int k = 0; k < W; ++k) a += N[k] * node_value[k];
        velocity[p] += step * a;  // (A.10)
      } else {
        Vec2 v = Vec2::Zero();
        for (int k = 0; k < W; ++k) v += N[k] * node_value[k];
        velocity[p] = v;
        if constexpr (kAffine) affine[p] = affine_matrix(W, S, inverse_inertia, own_inverse, p, node_value, node_position, position[p]);
      }
      // Momentum for the remap (A.11), summed over the run.
      const double m = mass[p];
      const Vec2 mv = m * velocity[p];
      for (int k = 0; k < W; ++k) {
        if constexpr (kAffine) {
          const Vec4& C = affine[p];
          const Vec2 d = node_position[nodes[k]] - position[p];
          Nmv[k] += N[k] * (mv + m * Vec2(C[0] * d.x() + C[1] * d.y(), C[2] * d.x() + C[3] * d.y()));
        } else {
          Nmv[k] += N[k] * mv;
        }
      }
    }
    scatter_run();
  }
  });
}

}  // namespace

void update_particle_velocities(Particles& P, const Stencil& S, const std::vector<Vec2>& x_i, Transfer transfer,
                                double dt, const Grids& grids, ThreadBuffers& buffers, int threads) {
  switch (transfer) {
    case Transfer::Flip: return particle_velocities<Transfer::Flip>(P, S, x_i, dt, grids, buffers, threads);
    case Transfer::PicBlend: return particle_velocities<Transfer::PicBlend>(P, S, x_i, dt, grids, buffers, threads);
    case Transfer::Xpic: return particle_velocities<Transfer::Xpic>(P, S, x_i, dt, grids, buffers, threads);
    case Transfer::Apic: return particle_velocities<Transfer::Apic>(P, S, x_i, dt, grids, buffers, threads);
  }
}

void update_particle_kinematics(Particles& P, const Stencil& stencil, const Grids& grids, double pic_fraction,
                                double dt, std::vector<Vec4>& d_eps, int threads) {
  with_width(stencil, [&](auto W) {
#pragma omp parallel num_threads(threads)
  {
    const StencilView S(stencil, W);  // and the rest the loop reads, taken once in the region
    const long moving = static_cast<long>(P.moving_count);
    const double step = dt, pic = pic_fraction;
    const int32_t* const body = P.body.data();
    const int32_t* const field_index = grids.field_index.data();
    Vec2* const position = P.x.data();
    Vec2* const velocity = P.v.data();
    Vec4* const sigma = P.sigma.data();
    Vec4* const strain = d_eps.data();
    // A run of particles shares its nodes' velocities and, since it shares the gradients, the
    // velocity gradient too: both are read once per run.
    Runs runs;
    Vec2 node_v[kMaxStencilWidth];
    for (Vec2& v : node_v) v.setZero();
    Eigen::Matrix2d L = Eigen::Matrix2d::Zero();  // velocity gradient, L_ab = dv_a / dx_b
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      const RunKey key{S.row(p), field_index[body[p]]};
      if (runs.starts(key)) {
        runs.open(key);
        const int32_t* nodes = S.nodes(p);
        const Vec2* dN = S.gradients(p);
        const Grid& grid = grids.fields[runs.current().field];
        L.setZero();
        for (int k = 0; k < W; ++k) {
          node_v[k] = grid.v[nodes[k]];
          L += node_v[k] * dN[k].transpose();
        }
      }
      const double* N = S.weights(p);
      Vec2 v = Vec2::Zero();
      for (int k = 0; k < W; ++k) v += N[k] * node_v[k];
      position[p] += step * v;  // (A.12)
      if (pic != 0) velocity[p] += pic * (v - velocity[p]);  // FLIP-PIC blend; not for the pure FLIP of (A.10)

      strain[p] = Vec4(step * L(0, 0), step * L(1, 1), 0, 0.5 * step * (L(0, 1) + L(1, 0)));
      // Jaumann rate: sigma += W sigma - sigma W with the spin w = dt (L_xy - L_yx) / 2.
      const double w = 0.5 * step * (L(0, 1) - L(1, 0));
      Vec4& s = sigma[p];
      const double rotation_xx = 2 * w * s[3], rotation_xy = w * (s[1] - s[0]);
      s[0] += rotation_xx;
      s[1] -= rotation_xx;
      s[3] += rotation_xy;
    }
  }
  });
}

}  // namespace talus::solver
