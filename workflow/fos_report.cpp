#include "workflow/fos_report.hpp"

#include <cmath>

#include "postproc/bishop_json.hpp"
#include "postproc/seismic_json.hpp"
#include "postproc/output.hpp"
#include "postproc/slope_geometry.hpp"

namespace talus::workflow {
namespace {

using Vec2 = Eigen::Vector2d;

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

}  // namespace

std::string fos_json(const FosReport& r) {
  const solver::ReductionSettings& s = r.problem.settings;
  const double height = r.problem.height;
  postproc::JsonWriter json;
  json.begin_object();
  json.key("scene").value(r.scene.name);
  json.key("factor_of_safety").value(r.search.factor);
  json.key("bracket").begin_object().key("lower").value(r.search.lower).key("upper").value(r.search.upper).end_object();
  json.key("fails_as_built").value(r.equilibrium.fails_as_built);
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
  const Vec2& monitor = r.model.position[r.problem.monitor];
  json.key("monitoring_point").begin_object()
      .key("particle").value(static_cast<long>(r.problem.monitor))
      .key("x_m").value(monitor.x()).key("y_m").value(monitor.y()).end_object();
  json.key("slope_height_m").value(height);
  json.key("particles").value(static_cast<long>(r.model.particle_count()));
  json.key("elements").value(static_cast<long>(r.model.triangles.size()));
  json.key("element_size_m").value(r.scene.mesh.size ? *r.scene.mesh.size : std::nan(""));
  json.key("workers").value(static_cast<long>(r.workers));
  json.key("equilibrium_runtime_s").value(r.equilibrium_seconds);
  json.key("search_runtime_s").value(r.search_seconds);
  json.key("equilibrium").begin_array();
  for (const auto& attempt : r.equilibrium.attempts) {
    json.begin_object();
    outcome_json(json, attempt.outcome);
    json.end_object();
  }
  json.end_array();
  json.key("rounds").value(static_cast<long>(r.search.rounds));
  json.key("trials").begin_array();
  for (const auto& trial : r.search.trials) {
    json.begin_object();
    outcome_json(json, trial);
    json.end_object();
  }
  json.end_array();
  if (r.slip) {
    json.key("failing_factor").value(r.search.upper);
    json.key("sliding_threshold_m").value(r.slip->threshold);
    json.key("failed_area_m2").value(r.slip->surface.failed_area);
    json.key("slip_surface").value(r.slip->surface.surface);
    json.key("slip_circle").value(r.slip->surface.circle);
  } else {
    json.key("slip_surface").null();
    json.key("slip_circle").null();
  }
  postproc::write_bishop_keys(json, r.bishop);
  postproc::write_water_keys(json, r.model.water);
  if (r.k_y) postproc::write_seismic_keys(json, r.model, *r.k_y);
  if (!r.model.loads.empty()) json.key("bishop_surcharge_N_m").value(r.surcharge);
  json.key("bodies").begin_array();
  for (int b : r.bodies) json.value(r.model.bodies[b].name);
  json.end_array();
  json.key("body_outline").value(postproc::outer_loop(r.model.bodies[r.bodies.front()].loops));
  json.key("body_outlines").begin_array();
  for (int b : r.bodies) json.value(postproc::outer_loop(r.model.bodies[b].loops));
  json.end_array();
  json.end_object();
  return json.text();
}

}  // namespace talus::workflow
