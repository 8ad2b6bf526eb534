#include "solver/step/step.hpp"

#include "solver/parallel/domain.hpp"
#include "solver/parallel/threads.hpp"
#include "solver/stress/stress.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

namespace talus::solver {

namespace {

// Laps of step()'s phases into PhaseTimes when timing is on; a null check per phase when off.
class PhaseClock {
 public:
  explicit PhaseClock(PhaseTimes* times) : times_(times) {
    if (times_) last_ = std::chrono::steady_clock::now();
  }
  void lap(PhaseTimes::Phase phase) {
    if (!times_) return;
    const auto now = std::chrono::steady_clock::now();
    times_->seconds[phase] += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }
  ~PhaseClock() {
    if (times_) ++times_->steps;
  }

 private:
  PhaseTimes* times_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace

bool step(Simulation& sim, double dt) {
  const Config& c = sim.config;
  Particles& P = sim.particles;
  Scratch& s = sim.scratch;
  const int threads = c.threads;
  const ContactRules contact{c.pair_friction, c.field_fixed, c.constraints};

  PhaseClock clock(s.phase_times);
  // Several ranks: partition again when the particles have gathered on some (at the start of a
  // step, so that the last step's grid stays whole for the observers).
  if (sim.domain.distributed() && sim.steps > 0 && sim.steps % kRebalanceInterval == 0 && rebalance(sim))
    sort_particles(sim);
  mark_active_nodes(s.stencil, P.size(), s.node_stamp, s.stamp, s.grids, threads);
  clock.lap(PhaseTimes::Mark);
  load_factors(c, sim.time, s.load_factor);
  if (c.full_cell_fill > 0) full_cell_scales(c.mesh, P, c.full_cell_fill, s.cell_volume, s.cell_scale, threads);
  particles_to_grid(P, s.stencil, c.mesh.nodes, gravity_at(c, sim.time), s.load_factor, s.cell_scale, s.grids,
                    s.buffers, threads);
  const bool distributed = sim.domain.distributed();
  if (distributed) exchange_grid_sums(sim);
  clock.lap(PhaseTimes::ToGrid);
  update_grid_accelerations(c.constraints, c.field_fixed, c.damping, dt, s.grids, threads);
  clock.lap(PhaseTimes::GridAcceleration);
  if (c.contact) {
    // The masses are those of this P2G; the remap (A.11) reuses them, and so the list.
    find_contact_nodes(contact, P, s.stencil, s.grids, s.contact_nodes, threads, distributed ? &sim.domain : nullptr);
    apply_contact(contact, dt, s.contact_nodes, s.grids, threads);
    clock.lap(PhaseTimes::Contact);
  }
  if (c.transfer == Transfer::Xpic || c.transfer == Transfer::Apic) {
    // The particles take a grid velocity rather than its increment: PIC's v_i + dt a_i, which
    // XPIC(m) then extends with the part of the particle velocities the grid can represent.
    lagrangian_grid_velocities(dt, s.grids, threads);
    if (c.xpic_order > 1) {
      add_xpic_terms(P, s.stencil, c.constraints, c.xpic_order, s.grids, s.buffers, threads);
      if (c.contact) apply_contact_velocities(contact, s.contact_nodes, s.grids, threads);
    }
    clock.lap(PhaseTimes::GridVelocity);
  }
  update_particle_velocities(P, s.stencil, c.mesh.nodes, c.transfer, dt, s.grids, s.buffers, threads);
  clock.lap(PhaseTimes::ParticleVelocity);
  if (distributed) remap_grid_velocities_distributed(sim);
  else remap_grid_velocities(c.constraints, c.field_fixed, s.grids, s.buffers, threads);
  if (c.contact) apply_contact_velocities(contact, s.contact_nodes, s.grids, threads);
  clock.lap(PhaseTimes::Remap);
  update_particle_kinematics(P, s.stencil, s.grids, c.pic_fraction, dt, s.d_eps, threads);
  clock.lap(PhaseTimes::Kinematics);
  sum_cells(c.mesh, P, c.evs, s.grids.active, s.element_count, s.evs, s.d_eps, threads);
  if (c.evs && distributed) exchange_evs_sums(sim);
  if (c.evs) evs_node_means(s.grids.active, s.evs, threads);
  clock.lap(PhaseTimes::CellSums);
  const CellSums cells{c.mesh, s.stencil, s.element_count, c.evs ? s.evs.node_mean.data() : nullptr};
  s.bad_particle = update_stresses(P, s.d_eps, cells, c, sim.time + dt, dt, threads);
  clock.lap(PhaseTimes::Stresses);
  if (!distributed) {
    s.lost_particle = relocate_particles(c.mesh, P, s.stencil, threads);
  } else {
    // Collective: every rank fails the step when one has a lost or broken particle.
    s.lost_particle = locate_particles(c.mesh, P, threads);
    if (mpi::any(s.lost_particle >= 0 || s.bad_particle >= 0)) {
      s.failed_elsewhere = s.lost_particle < 0 && s.bad_particle < 0;
      sim.time += dt;  // the failed step is counted, as with one rank
      ++sim.steps;
      return false;
    }
    migrate_particles(sim);
    compute_stencil(c.mesh, sim.particles, 0, sim.particles.moving_count, s.stencil, threads);
  }
  clock.lap(PhaseTimes::Relocate);
  sim.time += dt;
  ++sim.steps;
  return s.lost_particle < 0 && s.bad_particle < 0;
}

void mark_active_nodes(const Stencil& stencil, std::size_t particles, std::vector<int32_t>& node_stamp,
                       int32_t& stamp, Grids& grids, int threads) {
  ++stamp;
  const int32_t current = stamp;
  const long nodes = static_cast<long>(node_stamp.size());
  std::vector<int32_t>& offsets = grids.active_offsets;
  offsets.assign(static_cast<std::size_t>(threads) + 1, 0);
  with_width(stencil, [&](auto W) {
#pragma omp parallel num_threads(threads)
  {
    const StencilView S(stencil, W);  // and the rest the loop reads, taken once in the region
    const long n = static_cast<long>(particles);
    const int32_t mark = current;
    int32_t* const stamps = node_stamp.data();
#pragma omp for schedule(static)
    for (long p = 0; p < n; ++p) {
      // Particles sorted by element mostly share their row with the one before: its nodes are marked.
      if (p > 0 && S.row(p) == S.row(p - 1)) continue;
      const int32_t* nodes_of_p = S.nodes(p);
      for (int k = 0; k < W; ++k)
        std::atomic_ref<int32_t>(stamps[nodes_of_p[k]]).store(mark, std::memory_order_relaxed);
    }
    // The list, ascending: each thread counts the marked nodes of its own range of the node
    // numbers, then writes them from the offset the counts before its range give.
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    const long begin = nodes * t / team, end = nodes * (t + 1) / team;
    int32_t count = 0;
    for (long i = begin; i < end; ++i) count += stamps[i] == mark;
    offsets[t + 1] = count;
#pragma omp barrier
#pragma omp single
    {
      for (int k = 0; k < team; ++k) offsets[k + 1] += offsets[k];
      grids.active.resize(static_cast<std::size_t>(offsets[team]));
    }
    int32_t* out = grids.active.data() + offsets[t];
    for (long i = begin; i < end; ++i)
      if (stamps[i] == mark) *out++ = static_cast<int32_t>(i);
  }
  });
}

void full_cell_scales(const Mesh& mesh, const Particles& P, double full_fill,
                      std::vector<std::vector<double>>& cell_volume, std::vector<double>& scale, int threads) {
  const long n = static_cast<long>(P.size());
  const long elements = static_cast<long>(mesh.element_count());
#pragma omp parallel num_threads(threads)
  {
    // Each thread sums into its own array (a run of one cell at a time); the arrays are then
    // added in thread order, so the factors do not depend on the schedule.
    std::vector<double>& volume = cell_volume[omp_get_thread_num()];
    int32_t run_element = -1;
    double run_volume = 0;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      const int32_t e = P.element[p];
      if (e != run_element) {
        if (run_element >= 0) volume[run_element] += run_volume;
        run_element = e, run_volume = 0;
      }
      run_volume += P.volume[p];
    }
    if (run_element >= 0) volume[run_element] += run_volume;
#pragma omp barrier
    const std::size_t team = cell_volume.size();
    std::vector<double>& fill = cell_volume[0];  // the sums, then each cell's fill
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) {
      double sum = fill[e];
      for (std::size_t t = 1; t < team; ++t) sum += cell_volume[t][e], cell_volume[t][e] = 0;
      fill[e] = sum / mesh.area[e];
    }
    // Full: the cell and each cell across its edges (inside the mesh) are filled to full_fill.
    // A cell that lost a particle to its neighbour stays full; a cell at a free surface does not.
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) {
      bool full = fill[e] >= full_fill;
      for (int k = 0; k < 3 && full; ++k) {
        const int32_t across = mesh.neighbours[e][k];
        full = across < 0 || fill[across] >= full_fill;
      }
      scale[e] = full ? 1.0 / fill[e] : 1.0;
    }
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) fill[e] = 0;
  }
}

void particles_to_grid(const Particles& P, const Stencil& stencil, const std::vector<Vec2>& x_i, const Vec2& g,
                       const std::vector<double>& load_factor, const std::vector<double>& cell_scale, Grids& grids,
                       ThreadBuffers& buffers, int threads) {
  with_width(stencil, [&](auto W) {
#pragma omp parallel num_threads(threads)
  {
    auto& mine = buffers[omp_get_thread_num()];
    // What the loop reads, taken once in the region (StencilView): 14 of its 128 instructions a
    // particle were reloads of these (callgrind, docs/benchmarks.md).
    const StencilView S(stencil, W);
    const long n = static_cast<long>(P.size());
    const long moving = static_cast<long>(P.moving_count);
    const bool gradients = grids.per_body;
    const bool affine = !P.C.empty();  // APIC
    const bool loaded = !P.load.empty();  // surface loads
    const bool mixed = !cell_scale.empty();  // mixed integration
    const Vec2 gravity = g;
    const int32_t* const body = P.body.data();
    const int32_t* const field_index = grids.field_index.data();
    const double* const mass = P.m.data();
    const Vec2* const velocity = P.v.data();
    const double* const volume = P.volume.data();
    const Vec4* const sigma = P.sigma.data();
    // Particles sorted by element come in runs that share a stencil row (the same nodes and
    // gradients) and a field: a run's sums over its particles are scattered once, so that the
    // buffers see one update per node and run rather than per particle. The stress enters the
    // force only through V sigma (A.8), whose sum over the run multiplies the shared gradients.
    int32_t run_row = -1, run_element = -1;
    int run_field = 0;
    bool run_fixed = false;
    const int32_t* run_nodes = nullptr;
    const Vec2* run_dN = nullptr;
    double run_mass = 0, Nm[kMaxStencilWidth];
    Vec2 Nmv[kMaxStencilWidth], Nf[kMaxStencilWidth];
    Vec4 V_sigma = Vec4::Zero();
    const auto scatter_run = [&] {
      if (run_row < 0) return;
      NodeBuffer& b = mine[run_field];
      if (mixed) V_sigma *= cell_scale[run_element];
      for (int k = 0; k < W; ++k) {
        const int32_t i = run_nodes[k];
        b.m[i] += Nm[k];                                       // (A.6), lumped
        if (gradients) b.mass_gradient[i] += run_mass * run_dN[k];
        if (run_fixed) continue;  // a fixed body lends its mass (and, for contact, its normals) only
        const Vec2& dN_k = run_dN[k];
        b.p[i] += Nmv[k];
        b.f[i] += Nm[k] * gravity                              // (A.7)
                  - Vec2(V_sigma[0] * dN_k.x() + V_sigma[3] * dN_k.y(),
                         V_sigma[3] * dN_k.x() + V_sigma[1] * dN_k.y())  // (A.8)
                  + Nf[k];
      }
    };
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      const int32_t row = S.row(p);
      const int field = field_index[body[p]];
      const bool fixed = p >= moving;
      if (row != run_row || field != run_field || fixed != run_fixed) {
        scatter_run();
        run_row = row, run_field = field, run_fixed = fixed;
        if (mixed) run_element = P.element[p];  // a row lies in one element (one per element, or per particle)
        run_nodes = S.nodes(p), run_dN = S.gradients(p);
        run_mass = 0;
        V_sigma.setZero();
        for (int k = 0; k < W; ++k) Nm[k] = 0, Nmv[k].setZero(), Nf[k].setZero();
      }
      const double* N = S.weights(p);
      const double m = mass[p];
      run_mass += m;
      for (int k = 0; k < W; ++k) Nm[k] += N[k] * m;
      if (fixed) continue;
      const Vec2 mv = m * velocity[p];
      V_sigma += volume[p] * sigma[p];
      for (int k = 0; k < W; ++k) Nmv[k] += N[k] * mv;
      if (affine) {  // APIC: m_p C_p (x_i - x_p) (Jiang et al. 2015)
        const Vec4& C = P.C[p];
        for (int k = 0; k < W; ++k) {
          const Vec2 d = x_i[run_nodes[k]] - P.x[p];
          Nmv[k] += N[k] * m * Vec2(C[0] * d.x() + C[1] * d.y(), C[2] * d.x() + C[3] * d.y());
        }
      }
      // A surface load's force on the particle, spread over its nodes like its weight (A.7).
      if (loaded && P.load[p] >= 0) {
        const Vec2 f_load = load_factor[P.load[p]] * P.load_force[p];
        for (int k = 0; k < W; ++k) Nf[k] += N[k] * f_load;
      }
    }
    scatter_run();
#pragma omp barrier
    // Reduce the per-thread buffers on the active nodes, in thread order, and clear them.
    const long count = static_cast<long>(grids.active.size());
    const std::size_t team = buffers.size();
#pragma omp for schedule(static)
    for (long k = 0; k < count; ++k) {
      const int32_t i = grids.active[k];
      for (std::size_t field = 0; field < grids.fields.size(); ++field) {
        Grid& grid = grids.fields[field];
        double m = 0;
        Vec2 mom = Vec2::Zero(), force = Vec2::Zero(), gradient = Vec2::Zero();
        for (std::size_t t = 0; t < team; ++t) {
          NodeBuffer& b = buffers[t][field];
          m += b.m[i];
          mom += b.p[i];
          force += b.f[i];
          b.m[i] = 0;
          b.p[i].setZero();
          b.f[i].setZero();
          if (gradients) {
            gradient += b.mass_gradient[i];
            b.mass_gradient[i].setZero();
          }
        }
        grid.m[i] = m;
        grid.p[i] = mom;
        grid.f[i] = force;
        if (gradients) grid.mass_gradient[i] = gradient;
      }
    }
  }
  });
}

void update_grid_accelerations(const Constraints& constraints, const std::vector<uint8_t>& field_fixed, double damping,
                               double dt, Grids& grids, int threads) {
  const auto& active = grids.active;
  const long count = static_cast<long>(active.size());
  for (std::size_t field = 0; field < grids.fields.size(); ++field) {
    Grid& grid = grids.fields[field];
    const bool fixed_body = grids.per_body && field_fixed[field];
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long k = 0; k < count; ++k) {
      const int32_t i = active[k];
      if (grid.m[i] <= 0 || fixed_body) {
        grid.a[i].setZero();
        grid.p[i].setZero();
        continue;
      }
      Vec2 f = grid.f[i];
      if (damping > 0) {  // local damping against the sign of the nodal velocity (Cundall)
        const Vec2& mom = grid.p[i];
        for (int d = 0; d < 2; ++d) f[d] -= damping * std::abs(f[d]) * (mom[d] > 0 ? 1.0 : mom[d] < 0 ? -1.0 : 0.0);
      }
      // The constraint holds for the velocity at the end of the step: a constrained node's
      // acceleration is whatever brings its velocity to the allowed one in dt. Zeroing the
      // acceleration alone would leave the particles beside a fixed node with whatever velocity
      // they carried in, moving nowhere but counted as kinetic energy.
      const Vec2 v = grid.p[i] / grid.m[i];
      Vec2 v_end = v + dt * f / grid.m[i];
      constrain(constraints, i, v_end);
      grid.a[i] = dt > 0 ? Vec2((v_end - v) / dt) : Vec2(f / grid.m[i]);
      if (dt == 0) constrain(constraints, i, grid.a[i]);
    }
  }
}

namespace {

// The velocity update of one transfer scheme, and the momentum for the remap (A.11) scattered
// in the same pass. Flip and PicBlend add the grid acceleration (A.10); Xpic and Apic take the
// velocity left in grid.v; Apic also takes its gradient as the affine matrix C_p (Jiang et al.
// 2015, with grad N for linear elements) and carries it into the remap's momentum,
// m_p (v_p + C_p (x_i - x_p)).
template <Transfer kTransfer>
void particle_velocities(Particles& P, const Stencil& stencil, const std::vector<Vec2>& x_i, double dt,
                         const Grids& grids, ThreadBuffers& buffers, int threads) {
  constexpr bool kIncrement = kTransfer == Transfer::Flip || kTransfer == Transfer::PicBlend;
  constexpr bool kAffine = kTransfer == Transfer::Apic;
  with_width(stencil, [&](auto W) {
#pragma omp parallel num_threads(threads)
  {
    auto& mine = buffers[omp_get_thread_num()];
    const StencilView S(stencil, W);  // and the rest the loop reads, taken once in the region
    const long moving = static_cast<long>(P.moving_count);
    const double step = dt;
    const int32_t* const body = P.body.data();
    const int32_t* const field_index = grids.field_index.data();
    const double* const mass = P.m.data();
    Vec2* const velocity = P.v.data();
    // As in P2G: a run of particles that share a stencil row and a field reads its nodes' values
    // once and scatters the remap's momentum once.
    int32_t run_row = -1;
    int run_field = 0;
    const int32_t* nodes = nullptr;
    const Grid* grid = nullptr;
    Vec2 node_value[kMaxStencilWidth], Nmv[kMaxStencilWidth];
    for (int k = 0; k < kMaxStencilWidth; ++k) node_value[k].setZero(), Nmv[k].setZero();
    const auto scatter_run = [&] {
      if (run_row < 0) return;
      NodeBuffer& b = mine[run_field];
      for (int k = 0; k < W; ++k) b.p[nodes[k]] += Nmv[k];
    };
#pragma omp for schedule(static) nowait
    for (long p = 0; p < moving; ++p) {
      const int32_t row = S.row(p);
      const int field = field_index[body[p]];
      if (row != run_row || field != run_field) {
        scatter_run();
        run_row = row, run_field = field;
        nodes = S.nodes(p);
        grid = &grids.fields[field];
        for (int k = 0; k < W; ++k) {
          node_value[k] = kIncrement ? grid->a[nodes[k]] : grid->v[nodes[k]];
          Nmv[k].setZero();
        }
      }
      const double* N = S.weights(p);
      if constexpr (kIncrement) {
        Vec2 a = Vec2::Zero();
        for (int k = 0; k < W; ++k) a += N[k] * node_value[k];
        velocity[p] += step * a;  // (A.10)
      } else {
        const Vec2* dN = S.gradients(p);
        Vec2 v = Vec2::Zero();
        Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
        for (int k = 0; k < W; ++k) {
          const Vec2& vi = node_value[k];
          v += N[k] * vi;
          if constexpr (kAffine) C += vi * dN[k].transpose();
        }
        velocity[p] = v;
        if constexpr (kAffine) P.C[p] = Vec4(C(0, 0), C(0, 1), C(1, 0), C(1, 1));
      }
      // Momentum for the remap (A.11), summed over the run.
      const double m = mass[p];
      const Vec2 mv = m * velocity[p];
      for (int k = 0; k < W; ++k) {
        if constexpr (kAffine) {
          const Vec4& C = P.C[p];
          const Vec2 d = x_i[nodes[k]] - P.x[p];
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

void remap_grid_velocities(const Constraints& constraints, const std::vector<uint8_t>& field_fixed, Grids& grids,
                           ThreadBuffers& buffers, int threads) {
  const auto& active = grids.active;
  const long count = static_cast<long>(active.size());
  const std::size_t team = buffers.size();
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    const int32_t i = active[k];
    for (std::size_t field = 0; field < grids.fields.size(); ++field) {
      Grid& grid = grids.fields[field];
      Vec2 mom = Vec2::Zero();
      for (std::size_t t = 0; t < team; ++t) {
        mom += buffers[t][field].p[i];
        buffers[t][field].p[i].setZero();
      }
      const bool fixed_body = grids.per_body && field_fixed[field];
      grid.v[i] = grid.m[i] > 0 && !fixed_body ? Vec2(mom / grid.m[i]) : Vec2::Zero();  // (A.11)
      constrain(constraints, i, grid.v[i]);
    }
  }
}

void remap_grid_velocities_distributed(Simulation& sim) {
  const Config& c = sim.config;
  Grids& grids = sim.scratch.grids;
  ThreadBuffers& buffers = sim.scratch.buffers;
  const auto& active = grids.active;
  const long count = static_cast<long>(active.size());
  const std::size_t team = buffers.size();
  // This rank's momentum into grid.v, the ranks' sums at the shared nodes, then (A.11).
#pragma omp parallel for schedule(static) num_threads(c.threads)
  for (long k = 0; k < count; ++k) {
    const int32_t i = active[k];
    for (std::size_t field = 0; field < grids.fields.size(); ++field) {
      Vec2 mom = Vec2::Zero();
      for (std::size_t t = 0; t < team; ++t) {
        mom += buffers[t][field].p[i];
        buffers[t][field].p[i].setZero();
      }
      grids.fields[field].v[i] = mom;
    }
  }
  exchange_remap_momentum(sim);
#pragma omp parallel for schedule(static) num_threads(c.threads)
  for (long k = 0; k < count; ++k) {
    const int32_t i = active[k];
    for (std::size_t field = 0; field < grids.fields.size(); ++field) {
      Grid& grid = grids.fields[field];
      const bool fixed_body = grids.per_body && c.field_fixed[field];
      grid.v[i] = grid.m[i] > 0 && !fixed_body ? Vec2(grid.v[i] / grid.m[i]) : Vec2::Zero();
      constrain(c.constraints, i, grid.v[i]);
    }
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
    // A run of particles that share a stencil row and a field shares the nodes' velocities and,
    // since it shares the gradients, the velocity gradient too: both are read once per run.
    int32_t run_row = -1;
    int run_field = 0;
    Vec2 node_v[kMaxStencilWidth];
    for (Vec2& v : node_v) v.setZero();
    Eigen::Matrix2d L = Eigen::Matrix2d::Zero();  // velocity gradient, L_ab = dv_a / dx_b
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      const int32_t row = S.row(p);
      const int field = field_index[body[p]];
      if (row != run_row || field != run_field) {
        run_row = row, run_field = field;
        const int32_t* nodes = S.nodes(p);
        const Vec2* dN = S.gradients(p);
        const Grid& grid = grids.fields[field];
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

namespace {

// The neighbour walk of every moving particle to its element; with a stencil, in the same pass,
// the particle's row from the walk's last weights, which are its stencil weights in that element.
// (The walk and the stencil were two passes; one runs 300 million fewer instructions over 150
// steps of the 48,812-particle slope, docs/benchmarks.md.) Returns the last particle that left
// the domain, or -1. A template, so that the walk alone tests nothing per particle.
template <bool kWithStencil>
long walk_to_elements(const Mesh& mesh, Particles& P, Stencil* stencil, int threads) {
  long lost = -1;
#pragma omp parallel num_threads(threads) reduction(max : lost)
  {
    // What the loop reads, taken once in the region (MeshView, StencilView).
    const MeshView tables(mesh);
    const long moving = static_cast<long>(P.moving_count);
    const Vec2* const position = P.x.data();
    int32_t* const element = P.element.data();
    StencilRows rows(stencil);
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      Vec3 w;
      const int32_t e = locate(tables, element[p], position[p], &w);
      if (e < 0) {
        lost = std::max(lost, p);
        continue;
      }
      element[p] = e;
      if constexpr (kWithStencil) rows.fill(w, e, static_cast<std::size_t>(p));
    }
  }
  return lost;
}

}  // namespace

long relocate_particles(const Mesh& mesh, Particles& P, Stencil& stencil, int threads) {
  return walk_to_elements<true>(mesh, P, &stencil, threads);
}

long locate_particles(const Mesh& mesh, Particles& P, int threads) {
  return walk_to_elements<false>(mesh, P, nullptr, threads);
}

}  // namespace talus::solver
