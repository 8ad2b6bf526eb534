// Factor of safety by shear strength reduction (SRM) with explicit MPM (docs/fos.md).
//
// For a trial factor F every Mohr-Coulomb material gets
//   c_F = c / F,  tan(phi_F) = tan(phi) / F,  tan(psi_F) = tan(psi) / F,  t_F = t / F
// (the dilation and the tension cut-off reduced like the friction, so psi_F <= phi_F always
// holds and F < 1 raises all three). The slope is first brought to equilibrium under a gravity
// ramp with Cundall local damping at F_eq = 1 (or, when it fails as built, at the first stable
// F_eq of 1/2, 1/4, 1/8: strength raised). Each trial copies that equilibrium state, reduces
// the strength to F and runs the damped explicit step until a verdict:
//   stable  the grid kinetic energy E_k / (M g H) < kinetic_tolerance and the monitoring
//           point's speed / sqrt(g H) < rate_tolerance, both held for `window` periods after
//           at least `min_time` periods;
//   failed  the monitoring point moved more than displacement_limit x H from its equilibrium
//           position, or no equilibrium within `budget` periods, or the run blew up.
// Times are in units of the slope's elastic period T0 = 4 H / c_s (shear wave, c_s =
// sqrt(G / rho) of the stiffest material), so one setting serves a 1 m model and a 100 m slope.
//
// The search is a pure function over a batch evaluator: it brackets F (expanding upwards from
// a known stable factor until a trial fails) and then shrinks the bracket by evaluating
// `workers` equally spaced interior points per round (bisection with one worker, trisection
// with two), until upper - lower <= tolerance.
#pragma once
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "solver/step/simulation.hpp"

namespace talus::solver {

struct TrialOutcome {
  double factor = 0;        // F of the trial
  bool failed = false;
  std::string reason;       // "equilibrium", "displacement limit", "step budget", "blow-up"
  long steps = 0;
  double simulated_time = 0;         // s, of this trial alone
  double seconds = 0;                // wall time
  double monitor_displacement = 0;   // m, from the equilibrium state
  double kinetic_ratio = 0;          // E_k / (M g H) at the verdict
  std::vector<Vec2> position;        // particle positions at the verdict, model order (failed trials)
};

// ---- The search (pure; tested with a mocked evaluator) -------------------------------------

struct SearchSettings {
  double tolerance = 0.01;             // stop when upper - lower <= tolerance
  double stable_factor = 1;            // a factor known to be stable (not evaluated again)
  std::optional<double> failed_factor; // a factor known to fail, if any
  int workers = 2;                     // trials per round
  double growth = 1.5;                 // bracket expansion: F_k = stable x growth^k
  double max_factor = 50;              // no failure up to here: an error
  int max_rounds = 100;
};

struct SearchResult {
  double factor = 0;                 // (lower + upper) / 2
  double lower = 0, upper = 0;       // largest stable, smallest failing factor
  std::vector<TrialOutcome> trials;  // in evaluation order
  int rounds = 0;
  int upper_trial = -1;              // index in trials of the smallest failing factor; -1: given
};

// Evaluates the trial factors of one round (any order of evaluation; results in input order).
using TrialBatch = std::function<std::vector<TrialOutcome>(const std::vector<double>&)>;

// Throws talus::Error when stable_factor >= failed_factor, or no failure up to max_factor.
SearchResult search_factor_of_safety(const TrialBatch& evaluate, const SearchSettings& settings);

// ---- The MPM trials ------------------------------------------------------------------------

struct ReductionSettings {
  double damping = 0.6;               // Cundall local damping during every phase
  double cfl = 0.5;
  double kinetic_tolerance = 1e-9;    // E_k / (M g H)
  double rate_tolerance = 1e-4;       // monitoring speed / sqrt(g H)
  double displacement_limit = 0.05;   // x H, monitoring point displacement that means failure
  double ramp = 3;                    // gravity ramp of the equilibrium phase, periods T0
  double min_time = 2;                // periods before a verdict of equilibrium
  double window = 1;                  // periods the tolerances must hold
  double budget = 25;                 // periods without equilibrium = failure
  int check_interval = 10;            // steps between checks
};

struct ReductionProblem {
  const Model* model = nullptr;
  double height = 0;            // slope height H (m)
  int32_t monitor = 0;          // monitoring particle, model order
  ReductionSettings settings;
  // [seismic]: the pseudo-static body force added to gravity from the start of the equilibrium
  // phase (ramped with it) and kept in every trial (m/s^2; pseudo_static_force).
  Vec2 pseudo_static{0, 0};
  // When given and non-zero after a step (a signal, `talus ensemble`), the equilibrium phase or the
  // trial stops after that step and throws TrialsStopped.
  const std::atomic<int>* stop = nullptr;
};

// Thrown by bring_to_equilibrium and run_trial(s) when ReductionProblem::stop asked them to stop.
struct TrialsStopped {};

// k_h |g| towards the toe (-x when the slope descends towards -x) and k_v |g| upwards, for gravity
// along -y; zero without [seismic].
inline Vec2 pseudo_static_force(const SeismicSettings& seismic, const Vec2& gravity, bool descends_to_left) {
  const double g = gravity.norm();
  return Vec2((descends_to_left ? -1.0 : 1.0) * seismic.k_h * g, seismic.k_v * g);
}

// Elastic period T0 = 4 H / c_s of the problem (s).
double elastic_period(const ReductionProblem& problem);

// Sets the strength of every material of sim that has one (has_strength) to the scene's reduced
// by F, its particles' own values alike.
void reduce_strength(Simulation& sim, const Model& model, double factor);

struct EquilibriumAttempt {
  double factor = 0;
  TrialOutcome outcome;
};

// The factors the equilibrium phase tries, in order, until one reaches equilibrium: the
// scene's strength first, then raised (F < 1) for a slope that fails as built.
inline constexpr double kEquilibriumFactors[] = {1.0, 0.5, 0.25, 0.125};

struct EquilibriumState {
  Simulation sim;
  double factor = 1;            // the F_eq it is in equilibrium at
  bool fails_as_built = false;  // F_eq = 1 did not reach equilibrium
  // The factor tried just before `factor`, which failed: an upper bound of the factor of
  // safety when the slope fails as built (empty otherwise).
  std::optional<double> failed_factor;
  std::vector<EquilibriumAttempt> attempts;
};

// Gravity ramp then damped run, at each of kEquilibriumFactors until one reaches equilibrium.
// Throws talus::Error when none does. `threads`: OpenMP threads of this phase.
EquilibriumState bring_to_equilibrium(const ReductionProblem& problem, int threads, std::ostream* log = nullptr);

// One trial from the equilibrium state (copied), on the calling thread's OpenMP settings.
TrialOutcome run_trial(const ReductionProblem& problem, const EquilibriumState& equilibrium, double factor);

// Runs the trials of a batch on separate std::threads (at most `workers` at once), each with
// one OpenMP thread. `progress` (may be empty) is called after each trial, under a lock.
std::vector<TrialOutcome> run_trials(const ReductionProblem& problem, const EquilibriumState& equilibrium,
                                     const std::vector<double>& factors, int workers,
                                     const std::function<void(const TrialOutcome&)>& progress = {});

}  // namespace talus::solver
