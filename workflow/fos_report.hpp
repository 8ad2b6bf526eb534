// fos.json: what a factor-of-safety run found, the criteria it used and every trial it ran
// (keys listed in docs/fos.md).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "postproc/bishop.hpp"
#include "postproc/failure_surface.hpp"
#include "postproc/pseudo_static.hpp"
#include "solver/strength_reduction.hpp"

namespace talus::workflow {

// The slip surface of the smallest failing trial.
struct FosSlip {
  postproc::SlipSurface surface;     // scene frame
  double threshold = 0;              // m, of the sliding mask
  std::vector<double> displacement;  // m, per particle of the analysed body, from equilibrium
};

struct FosReport {
  const Scene& scene;
  const Model& model;
  std::vector<int> bodies;  // the analysed bodies (post.bodies, else post.body), indices into model.bodies
  const solver::ReductionProblem& problem;
  const solver::EquilibriumState& equilibrium;
  const solver::SearchResult& search;
  const std::optional<postproc::BishopResult>& bishop;
  double surcharge;  // N/m, the loads' total downward force on the analysed bodies (Bishop's)
  const FosSlip* slip;  // null when no trial failed (the failing bound was known beforehand)
  double tolerance, period, search_seconds, equilibrium_seconds;
  int workers;
  // With [seismic] or [base_motion]: Bishop's yield coefficient (the seismic keys, seismic_json.hpp).
  const std::optional<postproc::YieldCoefficient>* k_y = nullptr;
};

std::string fos_json(const FosReport& report);

}  // namespace talus::workflow
