#include "solver/step/time_loop.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "solver/parallel/domain.hpp"
#include "solver/step/step.hpp"

namespace talus::solver {

double stable_time_step(const Simulation& sim, double cfl) {
  double wave_speed = 0;
  for (const auto& material : sim.config.materials) wave_speed = std::max(wave_speed, material.wave_speed);
  double max_speed_squared = 0;
  const Particles& P = sim.particles;
  const long n = static_cast<long>(P.moving_count);
#pragma omp parallel for reduction(max : max_speed_squared) schedule(static) num_threads(sim.config.threads)
  for (long p = 0; p < n; ++p) max_speed_squared = std::max(max_speed_squared, P.v[p].squaredNorm());
  double max_speed = std::sqrt(max_speed_squared);  // sqrt is monotone: the largest norm, exactly
  if (sim.domain.distributed()) max_speed = mpi::max(max_speed);
  return cfl * sim.config.mesh.h_min / (wave_speed + max_speed);  // (A.13)
}

LoopEnd run_time_loop(Simulation& sim, double cfl, double end_time, const std::vector<Observer*>& observers) {
  // Times within a billionth of the end time count as the end (a frame time summed from its
  // interval lands there only to round-off).
  const double tolerance = std::isfinite(end_time) ? 1e-9 * end_time : 0;
  while (sim.time < end_time - tolerance) {
    double dt = stable_time_step(sim, cfl);
    if (!std::isfinite(dt) || dt <= 0) {
      std::ostringstream why;
      why << "non-finite time step at t = " << sim.time << " s";
      return {LoopEnd::BadTimeStep, why.str()};
    }
    double landing = kNever;
    for (const Observer* o : observers) landing = std::min(landing, o->next_landing(sim));
    dt = std::min(dt, landing - sim.time);
    if (!(dt > 0)) {  // an observer landing at or before now would make the loop spin in place
      std::ostringstream why;
      why << "no time step left at t = " << sim.time << " s: the next output or checkpoint time, " << landing
          << " s, is not ahead of it";
      return {LoopEnd::BadTimeStep, why.str()};
    }
    bool keep = false;
    for (const Observer* o : observers) keep = keep || o->wants_step_velocity(sim, sim.time + dt);
    sim.scratch.keep_step_velocity = keep;
    if (!step(sim, dt)) return {LoopEnd::StepFailed, ""};

    bool energies_due = false;
    for (const Observer* o : observers) energies_due = energies_due || o->wants_energies(sim);
    const StepEvent event(sim, dt, energies_due);
    for (Observer* o : observers) {
      const Verdict verdict = o->after_step(sim, event);
      if (verdict.kind == Verdict::Stop) return {LoopEnd::Stopped, verdict.reason, o};
      if (verdict.kind == Verdict::Fail) return {LoopEnd::Failed, verdict.reason, o};
    }
  }
  return {LoopEnd::EndTime, ""};
}

Verdict ParticleSorter::after_step(Simulation& sim, const StepEvent&) {
  if (sim.steps % interval_ == 0) sort_particles(sim);
  return Verdict::go_on();
}

EnergySources energy_sources(const Simulation& sim, const Energies& start) {
  const Vec2& g = sim.config.gravity;
  double lowest = kNever;
  const Vec2 down = g.norm() > 0 ? Vec2(g.normalized()) : Vec2(0, -1);
  for (const auto& x : sim.config.mesh.nodes) lowest = std::min(lowest, -down.dot(x));
  double fall = 0, release = 0;
  const Particles& P = sim.particles;
  for (std::size_t p = 0; p < P.moving_count; ++p) fall += P.m[p] * g.norm() * (-down.dot(P.x[p]) - lowest);
  // Surface loads: at most their full force over the width of the mesh each.
  if (!P.load.empty()) {
    Eigen::AlignedBox<double, 2> box;
    for (const auto& x : sim.config.mesh.nodes) box.extend(x);
    for (std::size_t p = 0; p < P.moving_count; ++p) release += P.load_force[p].norm() * box.diagonal().norm();
  }
  // A moving ground: its inertial force over at most the mesh's width (one of the ground's frame).
  if (sim.config.ground_moves) {
    Eigen::AlignedBox<double, 2> box;
    for (const auto& x : sim.config.mesh.nodes) box.extend(x);
    const double work = sim.config.base_motion.peak_acceleration() * box.diagonal().norm();
    for (std::size_t p = 0; p < P.moving_count; ++p) release += P.m[p] * work;
  }
  // A compliant base: the outcrop motion's kinetic energy, taken 100 times over (resonance).
  if (sim.config.base_motion.compliant && !sim.config.absorbing.empty()) {
    const BaseMotion& m = sim.config.base_motion;
    double peak = 0;
    for (int k = 0; k <= 1000; ++k) peak = std::max(peak, m.ground_velocity(m.start + k * m.duration() / 1000).norm());
    for (std::size_t p = 0; p < P.moving_count; ++p) release += 50 * P.m[p] * peak * peak;
  }
  if (sim.domain.distributed()) {
    double both[2] = {fall, release};
    mpi::sum_in_rank_order(both, 2);
    fall = both[0], release = both[1];
  }
  return {start.kinetic + start.strain + release, fall};
}

BlowUpBudget BlowUpBudget::starting_from(const Simulation& sim, const Energies& start) {
  const EnergySources sources = energy_sources(sim, start);
  const double budget = sources.initial + sources.gravity;  // the most energy the run can have
  // Round-off in the budget's own terms, so a body at rest under no load is no blow-up.
  return BlowUpBudget(budget, 2 * budget + 1e-9 * std::abs(start.potential) + 1e-12, sources.initial,
                      start.potential);
}

double BlowUpBudget::drawn_limit(const Energies& energy) const {
  return 4 * (supply_ + std::max(0.0, start_potential_ - energy.potential)) + 1e-3 * budget_;
}

bool BlowUpBudget::beyond_budget(const Energies& energy) const {
  return !std::isfinite(energy.kinetic + energy.grid_kinetic + energy.strain) ||
         std::max(energy.kinetic, energy.grid_kinetic) > limit_;
}

bool BlowUpBudget::exceeded_by(const Energies& energy) const {
  return beyond_budget(energy) ||
         std::max(energy.kinetic, energy.grid_kinetic) + energy.strain > drawn_limit(energy);
}

Verdict BlowUpBudget::after_step(Simulation& sim, const StepEvent& event) {
  if (!event.energies_due || !exceeded_by(event.energies())) return Verdict::go_on();
  const Energies& energy = event.energies();
  std::ostringstream message;
  message << "numerical blow-up at step " << sim.steps << ", t = " << sim.time << " s: ";
  if (beyond_budget(energy))
    message << "kinetic energy " << energy.kinetic << " J/m exceeds the " << budget_
            << " J/m that gravity and the initial state can supply";
  else
    message << "kinetic and elastic strain energy " << std::max(energy.kinetic, energy.grid_kinetic) + energy.strain
            << " J/m exceed 4 times the "
            << supply_ + std::max(0.0, start_potential_ - energy.potential)
            << " J/m that the initial state and gravity's work so far supply";
  message << " (try a smaller run.cfl)";
  return Verdict::fail(message.str());
}

}  // namespace talus::solver
