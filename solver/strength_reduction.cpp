#include "solver/strength_reduction.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <ostream>
#include <sstream>
#include <thread>

#include "common/error.hpp"
#include "solver/step/time_loop.hpp"

namespace talus::solver {

// ---- The search -----------------------------------------------------------------------------

SearchResult search_factor_of_safety(const TrialBatch& evaluate, const SearchSettings& s) {
  if (!(s.stable_factor > 0)) throw Error("factor of safety search: the stable factor must be positive");
  if (s.failed_factor && !(*s.failed_factor > s.stable_factor))
    throw Error("factor of safety search: the failing factor " + std::to_string(*s.failed_factor) +
                " is not above the stable one " + std::to_string(s.stable_factor));
  if (!(s.tolerance > 0)) throw Error("factor of safety search: the tolerance must be positive");
  const int workers = std::max(1, s.workers);
  SearchResult r;
  r.lower = s.stable_factor;
  std::optional<double> upper = s.failed_factor;

  while (!upper || *upper - r.lower > s.tolerance) {
    if (r.rounds >= s.max_rounds) throw Error("factor of safety search: no bracket within " + std::to_string(s.max_rounds) + " rounds");
    std::vector<double> factors;
    if (!upper) {  // expand upwards from the largest stable factor
      if (r.lower * s.growth > s.max_factor)
        throw Error("factor of safety search: the slope is still stable at F = " + std::to_string(r.lower) +
                    " (searched up to " + std::to_string(s.max_factor) + ")");
      double f = r.lower;
      for (int k = 0; k < workers; ++k) factors.push_back(f *= s.growth);
    } else {  // equally spaced interior points: bisection (1 worker), trisection (2), ...
      for (int k = 1; k <= workers; ++k) factors.push_back(r.lower + (*upper - r.lower) * k / (workers + 1));
    }
    const std::vector<TrialOutcome> outcomes = evaluate(factors);
    if (outcomes.size() != factors.size()) throw Error("factor of safety search: the evaluator returned the wrong count");
    ++r.rounds;
    const int first = static_cast<int>(r.trials.size());
    r.trials.insert(r.trials.end(), outcomes.begin(), outcomes.end());
    // The smallest failing factor bounds from above; the largest stable one below it from below.
    // A stable trial above a failing one (not monotone: a numerical accident) is ignored.
    for (std::size_t k = 0; k < outcomes.size(); ++k)
      if (outcomes[k].failed && (!upper || outcomes[k].factor < *upper)) {
        upper = outcomes[k].factor;
        r.upper_trial = first + static_cast<int>(k);
      }
    for (const auto& o : outcomes)
      if (!o.failed && o.factor > r.lower && (!upper || o.factor < *upper)) r.lower = o.factor;
  }
  r.upper = *upper;
  r.factor = 0.5 * (r.lower + r.upper);
  return r;
}

// ---- The MPM trials -------------------------------------------------------------------------

namespace {

using Clock = std::chrono::steady_clock;

double moving_mass(const Simulation& sim) {
  double mass = 0;
  for (std::size_t p = 0; p < sim.particles.moving_count; ++p) mass += sim.particles.m[p];
  return mass;
}

long index_of(const Simulation& sim, int32_t id) {
  const auto& ids = sim.particles.id;
  const auto found = std::find(ids.begin(), ids.end(), id);
  if (found == ids.end()) throw Error("strength reduction: no monitoring particle " + std::to_string(id));
  return found - ids.begin();
}

// The verdict of the header's criteria, checked every check_interval steps. Times in seconds,
// from the simulation's time when it was made.
class TrialVerdict : public Observer {
 public:
  TrialVerdict(const Simulation& sim, const ReductionProblem& problem, double min_time, double budget, double window)
      : s_(problem.settings), min_time_(min_time), budget_(budget), window_(window), monitor_id_(problem.monitor) {
    const double g = sim.config.gravity.norm();
    energy_scale_ = moving_mass(sim) * g * problem.height;
    speed_scale_ = std::sqrt(g * problem.height);
    limit_ = s_.displacement_limit * problem.height;
    x_ref_ = x_last_ = monitor_position(sim);
    t0_ = t_last_ = sim.time;
    steps0_ = sim.steps;
  }

  bool wants_energies(const Simulation& sim) const override { return (sim.steps - steps0_) % s_.check_interval == 0; }

  Verdict after_step(Simulation& sim, const StepEvent& event) override {
    if (!event.energies_due) return Verdict::go_on();
    const Vec2 x = monitor_position(sim);
    const double t = sim.time;
    outcome.monitor_displacement = (x - x_ref_).norm();
    outcome.kinetic_ratio = event.energies().grid_kinetic / energy_scale_;
    const double rate = (x - x_last_).norm() / (t - t_last_) / speed_scale_;
    x_last_ = x;
    t_last_ = t;
    if (!std::isfinite(outcome.kinetic_ratio)) return Verdict::fail("blow-up");
    if (outcome.monitor_displacement > limit_) return Verdict::fail("displacement limit");
    const bool quiet = outcome.kinetic_ratio < s_.kinetic_tolerance && rate < s_.rate_tolerance;
    if (!quiet || t - t0_ < min_time_) quiet_since_ = -1;
    else if (quiet_since_ < 0) quiet_since_ = t;
    if (quiet_since_ >= 0 && t - quiet_since_ >= window_) return Verdict::stop("equilibrium");
    if (t - t0_ >= budget_) return Verdict::fail("step budget");
    return Verdict::go_on();
  }

  TrialOutcome outcome;
  double t0() const { return t0_; }
  long steps0() const { return steps0_; }

 private:
  // The monitoring particle's position; its index is looked up again after a re-ordering.
  Vec2 monitor_position(const Simulation& sim) {
    if (monitor_reorders_ != sim.reorders) {
      monitor_ = index_of(sim, monitor_id_);
      monitor_reorders_ = sim.reorders;
    }
    return sim.particles.x[monitor_];
  }

  const ReductionSettings& s_;
  double min_time_, budget_, window_;
  int32_t monitor_id_;
  long monitor_ = 0, monitor_reorders_ = -1;
  double energy_scale_ = 0, speed_scale_ = 0, limit_ = 0;
  Vec2 x_ref_, x_last_;
  double t0_ = 0, t_last_ = 0, quiet_since_ = -1;
  long steps0_ = 0;
};

// Stops the run after the step in which ReductionProblem::stop became non-zero.
class StopWhenAsked : public Observer {
 public:
  explicit StopWhenAsked(const std::atomic<int>* stop) : stop_(stop) {}
  Verdict after_step(Simulation&, const StepEvent&) override {
    return stop_ && stop_->load() != 0 ? Verdict::stop("stopped") : Verdict::go_on();
  }

 private:
  const std::atomic<int>* stop_;
};

// Runs sim until the verdict, through the one time loop with the particle sorter and the
// blow-up budget of every run. Throws TrialsStopped when problem.stop asked it to stop.
TrialOutcome run_to_verdict(Simulation& sim, const ReductionProblem& problem, double min_time, double budget,
                            double window) {
  const auto start = Clock::now();
  ParticleSorter sorter;
  BlowUpBudget blow_up = BlowUpBudget::starting_from(sim, energies(sim));
  TrialVerdict verdict(sim, problem, min_time, budget, window);
  StopWhenAsked stop(problem.stop);
  const LoopEnd end = run_time_loop(sim, problem.settings.cfl, kNever, {&sorter, &blow_up, &verdict, &stop});
  if (end.by == &stop) throw TrialsStopped{};
  TrialOutcome out = verdict.outcome;
  out.failed = end.kind != LoopEnd::Stopped;
  out.reason = end.kind == LoopEnd::Stopped || end.kind == LoopEnd::Failed ? end.reason : "blow-up";
  if (end.kind == LoopEnd::Failed && end.by == &blow_up) out.reason = "blow-up";
  out.steps = sim.steps - verdict.steps0();
  out.simulated_time = sim.time - verdict.t0();
  out.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return out;
}

std::vector<Vec2> positions_in_model_order(const Simulation& sim) {
  std::vector<Vec2> x(sim.particles.size());
  for (std::size_t p = 0; p < sim.particles.size(); ++p) x[sim.particles.id[p]] = sim.particles.x[p];
  return x;
}

}  // namespace

double elastic_period(const ReductionProblem& problem) {
  double c_s = 0;
  for (const auto& m : problem.model->materials) {
    const double shear_modulus = m.youngs_modulus / (2 * (1 + m.poisson_ratio));
    c_s = std::max(c_s, std::sqrt(shear_modulus / m.density));
  }
  return 4 * problem.height / c_s;
}

void reduce_strength(Simulation& sim, const Model& model, double factor) {
  for (std::size_t i = 0; i < model.materials.size(); ++i)
    if (has_strength(model.materials[i])) solver::reduce_strength(sim.config.materials[i], factor);
  prepare_particle_materials(sim.config.materials, sim.config.material_of_body, sim.particles);
}

EquilibriumState bring_to_equilibrium(const ReductionProblem& problem, int threads, std::ostream* log) {
  const ReductionSettings& s = problem.settings;
  const double period = elastic_period(problem);
  EquilibriumState state;
  for (double factor : kEquilibriumFactors) {
    Simulation sim = make_simulation(*problem.model, threads);
    sim.config.damping = s.damping;
    sim.config.gravity_ramp = s.ramp * period;
    if (problem.pseudo_static != Vec2::Zero()) sim.config.gravity += problem.pseudo_static;
    reduce_strength(sim, *problem.model, factor);
    EquilibriumAttempt attempt{factor, run_to_verdict(sim, problem, (s.ramp + s.min_time) * period,
                                                      (s.ramp + s.budget) * period, s.window * period)};
    attempt.outcome.factor = factor;
    if (log)
      *log << "equilibrium at F = " << factor << ": " << attempt.outcome.reason << " after "
           << attempt.outcome.simulated_time << " s (" << attempt.outcome.steps << " steps, "
           << attempt.outcome.seconds << " s wall)" << std::endl;
    state.attempts.push_back(std::move(attempt));
    if (!state.attempts.back().outcome.failed) {
      state.sim = std::move(sim);
      state.factor = factor;
      state.fails_as_built = factor < 1;
      if (state.attempts.size() > 1) state.failed_factor = state.attempts[state.attempts.size() - 2].factor;
      return state;
    }
  }
  throw Error("strength reduction: the slope reaches no equilibrium even with its strength raised 8 times");
}

TrialOutcome run_trial(const ReductionProblem& problem, const EquilibriumState& equilibrium, double factor) {
  const ReductionSettings& s = problem.settings;
  const double period = elastic_period(problem);
  Simulation sim = equilibrium.sim;
  set_threads(sim, 1);  // one core per trial: the trials are the parallelism
  reduce_strength(sim, *problem.model, factor);
  TrialOutcome out = run_to_verdict(sim, problem, s.min_time * period, s.budget * period, s.window * period);
  out.factor = factor;
  if (out.failed) out.position = positions_in_model_order(sim);
  return out;
}

std::vector<TrialOutcome> run_trials(const ReductionProblem& problem, const EquilibriumState& equilibrium,
                                     const std::vector<double>& factors, int workers,
                                     const std::function<void(const TrialOutcome&)>& progress) {
  std::vector<TrialOutcome> outcomes(factors.size());
  std::atomic<std::size_t> next{0};
  std::mutex lock;
  std::exception_ptr error;
  auto work = [&] {
    for (std::size_t k; (k = next++) < factors.size();) {
      try {
        outcomes[k] = run_trial(problem, equilibrium, factors[k]);
      } catch (...) {
        std::lock_guard<std::mutex> guard(lock);
        if (!error) error = std::current_exception();
        continue;
      }
      std::lock_guard<std::mutex> guard(lock);
      if (progress) progress(outcomes[k]);
    }
  };
  std::vector<std::thread> threads;
  const int count = std::max(1, std::min<int>(workers, static_cast<int>(factors.size())));
  for (int t = 0; t < count; ++t) threads.emplace_back(work);
  for (auto& t : threads) t.join();
  if (error) std::rethrow_exception(error);
  return outcomes;
}

}  // namespace talus::solver
