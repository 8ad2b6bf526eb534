// The factor-of-safety workflow. Method and criteria: docs/fos.md.
#include "workflow/fos.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "common/error.hpp"
#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "postproc/analysed_slope.hpp"
#include "postproc/figure_script.hpp"
#include "postproc/output.hpp"
#include "postproc/runout.hpp"
#include "postproc/seismic_json.hpp"
#include "workflow/folder_lock.hpp"
#include "preproc/preproc.hpp"
#include "solver/strength_reduction.hpp"
#include "workflow/fos_report.hpp"
#include "workflow/pipeline.hpp"

namespace fs = std::filesystem;

namespace talus::workflow {
namespace {

using Clock = std::chrono::steady_clock;
using Vec2 = Eigen::Vector2d;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The monitoring point: the body's particle nearest the middle of the slope face.
int32_t monitoring_particle(const postproc::AnalysedSlope& slope, const postproc::AnalysedBodies& body,
                            const Model& model) {
  const double x = 0.5 * (slope.profile.crest.x() + slope.profile.toe.x());
  const Vec2 target(x, postproc::surface_height(slope.profile.surface, x));
  const auto distance = [&](std::size_t p) { return (slope.mirror.point(model.position[p]) - target).norm(); };
  std::size_t best = body.particles.front();
  for (std::size_t p : body.particles)
    if (distance(p) < distance(best)) best = p;
  return static_cast<int32_t>(best);
}

std::vector<Vec2> equilibrium_positions(const solver::Simulation& sim) {
  std::vector<Vec2> x(sim.particles.size());
  for (std::size_t p = 0; p < sim.particles.size(); ++p) x[sim.particles.id[p]] = sim.particles.x[p];
  return x;
}

// The postproc's extraction on the displacements of the failing trial from equilibrium, drawn
// in the initial configuration. Threshold: half the smaller of the displacement limit and the
// monitoring point's displacement (a trial failed by its step budget may have moved less).
FosSlip slip_of(const postproc::AnalysedSlope& slope, const postproc::AnalysedBodies& body, const Model& model,
                const std::vector<Vec2>& x_eq, const solver::TrialOutcome& failing, double limit) {
  FosSlip out;
  out.threshold = 0.5 * std::min(limit, failing.monitor_displacement);
  std::vector<double> volume;
  for (std::size_t p : body.particles) {
    volume.push_back(model.volume[p]);
    out.displacement.push_back((failing.position[p] - x_eq[p]).norm());
  }
  out.surface = postproc::extract_slip_surface(
      postproc::canonical_positions(model.position, body.particles, slope.mirror),
      postproc::canonical_positions(x_eq, body.particles, slope.mirror),
      postproc::canonical_positions(failing.position, body.particles, slope.mirror), volume, out.threshold,
      postproc::column_rule_for(volume).width, slope.mirror);
  return out;
}

void print_trial(std::ostream& log, int round, const solver::TrialOutcome& o) {
  log << "  round " << round << ": F = " << std::fixed << std::setprecision(4) << o.factor << "  "
      << (o.failed ? "FAILED" : "stable") << " (" << o.reason << "), d_monitor = " << std::setprecision(4)
      << o.monitor_displacement << " m, " << o.steps << " steps, " << std::setprecision(1) << o.seconds << " s"
      << std::defaultfloat << std::endl;
}

void print_result(std::ostream& log, const FosReport& r) {
  log << std::fixed << std::setprecision(3) << "factor of safety F = " << r.search.factor << " (bracket "
      << r.search.lower << " .. " << r.search.upper << ", tolerance " << r.tolerance << ")"
      << (r.equilibrium.fails_as_built ? ": below 1, the slope fails as built" : "") << "\n"
      << "  Bishop (simplified, critical circle): "
      << (r.bishop ? std::to_string(r.bishop->factor_of_safety) : "n/a") << "\n"
      << "  " << r.search.trials.size() << " trials in " << r.search.rounds << " rounds on " << r.workers
      << " workers, search " << std::setprecision(1) << r.search_seconds << " s, equilibrium "
      << r.equilibrium_seconds << " s\n" << std::defaultfloat;
}

// The narrowest bracket the search can resolve: in its rounds, after the expansion from the
// lowest stable factor it may start from (1/8, a slope that fails as built) up to max_factor, one
// trial a round halving the bracket (max_factor (1 - 1/growth) wide at most); and in double
// precision, where the interior points of a bracket a few ulps of max_factor wide fall on its ends.
double narrowest_bracket(const solver::SearchSettings& s) {
  constexpr double kLowestStableFactor = 0.125;
  const double expansion = std::ceil(std::log(s.max_factor / kLowestStableFactor) / std::log(s.growth));
  const double widest = s.max_factor * (1 - 1 / s.growth);
  const double by_rounds = widest * std::pow(2.0, -(s.max_rounds - expansion));
  const double by_precision = 16 * s.max_factor * std::numeric_limits<double>::epsilon();
  return std::max(by_rounds, by_precision);
}

}  // namespace

void check_fos_tolerance(double tolerance, const std::string& option) {
  // Refused at once: before, --tolerance 1e-300 ran every trial of 100 rounds and then said
  // "no bracket within 100 rounds".
  if (const double narrowest = narrowest_bracket(solver::SearchSettings{}); tolerance < narrowest) {
    std::ostringstream message;
    message << option << ": got " << tolerance << ", below " << std::setprecision(3) << narrowest
            << ", the narrowest bracket the search can resolve (factors up to " << solver::SearchSettings{}.max_factor
            << " in double precision, in at most " << solver::SearchSettings{}.max_rounds << " rounds)";
    throw Error(message.str());
  }
}

void require_strength(const Model& model, const postproc::AnalysedBodies& body, const std::string& scene_path,
                      const std::string& who) {
  for (int index : body.indices) {
    const Material& material = model.materials[model.bodies[index].material];
    if (!has_strength(material))
      throw Error(located(scene_path, "materials." + material.name,
                          who + " a material with a strength (body '" +
                              model.bodies[index].name + "' is " + std::string(model_name(material)) + ")"));
  }
}

solver::ReductionProblem reduction_problem(const Model& model, const postproc::AnalysedSlope& slope,
                                           const postproc::AnalysedBodies& body) {
  solver::ReductionProblem problem;
  problem.model = &model;
  problem.height = slope.profile.height;
  problem.monitor = monitoring_particle(slope, body, model);
  problem.settings.cfl = model.run.cfl;
  problem.pseudo_static = solver::pseudo_static_force(model.seismic, model.run.gravity, slope.mirror.active);
  return problem;
}

FosSearch search_fos(const solver::ReductionProblem& problem, double tolerance, int workers, std::ostream* log,
                     const std::function<void(int, const solver::TrialOutcome&)>& on_trial) {
  FosSearch out;
  const auto equilibrium_start = Clock::now();
  out.equilibrium = solver::bring_to_equilibrium(problem, workers, log);
  out.equilibrium_seconds = seconds_since(equilibrium_start);
  if (out.equilibrium.fails_as_built && log)
    *log << "the slope fails as built (no equilibrium at F = 1): F < 1, searched with raised strength" << std::endl;

  solver::SearchSettings settings;
  settings.tolerance = tolerance;
  settings.stable_factor = out.equilibrium.factor;
  settings.failed_factor = out.equilibrium.failed_factor;
  settings.workers = workers;
  const auto search_start = Clock::now();
  int round = 0;
  out.search = solver::search_factor_of_safety(
      [&](const std::vector<double>& factors) {
        ++round;
        return solver::run_trials(problem, out.equilibrium, factors, workers, [&](const solver::TrialOutcome& o) {
          if (on_trial) on_trial(round, o);
        });
      },
      settings);
  out.search_seconds = seconds_since(search_start);
  return out;
}

int run_fos(const FosOptions& options, std::ostream& out_log) {
  std::ostringstream discarded;
  std::ostream& log = options.quiet ? static_cast<std::ostream&>(discarded) : out_log;
  const double tolerance = options.tolerance.value_or(solver::SearchSettings{}.tolerance);
  check_fos_tolerance(tolerance);

  const Scene scene = load_scene(options.scene_path, options.overrides);
  const fs::path out = output_folder(options.out, scene);
  const FolderLock lock(out.string());
  const Model model = preproc::build_model(scene);
  const postproc::Source source{scene.path, true, "fos needs"};
  const postproc::AnalysedBodies body = postproc::analysed_bodies(model, model.body, source);
  const postproc::AnalysedSlope slope = postproc::analysed_slope(model, body, source);
  require_strength(model, body, scene.path, "fos needs");

  const postproc::GroundLoads loads =
      postproc::ground_loads(body, model.position, particle_load_forces(model), model.volume);
  double surcharge = 0;
  for (const auto& f : loads.force) surcharge -= f.y();
  const std::optional<postproc::BishopResult> bishop = postproc::critical_circle(slope, model, body, loads, source);
  std::optional<postproc::YieldCoefficient> k_y;
  if (postproc::seismic_keys_due(model)) k_y = postproc::yield_coefficient(slope, model, body, loads);

  const solver::ReductionProblem problem = reduction_problem(model, slope, body);
  const double period = solver::elastic_period(problem);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  log << "talus fos: " << scene.name << ", " << model.particle_count() << " particles, " << model.triangles.size()
      << " elements, H = " << problem.height << " m, T0 = " << std::setprecision(3) << period << " s; "
      << "Bishop F = " << (bishop ? std::to_string(bishop->factor_of_safety) : "n/a") << std::endl;
  if (postproc::seismic_keys_due(model))
    log << "seismic: k_h = " << model.seismic.k_h << ", k_v = " << model.seismic.k_v
        << ", Bishop's yield coefficient k_y = " << (k_y ? std::to_string(k_y->k_y) : "n/a") << std::endl;

  const FosSearch found =
      search_fos(problem, tolerance, threads, &log, [&](int round, const solver::TrialOutcome& o) { print_trial(log, round, o); });
  const solver::EquilibriumState& equilibrium = found.equilibrium;
  const solver::SearchResult& search = found.search;
  const double equilibrium_seconds = found.equilibrium_seconds, search_seconds = found.search_seconds;

  std::optional<FosSlip> slip;
  if (search.upper_trial >= 0)
    slip = slip_of(slope, body, model, equilibrium_positions(equilibrium.sim), search.trials[search.upper_trial],
                   problem.settings.displacement_limit * problem.height);

  const FosReport report{scene,     model,  body.indices, problem,        equilibrium,         search, bishop,
                         surcharge, slip ? &*slip : nullptr, tolerance, period, search_seconds, equilibrium_seconds,
                         threads,    postproc::seismic_keys_due(model) ? &k_y : nullptr};
  postproc::write_file_atomically((out / "fos.json").string(), fos_json(report));
  if (slip) {
    std::vector<double> x, y;
    for (std::size_t p : body.particles) x.push_back(model.position[p].x()), y.push_back(model.position[p].y());
    postproc::write_csv((out / "fos_particles.csv").string(), {"x0_m", "y0_m", "displacement_m"},
                        {x, y, slip->displacement});
  }

  print_result(log, report);
  log << "wrote " << (out / "fos.json").string() << std::endl;
  if (!slip) return 0;
  postproc::run_figure_script(postproc::figure_script("fos_figure.py"), {"--out", out.string()}, log);
  return 0;
}

}  // namespace talus::workflow
