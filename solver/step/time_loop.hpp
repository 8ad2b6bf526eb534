// The one time loop: `talus solve` and every strength-reduction run drive the step through it.
// Each step takes the CFL time step (A.13), shortened to land exactly on the next time an
// observer asks for (a frame); then the observers see the result, in order. What a run does
// besides stepping (frames, checkpoints, the energy history, the blow-up budget, rest
// detection, sorting the particles, a factor-of-safety verdict, progress, signals) is an
// observer, so the two kinds of run share every policy they have in common.
#pragma once
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "solver/step/simulation.hpp"

namespace talus::solver {

inline constexpr double kNever = std::numeric_limits<double>::infinity();

// The CFL step (A.13): dt = cfl h_min / (c_d + max |v_p|).
double stable_time_step(const Simulation& sim, double cfl);

// What the observers see of a step. The energies are computed at most once per step, on the
// first call of energies(), so after any observer before it changed the particles' order.
class StepEvent {
 public:
  StepEvent(const Simulation& sim, double dt, bool energies_due) : dt(dt), energies_due(energies_due), sim_(&sim) {}
  double dt;          // the step just taken (s)
  bool energies_due;  // an observer asked for this step's energies (wants_energies)
  const Energies& energies() const {
    if (!energies_) energies_ = solver::energies(*sim_);
    return *energies_;
  }

 private:
  const Simulation* sim_;
  mutable std::optional<Energies> energies_;
};

// An observer's answer after a step.
struct Verdict {
  enum Kind { Continue, Stop, Fail } kind = Continue;
  std::string reason;  // why the run stops or fails

  static Verdict go_on() { return {}; }
  static Verdict stop(std::string why) { return {Stop, std::move(why)}; }
  static Verdict fail(std::string why) { return {Fail, std::move(why)}; }
};

class Observer {
 public:
  virtual ~Observer() = default;
  // A time the loop must land on exactly (s); kNever for none.
  virtual double next_landing(const Simulation&) const { return kNever; }
  // Whether this step's energies are wanted; asked after the step, before any after_step.
  virtual bool wants_energies(const Simulation&) const { return false; }
  // Whether the step that ends at `time` (s) should keep its grid velocity at the particles
  // (Particles::step_velocity); asked before the step.
  virtual bool wants_step_velocity(const Simulation&, double /*time*/) const { return false; }
  virtual Verdict after_step(Simulation& sim, const StepEvent& event) = 0;
};

struct LoopEnd {
  enum Kind {
    EndTime,      // reached the end time
    Stopped,      // an observer stopped it (Verdict::reason says why)
    Failed,       // an observer found a failure (blow-up budget, say)
    StepFailed,   // the step itself failed: a particle left the domain or a state became non-finite
    BadTimeStep,  // the CFL step was not a positive finite number
  } kind = EndTime;
  std::string reason;
  const Observer* by = nullptr;  // Stopped, Failed: the observer that ended the run
};

// Steps sim until end_time (kNever: until an observer stops it), telling each observer after
// each step in the order given, until one stops or fails the run (the later ones are not told
// of that step). Observers are not owned.
LoopEnd run_time_loop(Simulation& sim, double cfl, double end_time, const std::vector<Observer*>& observers);

// ---- Observers that every run can use ---------------------------------------------------------

// Re-orders the particles by element every `interval` steps, for memory locality.
class ParticleSorter : public Observer {
 public:
  explicit ParticleSorter(long interval = 25) : interval_(interval) {}
  Verdict after_step(Simulation& sim, const StepEvent&) override;

 private:
  long interval_;
};

// What a run can draw on besides numerical sources, J/m. `initial`: the kinetic and strain energy
// at the start plus bounds on the work of surface loads and of a moving ground; `gravity`: what
// gravity can release by bringing each particle to the lowest node.
struct EnergySources {
  double initial = 0;
  double gravity = 0;
};
EnergySources energy_sources(const Simulation& sim, const Energies& start);

// Fails the run on a numerical blow-up, checked on every step whose energies are due:
// - the kinetic energy (grid or particle) is non-finite or beyond twice the budget;
// - the kinetic plus elastic strain energy is beyond 4 times what the run has drawn so far: the
//   initial sources and the work gravity has done since the start (the fall of the potential
//   energy -sum m_p g . x_p, with the full gravity), plus a thousandth of the budget. An
//   instability that stores its energy in the stress (a stiff body's particles in a light
//   body's elements, say) passes the first test: a block 1 m up a light spring has a budget of
//   51 J/m while the spring and block settle with 0.07 J/m.
class BlowUpBudget : public Observer {
 public:
  BlowUpBudget() = default;
  // `supply` and `start_potential` (the initial sources and the potential energy at the start):
  // infinite when a checkpoint written before the second test does not hold them.
  BlowUpBudget(double budget, double limit, double supply = kNever, double start_potential = 0)
      : budget_(budget), limit_(limit), supply_(supply), start_potential_(start_potential) {}
  // Budget and limit of a run starting from sim's current state.
  static BlowUpBudget starting_from(const Simulation& sim, const Energies& start);
  Verdict after_step(Simulation& sim, const StepEvent& event) override;
  double budget() const { return budget_; }
  double limit() const { return limit_; }
  double supply() const { return supply_; }
  double start_potential() const { return start_potential_; }
  // The second test's threshold at the state `energy`.
  double drawn_limit(const Energies& energy) const;
  bool exceeded_by(const Energies& energy) const;

 private:
  // The first test: a non-finite energy, or the kinetic energy beyond the limit.
  bool beyond_budget(const Energies& energy) const;

  double budget_ = kNever, limit_ = kNever, supply_ = kNever, start_potential_ = 0;
};

}  // namespace talus::solver
