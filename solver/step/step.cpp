// The step's recipe: the phases of the explicit MUSL step in order, each citing the seed's
// equations (appendix A) it carries out. The phases skip what a scene does not need (design.md,
// "Skip what a scene does not need"): contact without two fields that can meet, XPIC's and APIC's
// grid velocities for the other transfers, EVS, mixed integration, loads and water when absent.
#include "solver/step/step.hpp"

#include <chrono>

#include "solver/boundary/absorbing.hpp"
#include "solver/contact/contact.hpp"
#include "solver/interpolation/interpolation.hpp"
#include "solver/parallel/domain.hpp"
#include "solver/stress/stress.hpp"
#include "solver/stress/water.hpp"

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
  const ContactRules contact{c.pair_friction, c.field_fixed, c.constraints, c.node_length,
                             s.stencil.family != ShapeFamily::LinearTriangle};
  const bool distributed = sim.domain.distributed();
  PhaseClock clock(s.phase_times);

  // Several ranks: partition again when the particles have gathered on some (at the start of a
  // step, so that the last step's grid stays whole for the observers).
  if (distributed && sim.steps > 0 && sim.steps % kRebalanceInterval == 0 && rebalance(sim)) sort_particles(sim);
  mark_active_nodes(s.stencil, P.size(), s.node_stamp, s.stamp, s.grids, threads);
  clock.lap(PhaseTimes::Mark);

  // (A.6)-(A.8): m_i, p_i and f_i = f_ext (gravity, surface loads) + f_int (-sum V_p sigma_p grad N_ip).
  load_factors(c.load_ramp, sim.time, s.load_factor);
  if (c.full_cell_fill > 0) full_cell_scales(c.mesh, P, c.full_cell_fill, s.cell_volume, s.cell_scale, threads);
  particles_to_grid({P, s.stencil, c.mesh.nodes, gravity_at(c, sim.time), s.load_factor, s.cell_scale}, s.grids,
                    s.buffers, threads);
  if (distributed) exchange_grid_sums(sim);
  fold_ghosts(c.constraints, s.grids);
  if (!c.absorbing.empty()) apply_static_reactions(sim);  // held fixed, then their reactions: absorbing.hpp
  clock.lap(PhaseTimes::ToGrid);

  // (A.9): a_i = f_i / m_i, constrained by the boundary conditions; contact corrects it.
  update_grid_accelerations(c.constraints, c.field_fixed, c.damping, dt, s.grids, threads);
  if (!c.absorbing.empty()) apply_dashpots(sim, dt);  // absorbing.hpp
  clock.lap(PhaseTimes::GridAcceleration);
  if (c.contact) {
    // The masses are those of this P2G; the remap (A.11) reuses them, and so the list.
    find_contact_nodes(contact, P, s.stencil, s.grids, s.contact, threads, distributed ? &sim.domain : nullptr);
    apply_contact(contact, dt, s.contact, s.grids, threads);
    mirror_accelerations(c.constraints, s.grids);
    clock.lap(PhaseTimes::Contact);
  }
  if (c.transfer == Transfer::Xpic || c.transfer == Transfer::Apic) {
    // The particles take a grid velocity rather than its increment: PIC's v_i + dt a_i, which
    // XPIC(m) then extends with the part of the particle velocities the grid can represent.
    lagrangian_grid_velocities(c.constraints, dt, s.grids, threads);
    if (c.xpic_order > 1) {
      add_xpic_terms(P, s.stencil, c.constraints, c.xpic_order, s.grids, s.buffers, threads);
      if (c.contact) {
        apply_contact_velocities(contact, s.contact, s.grids, threads);
        mirror_velocities(c.constraints, s.grids);
      }
    }
    clock.lap(PhaseTimes::GridVelocity);
  }

  // (A.10): v_p += dt sum N_ip a_i (or the transfer's grid velocity), and (A.11)'s momentum.
  update_particle_velocities(P, s.stencil, c.mesh.nodes, c.transfer, dt, s.grids, s.buffers, threads);
  clock.lap(PhaseTimes::ParticleVelocity);
  // (A.11): v_i = sum N_ip m_p v_p / m_i, constrained and contact-corrected.
  if (distributed) {
    remap_grid_velocities(c.constraints, c.field_fixed, s.grids, s.buffers, threads,
                          [&] { exchange_remap_momentum(sim); });
  } else {
    remap_grid_velocities(c.constraints, c.field_fixed, s.grids, s.buffers, threads);
  }
  if (c.contact) {
    apply_contact_velocities(contact, s.contact, s.grids, threads);
    mirror_velocities(c.constraints, s.grids);
  }
  clock.lap(PhaseTimes::Remap);

  // (A.12): x_p += dt sum N_ip v_i; the strain increment and the stress's rotation.
  update_particle_kinematics(P, s.stencil, s.grids, c.pic_fraction, dt, s.d_eps, threads);
  if (s.stencil.family == ShapeFamily::LinearCpdi) move_domains(c.mesh, P, s.stencil, s.grids, dt, threads);
  if (s.keep_step_velocity) keep_step_velocities(sim);  // for a frame, before the stencil moves on
  clock.lap(PhaseTimes::Kinematics);
  sum_cells(c.mesh, P, c.evs, s.grids.active, s.element_count, s.evs, s.d_eps, threads);
  if (c.evs && distributed) exchange_evs_sums(sim);
  if (c.evs) evs_node_means(s.grids.active, s.evs, threads);
  clock.lap(PhaseTimes::CellSums);

  // The constitutive update with EVS's volumetric strain, and V_p *= 1 + tr d_eps.
  const CellSums cells{c.mesh, s.stencil, s.element_count, c.evs ? s.evs.node_mean.data() : nullptr, &s.grids};
  s.bad_particle = update_stresses(P, s.d_eps, cells, c, sim.time + dt, dt, threads);
  clock.lap(PhaseTimes::Stresses);

  // Each particle's element and stencil for the next step.
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

}  // namespace talus::solver
