// `talus fos SCENE`: the scene is meshed in memory, brought to equilibrium, and its factor of
// safety bracketed by strength-reduction trials run side by side (solver/strength_reduction.hpp);
// the slip surface of the smallest failing trial comes from the postproc's extraction, beside
// Bishop's critical circle. Method and criteria: docs/fos.md.
#include "app/fos.hpp"

#include <omp.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <sys/wait.h>

#include "common/error.hpp"
#include "common/model.hpp"
#include "common/scene.hpp"
#include "postproc/bishop.hpp"
#include "postproc/bishop_json.hpp"
#include "postproc/circle_fit.hpp"
#include "postproc/failure_surface.hpp"
#include "postproc/output.hpp"
#include "postproc/postproc.hpp"
#include "postproc/runout.hpp"
#include "postproc/slope_geometry.hpp"
#include "preproc/preproc.hpp"
#include "solver/strength_reduction.hpp"

namespace fs = std::filesystem;

namespace talus {
namespace {

using Clock = std::chrono::steady_clock;
using Vec2 = Eigen::Vector2d;

double tolerance_of(const cli::Arguments& args) {
  if (!args.flags.empty()) throw Error("fos: unknown option '" + args.flags.front() + "' (see talus --help)");
  return args.tolerance.value_or(0.01);
}

std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The slope as the postproc sees it: the analysed body, its profile in the canonical frame.
struct Slope {
  int body = 0;
  postproc::Mirror mirror;
  postproc::SlopeProfile profile;  // canonical frame
  std::vector<int32_t> particles;  // model order
};

Slope slope_of(const Scene& scene, const Model& model) {
  Slope s;
  if (!scene.post.body.empty()) {
    s.body = scene.body_index(scene.post.body);
    if (s.body < 0) throw Error(located(scene.path, "post.body", "no body named '" + scene.post.body + "'"));
  }
  const postproc::Polyline& loop = postproc::outer_loop(model.bodies[s.body].loops);
  s.mirror.active = postproc::descends_to_left(loop);
  postproc::Polyline canonical;
  for (const auto& p : loop) canonical.push_back(s.mirror.point(p));
  s.profile = postproc::slope_profile(canonical);
  if (!(s.profile.height > 0))
    throw Error(located(scene.path, "bodies." + model.bodies[s.body].name, "fos needs a slope, but the ground surface is flat"));
  for (std::size_t p = 0; p < model.particle_count(); ++p)
    if (model.body[p] == s.body) s.particles.push_back(static_cast<int32_t>(p));
  return s;
}

// The monitoring point: the body's particle nearest the middle of the slope face.
int32_t monitoring_particle(const Slope& s, const Model& model) {
  const double x = 0.5 * (s.profile.crest.x() + s.profile.toe.x());
  const Vec2 target(x, postproc::surface_height(s.profile.surface, x));
  int32_t best = s.particles.front();
  for (int32_t p : s.particles)
    if ((s.mirror.point(model.position[p]) - target).norm() < (s.mirror.point(model.position[best]) - target).norm())
      best = p;
  return best;
}

std::vector<Vec2> equilibrium_positions(const solver::Simulation& sim) {
  std::vector<Vec2> x(sim.particles.size());
  for (std::size_t p = 0; p < sim.particles.size(); ++p) x[sim.particles.id[p]] = sim.particles.x[p];
  return x;
}

struct SlipSurface {
  postproc::Polyline line;  // scene coordinates
  std::optional<postproc::Circle> circle;
  double threshold = 0, failed_area = 0;
  std::vector<double> displacement;  // per body particle, of the failing trial
};

// The postproc's extraction on the displacements of the failing trial from equilibrium, drawn
// in the initial configuration. Threshold: half the smaller of the displacement limit and the
// monitoring point's displacement (a trial failed by its step budget may have moved less).
SlipSurface slip_surface_of(const Slope& s, const Model& model, const std::vector<Vec2>& x_eq,
                            const solver::TrialOutcome& failing, double limit) {
  SlipSurface out;
  out.threshold = 0.5 * std::min(limit, failing.monitor_displacement);
  std::vector<Vec2> x0, from, to;
  std::vector<double> volume;
  for (int32_t p : s.particles) {
    x0.push_back(s.mirror.point(model.position[p]));
    from.push_back(s.mirror.point(x_eq[p]));
    to.push_back(s.mirror.point(failing.position[p]));
    volume.push_back(model.volume[p]);
    out.displacement.push_back((failing.position[p] - x_eq[p]).norm());
  }
  const auto sliding = postproc::sliding_mask(from, to, out.threshold);
  out.failed_area = postproc::failed_area(sliding, volume);
  const postproc::Polyline line = postproc::slip_surface(x0, sliding, postproc::column_rule_for(volume).width);
  out.circle = postproc::fit_circle(line);
  if (out.circle) out.circle->centre = s.mirror.point(out.circle->centre);
  out.line = s.mirror.polyline(line);
  return out;
}

void outcome_json(postproc::JsonWriter& json, const solver::TrialOutcome& o) {
  json.key("factor").value(o.factor)
      .key("failed").value(o.failed)
      .key("outcome").value(o.reason)
      .key("steps").value(o.steps)
      .key("simulated_time_s").value(o.simulated_time)
      .key("runtime_s").value(o.seconds)
      .key("monitor_displacement_m").value(o.monitor_displacement)
      .key("kinetic_energy_ratio").value(o.kinetic_ratio);
}

struct Report {
  const Scene* scene;
  const Model* model;
  const Slope* slope;
  const solver::ReductionProblem* problem;
  const solver::EquilibriumState* equilibrium;
  const solver::SearchResult* search;
  const std::optional<postproc::BishopResult>* bishop;
  const SlipSurface* slip;  // may be null
  double tolerance, period, search_seconds, equilibrium_seconds;
  int workers;
};

std::string fos_json(const Report& r) {
  const solver::ReductionSettings& s = r.problem->settings;
  const double height = r.problem->height;
  postproc::JsonWriter json;
  json.begin_object();
  json.key("scene").value(r.scene->name);
  json.key("factor_of_safety").value(r.search->factor);
  json.key("bracket").begin_object().key("lower").value(r.search->lower).key("upper").value(r.search->upper).end_object();
  json.key("fails_as_built").value(r.equilibrium->fails_as_built);
  json.key("tolerance").value(r.tolerance);
  json.key("strength_reduction").value("c_F = c/F, tan(phi_F) = tan(phi)/F, tan(psi_F) = tan(psi)/F, t_F = t/F");
  json.key("criterion").begin_object()
      .key("equilibrium").value("E_k/(M g H) < kinetic_energy_ratio and |v_monitor|/sqrt(g H) < displacement_rate_ratio, "
                                "held for window_s after min_time_s")
      .key("failure").value("monitoring-point displacement from equilibrium > displacement_limit_m, or no equilibrium "
                            "within budget_s, or a numerical blow-up")
      .end_object();
  json.key("tolerances").begin_object()
      .key("kinetic_energy_ratio").value(s.kinetic_tolerance)
      .key("displacement_rate_ratio").value(s.rate_tolerance)
      .key("displacement_limit_m").value(s.displacement_limit * height)
      .key("min_time_s").value(s.min_time * r.period)
      .key("window_s").value(s.window * r.period)
      .key("budget_s").value(s.budget * r.period)
      .key("elastic_period_s").value(r.period)
      .key("damping").value(s.damping)
      .key("cfl").value(s.cfl)
      .end_object();
  const Vec2& monitor = r.model->position[r.problem->monitor];
  json.key("monitoring_point").begin_object()
      .key("particle").value(static_cast<long>(r.problem->monitor))
      .key("x_m").value(monitor.x()).key("y_m").value(monitor.y()).end_object();
  json.key("slope_height_m").value(height);
  json.key("particles").value(static_cast<long>(r.model->particle_count()));
  json.key("elements").value(static_cast<long>(r.model->triangles.size()));
  json.key("element_size_m").value(r.scene->mesh.size ? *r.scene->mesh.size : std::nan(""));
  json.key("workers").value(static_cast<long>(r.workers));
  json.key("equilibrium_runtime_s").value(r.equilibrium_seconds);
  json.key("search_runtime_s").value(r.search_seconds);
  json.key("equilibrium").begin_array();
  for (const auto& attempt : r.equilibrium->attempts) {
    json.begin_object();
    outcome_json(json, attempt.outcome);
    json.end_object();
  }
  json.end_array();
  json.key("rounds").value(static_cast<long>(r.search->rounds));
  json.key("trials").begin_array();
  for (const auto& trial : r.search->trials) {
    json.begin_object();
    outcome_json(json, trial);
    json.end_object();
  }
  json.end_array();
  if (r.slip) {
    json.key("failing_factor").value(r.search->upper);
    json.key("sliding_threshold_m").value(r.slip->threshold);
    json.key("failed_area_m2").value(r.slip->failed_area);
    json.key("slip_surface").value(r.slip->line);
    json.key("slip_circle").value(r.slip->circle);
  } else {
    json.key("slip_surface").null();
    json.key("slip_circle").null();
  }
  postproc::write_bishop_keys(json, *r.bishop);
  json.key("body_outline").value(postproc::outer_loop(r.model->bodies[r.slope->body].loops));
  json.end_object();
  return json.text();
}

// Runs postproc/fos_figure.py; its lines go to `log`. Returns false when it failed.
bool draw_figure(const std::string& out_dir, std::ostream& log) {
  const std::string figures = postproc::figures_script();
  const std::string script = figures.empty() ? "" : (fs::path(figures).parent_path() / "fos_figure.py").string();
  if (script.empty() || !fs::exists(script)) {
    log << "figure skipped: fos_figure.py not found\n";
    return false;
  }
  const std::string command = "/usr/bin/python3 " + quoted(script) + " --out " + quoted(out_dir) + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return false;
  std::array<char, 4096> line;
  while (std::fgets(line.data(), line.size(), pipe)) log << "  " << line.data();
  const int status = pclose(pipe);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

}  // namespace

int run_fos(const cli::Arguments& args) {
  if (args.positional.size() != 1) throw Error("fos: expected one scene file (see talus --help)");
  const double tolerance = tolerance_of(args);
  std::ostringstream discarded;
  std::ostream& log = args.quiet ? static_cast<std::ostream&>(discarded) : std::cout;

  const Scene scene = load_scene(args.positional.front(), args.overrides);
  const fs::path out = args.out ? fs::path(*args.out) : fs::path("out") / scene.name;
  fs::create_directories(out);
  const Model model = preproc::build_model(scene);
  const Slope slope = slope_of(scene, model);
  const Material& material = model.materials[model.bodies[slope.body].material];
  if (material.model != MaterialModel::MohrCoulomb)
    throw Error(located(scene.path, "materials." + material.name, "fos needs a Mohr-Coulomb material"));

  std::optional<postproc::BishopResult> bishop = postproc::bishop_search(
      slope.profile, {material.cohesion, material.friction_angle, material.density * scene.run.gravity.norm()});
  if (bishop) bishop = postproc::mirrored(*bishop, slope.mirror);

  solver::ReductionProblem problem;
  problem.model = &model;
  problem.height = slope.profile.height;
  problem.monitor = monitoring_particle(slope, model);
  problem.settings.cfl = scene.run.cfl;
  const double period = solver::elastic_period(problem);
  const int threads = args.threads > 0 ? args.threads : omp_get_max_threads();
  log << "talus fos: " << scene.name << ", " << model.particle_count() << " particles, " << model.triangles.size()
      << " elements, H = " << problem.height << " m, T0 = " << std::setprecision(3) << period << " s; "
      << "Bishop F = " << (bishop ? std::to_string(bishop->factor_of_safety) : "n/a") << std::endl;

  const auto equilibrium_start = Clock::now();
  const solver::EquilibriumState equilibrium = solver::bring_to_equilibrium(problem, threads, &log);
  const double equilibrium_seconds = std::chrono::duration<double>(Clock::now() - equilibrium_start).count();
  if (equilibrium.fails_as_built)
    log << "the slope fails as built (no equilibrium at F = 1): F < 1, searched with raised strength" << std::endl;

  solver::SearchSettings settings;
  settings.tolerance = tolerance;
  settings.stable_factor = equilibrium.factor;
  settings.failed_factor = equilibrium.failed_factor;
  settings.workers = threads;
  const auto search_start = Clock::now();
  int round = 0;
  const solver::SearchResult search = solver::search_factor_of_safety(
      [&](const std::vector<double>& factors) {
        ++round;
        return solver::run_trials(problem, equilibrium, factors, threads, [&](const solver::TrialOutcome& o) {
          log << "  round " << round << ": F = " << std::fixed << std::setprecision(4) << o.factor << "  "
              << (o.failed ? "FAILED" : "stable") << " (" << o.reason << "), d_monitor = " << std::setprecision(4)
              << o.monitor_displacement << " m, " << o.steps << " steps, " << std::setprecision(1) << o.seconds
              << " s" << std::defaultfloat << std::endl;
        });
      },
      settings);
  const double search_seconds = std::chrono::duration<double>(Clock::now() - search_start).count();

  std::optional<SlipSurface> slip;
  if (search.upper_trial >= 0)
    slip = slip_surface_of(slope, model, equilibrium_positions(equilibrium.sim), search.trials[search.upper_trial],
                           problem.settings.displacement_limit * problem.height);

  const Report report{&scene, &model, &slope, &problem, &equilibrium, &search, &bishop, slip ? &*slip : nullptr,
                      tolerance, period, search_seconds, equilibrium_seconds, threads};
  postproc::write_file_atomically((out / "fos.json").string(), fos_json(report));
  if (slip) {
    std::vector<double> x, y;
    for (int32_t p : slope.particles) x.push_back(model.position[p].x()), y.push_back(model.position[p].y());
    postproc::write_csv((out / "fos_particles.csv").string(), {"x0_m", "y0_m", "displacement_m"}, {x, y, slip->displacement});
  }

  log << std::fixed << std::setprecision(3) << "factor of safety F = " << search.factor << " (bracket "
      << search.lower << " .. " << search.upper << ", tolerance " << tolerance << ")"
      << (equilibrium.fails_as_built ? ": below 1, the slope fails as built" : "") << "\n"
      << "  Bishop (simplified, critical circle): " << (bishop ? std::to_string(bishop->factor_of_safety) : "n/a") << "\n"
      << "  " << search.trials.size() << " trials in " << search.rounds << " rounds on " << threads
      << " workers, search " << std::setprecision(1) << search_seconds << " s, equilibrium " << equilibrium_seconds
      << " s\n" << std::defaultfloat;
  log << "wrote " << (out / "fos.json").string() << std::endl;
  if (!slip) return 0;
  return draw_figure(out.string(), log) ? 0 : 1;
}

}  // namespace talus
