// One realisation of `talus ensemble` (docs/ensemble.md): the scene's random fields drawn from the
// realisation's seed (preproc/random_field/random_field.hpp) become per-particle properties of the
// model meshed once (Model::properties), the model is solved in memory on one thread with the
// observers of `talus solve` that decide when a run ends (sorting, the blow-up budget, rest, the
// step limit) and no frames written, and the final state is measured with the postproc's own
// functions (runout_metrics, extract_slip_surface, time_to_rest). One seed gives the same row
// whatever else runs beside it: the fields are the same on any thread, and the solve's one thread
// makes it bit for bit the same (docs/architecture.md, "Threads").
#pragma once
#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "postproc/analysed_slope.hpp"
#include "postproc/runout.hpp"
#include "preproc/random_field/random_field.hpp"
#include "solver/strength_reduction.hpp"
#include "workflow/ensemble_statistics.hpp"

namespace talus::workflow {

// A realisation fails when its sliding mass (particles of the analysed bodies displaced more than
// the sliding threshold, post.sliding_threshold x H, docs/postproc.md) holds at least this fraction
// of their area.
inline constexpr double kFailedAreaFraction = 0.01;

// What every realisation shares: the model meshed once, the fields' generators, and the slope
// the postproc analyses.
struct EnsembleModel {
  // Throws talus::Error (located at the scene) when the scene has no [random] table, its slope
  // cannot be analysed (no downhill face), or a field cannot be drawn on the model's grid.
  EnsembleModel(const Scene& scene, Model meshed);

  Scene scene;
  Model model;
  preproc::RandomFields fields;
  postproc::AnalysedBodies ground;
  postproc::AnalysedSlope slope;
  std::vector<Eigen::Vector2d> x0;  // the ground particles' initial positions, canonical frame
  std::vector<double> volume;       // their initial areas (m^2)
  postproc::ColumnRule rule;
  double sliding_threshold = 0;  // m
  double ground_area = 0;        // m^2, the analysed bodies' particle area
  double min_failed_area = 0;    // m^2, kFailedAreaFraction x ground_area

  // --fos: each realisation's factor of safety by strength reduction, `talus fos`'s search
  // (workflow/fos.hpp) with this bracket width. Throws talus::Error (located at the scene) when an
  // analysed body is not Mohr-Coulomb.
  void enable_fos(double tolerance);
  std::optional<solver::ReductionProblem> fos;  // the slope's problem (its model is set per realisation)
  double fos_tolerance = 0;
};

// The fields of realisation `seed` at every particle, one property per [random] table.
std::vector<ParticleProperty> realisation_properties(const EnsembleModel& ensemble, std::uint64_t seed);

// Wall time of one realisation's parts (s).
struct RealisationTiming {
  double fields = 0;  // drawing the fields and checking the particles' values
  double solve = 0;   // building the simulation and the time loop
  double post = 0;    // the runout, the slip surface and the time to rest
  double fos = 0;     // --fos: the equilibrium and the search
};

// Runs realisation `index` (seed `seed`) on `worker`, a copy of ensemble.model that the caller
// keeps for its realisations (only its properties are replaced). Returns nothing when `stop`
// became non-zero during the solve or the factor of safety's search (SIGINT, SIGTERM: the
// realisation is dropped, and a rerun runs it again). A solve that fails (blow-up, a particle out
// of the domain) gives a row with solved = false and the message; a search that finds no factor
// (no equilibrium even with the strength raised 8 times, no failure up to F = 50) a row without
// fos and its message. Throws talus::Error when the drawn values leave a particle's material
// invalid.
std::optional<RealisationRow> run_realisation(const EnsembleModel& ensemble, Model& worker, long index,
                                              std::uint64_t seed, const std::atomic<int>& stop,
                                              RealisationTiming* timing = nullptr);

}  // namespace talus::workflow
