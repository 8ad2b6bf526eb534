#include "workflow/ensemble_realisation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.hpp"
#include "postproc/failure_surface.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/solve_observers.hpp"
#include "solver/step/time_loop.hpp"
#include "workflow/fos.hpp"

namespace talus::workflow {
namespace {

// The grid of the fields: over the mesh's bounding box, no coarser than the particle spacing nor a
// quarter of any field's correlation length (field_spacing).
preproc::FieldGrid field_grid(const Scene& scene, const Model& model) {
  if (scene.random.empty())
    throw Error(located(scene.path, "random",
                        "the scene has no [random.NAME] table: an ensemble needs at least one random field "
                        "(docs/scenes.md, [random.NAME])"));
  std::vector<double> volume = model.volume;
  std::nth_element(volume.begin(), volume.begin() + static_cast<long>(volume.size() / 2), volume.end());
  const double spacing = std::sqrt(volume[volume.size() / 2]);
  Eigen::Vector2d finest = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  for (const RandomField& field : scene.random)
    finest = finest.cwiseMin(preproc::field_spacing(spacing, field.correlation_length));
  Eigen::Vector2d lo = model.nodes.front(), hi = model.nodes.front();
  for (const auto& node : model.nodes) lo = lo.cwiseMin(node), hi = hi.cwiseMax(node);
  return preproc::grid_over(lo, hi, finest);
}

// The grid kinetic energy whenever it is computed (every history_interval steps and whenever an
// observer asks): the record that `talus solve` writes to /history and time_to_rest reads.
class EnergyTrace : public solver::Observer {
 public:
  explicit EnergyTrace(int interval) : interval_(std::max(1, interval)) {}
  bool wants_energies(const solver::Simulation& sim) const override { return sim.steps % interval_ == 0; }
  solver::Verdict after_step(solver::Simulation& sim, const solver::StepEvent& event) override {
    if (event.energies_due) record(sim.time, event.energies().grid_kinetic);
    return solver::Verdict::go_on();
  }
  void record(double t, double kinetic) { time.push_back(t), this->kinetic.push_back(kinetic); }
  std::vector<double> time, kinetic;

 private:
  int interval_;
};

// Stops the run after the step in which `stop` became non-zero.
class StopRequest : public solver::Observer {
 public:
  explicit StopRequest(const std::atomic<int>& stop) : stop_(stop) {}
  solver::Verdict after_step(solver::Simulation&, const solver::StepEvent&) override {
    return stop_.load() != 0 ? solver::Verdict::stop("interrupted") : solver::Verdict::go_on();
  }

 private:
  const std::atomic<int>& stop_;
};

std::string failure_message(const solver::LoopEnd& end, const solver::Simulation& sim) {
  std::ostringstream message;
  if (end.kind == solver::LoopEnd::StepFailed)
    message << "the step failed (a particle left the domain or a state became non-finite)";
  else
    message << end.reason;
  message << " at step " << sim.steps << ", t = " << sim.time << " s";
  return message.str();
}

}  // namespace

EnsembleModel::EnsembleModel(const Scene& scene_in, Model meshed)
    : scene(scene_in),
      model(std::move(meshed)),
      fields(scene, field_grid(scene, model)),
      ground(postproc::analysed_bodies(model, model.body, {scene.path, true, "an ensemble needs"})),
      slope(postproc::analysed_slope(model, ground, {scene.path, true, "an ensemble needs"})) {
  x0 = postproc::canonical_positions(model.position, ground.particles, slope.mirror);
  for (std::size_t p : ground.particles) volume.push_back(model.volume[p]), ground_area += model.volume[p];
  rule = postproc::column_rule_for(volume);
  sliding_threshold = model.post.sliding_threshold * slope.profile.height;
  min_failed_area = kFailedAreaFraction * ground_area;
}

void EnsembleModel::enable_fos(double tolerance) {
  require_strength(model, ground, scene.path, "--fos needs");
  fos = reduction_problem(model, slope, ground);
  fos_tolerance = tolerance;
}

std::vector<ParticleProperty> realisation_properties(const EnsembleModel& ensemble, std::uint64_t seed) {
  const std::vector<std::vector<double>> gaussian = ensemble.fields.gaussian(seed);
  std::vector<ParticleProperty> properties;
  for (std::size_t k = 0; k < ensemble.fields.size(); ++k) {
    const RandomField& field = ensemble.fields.field(k);
    properties.push_back({field.material, field.parameter,
                          ensemble.fields.values_at(k, gaussian[k], ensemble.model.position)});
  }
  return properties;
}

std::optional<RealisationRow> run_realisation(const EnsembleModel& ensemble, Model& worker, long index,
                                              std::uint64_t seed, const std::atomic<int>& stop,
                                              RealisationTiming* timing) {
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  RealisationTiming times;
  auto t = Clock::now();
  RealisationRow row;
  row.index = index;
  row.seed = seed;
  worker.properties = realisation_properties(ensemble, seed);
  for (const ParticleProperty& property : worker.properties) {
    const int material = ensemble.scene.material_index(property.material);
    double sum = 0;
    long count = 0;
    for (std::size_t p = 0; p < property.values.size(); ++p)
      if (worker.bodies[worker.body[p]].material == material) sum += property.values[p], ++count;
    row.field_means.push_back(count > 0 ? sum / static_cast<double>(count) : std::nan(""));
  }
  if (const auto problem = properties_problem(worker))
    throw Error(located(ensemble.scene.path, "random",
                        "realisation " + std::to_string(index) + " (seed " + std::to_string(seed) +
                            ") draws values that leave a particle's material invalid (" + problem->key +
                            "): " + problem->message));

  times.fields = since(t);

  // --fos: `talus fos`'s search on this realisation's fields, on this thread.
  if (ensemble.fos) {
    t = Clock::now();
    solver::ReductionProblem problem = *ensemble.fos;
    problem.model = &worker;
    problem.stop = &stop;
    try {
      row.fos = search_fos(problem, ensemble.fos_tolerance, 1, nullptr).search.factor;
    } catch (const solver::TrialsStopped&) {
      return std::nullopt;
    } catch (const Error& e) {
      row.message = std::string("fos: ") + e.what();
    }
    times.fos = since(t);
  }
  t = Clock::now();

  // The run as `talus solve` ends it, in memory, on one thread.
  const RunSettings& run = worker.run;
  solver::Simulation sim = solver::make_simulation(worker, 1);
  const solver::Energies initial = solver::energies(sim);
  solver::LoopState loop;
  solver::ParticleSorter sorter;
  solver::BlowUpBudget budget = solver::BlowUpBudget::starting_from(sim, initial);
  EnergyTrace trace(run.history_interval);
  trace.record(sim.time, initial.grid_kinetic);
  solver::RestDetector rest(loop, run.rest_ratio, run.rest_window);
  solver::StepLimit step_limit(run.max_steps);
  StopRequest stop_request(stop);
  const std::vector<solver::Observer*> observers{&sorter, &budget, &trace, &rest, &step_limit, &stop_request};
  const solver::LoopEnd end = solver::run_time_loop(sim, run.cfl, run.end_time, observers);
  if (end.by == &stop_request) return std::nullopt;
  row.steps = sim.steps;
  row.simulated_time = sim.time;
  times.solve = since(t);
  t = Clock::now();
  if (timing) *timing = times;
  if (end.kind == solver::LoopEnd::StepFailed || end.kind == solver::LoopEnd::Failed ||
      end.kind == solver::LoopEnd::BadTimeStep) {
    row.solved = false;
    row.message = failure_message(end, sim) + (row.message.empty() ? "" : "; " + row.message);
    return row;
  }

  // The postproc's measures of the final state (docs/postproc.md).
  std::vector<Eigen::Vector2d> x1_all(sim.particles.size());
  for (std::size_t p = 0; p < sim.particles.size(); ++p) x1_all[sim.particles.id[p]] = sim.particles.x[p];
  const auto x1 = postproc::canonical_positions(x1_all, ensemble.ground.particles, ensemble.slope.mirror);
  const postproc::Mirror& mirror = ensemble.slope.mirror;
  const postproc::RunoutMetrics runout =
      postproc::runout_metrics(ensemble.slope.profile, ensemble.x0, x1, ensemble.sliding_threshold, ensemble.rule);
  const postproc::SlipSurface slip = postproc::extract_slip_surface(
      ensemble.x0, ensemble.x0, x1, ensemble.volume, ensemble.sliding_threshold, ensemble.rule.width, mirror);
  row.failed_area = slip.failed_area;
  row.failed = slip.failed_area >= ensemble.min_failed_area;
  row.time_to_rest = postproc::time_to_rest(trace.time, trace.kinetic);
  if (row.failed) {
    row.runout = runout.runout_distance;
    row.crest_retreat = runout.crest_retreat;
    row.travel_angle = runout.travel_angle_deg;
    row.crown_x = mirror.x(runout.crown.x());
    row.tip_x = mirror.x(runout.deposit_found ? runout.tip.x() : ensemble.slope.profile.toe.x());
  } else {
    row.crown_x = row.tip_x = std::numeric_limits<double>::quiet_NaN();  // nothing reached
  }
  if (timing) timing->post = since(t);
  return row;
}

}  // namespace talus::workflow
