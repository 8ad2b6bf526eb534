// `talus fos SCENE`: factor of safety by shear strength reduction with MPM (docs/fos.md). The
// scene is meshed in memory, brought to equilibrium and its factor bracketed by trials run side
// by side (solver/strength_reduction.hpp); the slope, the slip surface of the smallest failing
// trial and Bishop's critical circle come from postproc (analysed_slope.hpp,
// failure_surface.hpp). Writes OUT/fos.json, OUT/fos_particles.csv and the figure OUT/fos.png.
#pragma once
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "postproc/analysed_slope.hpp"
#include "solver/strength_reduction.hpp"

namespace talus::workflow {

struct FosOptions {
  std::string scene_path;
  std::vector<std::string> overrides;  // KEY=VALUE on the scene (--set)
  std::optional<std::string> out;      // output folder (created); default out/<scene name>
  int threads = 0;                     // parallel trials, one core each; 0: all cores
  std::optional<double> tolerance;     // bracket width; default solver::SearchSettings's
  bool quiet = false;                  // nothing to `log`
};

// Returns the exit status: 0, or 1 when fos.json was written but the figure failed. Throws
// talus::Error on a scene it cannot analyse (no slope, not Mohr-Coulomb, no equilibrium).
int run_fos(const FosOptions& options, std::ostream& log);

// ---- The pieces of run_fos that `talus ensemble --fos` shares (docs/ensemble.md) ----------

// Throws talus::Error when `tolerance` is narrower than the search can resolve (`option` names
// the command-line option in the message).
void check_fos_tolerance(double tolerance, const std::string& option = "--tolerance");

// Throws talus::Error (located at the scene) when an analysed body is not Mohr-Coulomb.
void require_strength(const Model& model, const postproc::AnalysedBodies& body, const std::string& scene_path,
                      const std::string& who);

// The strength-reduction problem of `model`'s slope: its height, the monitoring point (the
// analysed bodies' particle nearest the middle of the slope face), the run's CFL and the scene's
// pseudo-static force. problem.model points at `model`.
solver::ReductionProblem reduction_problem(const Model& model, const postproc::AnalysedSlope& slope,
                                           const postproc::AnalysedBodies& body);

// The factor of safety of `problem` as `talus fos` finds it: equilibrium at F = 1 (raised when the
// slope fails as built), then the bracket search down to `tolerance` with `workers` trials a round
// (the equilibrium on `workers` OpenMP threads). `on_trial` (may be empty) is told of each trial
// with its round. Throws talus::Error when no equilibrium or no failure is found, and
// solver::TrialsStopped when problem.stop asked it to stop.
struct FosSearch {
  solver::EquilibriumState equilibrium;
  solver::SearchResult search;
  double equilibrium_seconds = 0, search_seconds = 0;
};
FosSearch search_fos(const solver::ReductionProblem& problem, double tolerance, int workers, std::ostream* log,
                     const std::function<void(int, const solver::TrialOutcome&)>& on_trial = {});

}  // namespace talus::workflow
