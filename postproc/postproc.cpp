#include "postproc/postproc.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <optional>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "common/scene/scene.hpp"
#include "postproc/analysed_slope.hpp"
#include "postproc/bishop.hpp"
#include "postproc/bishop_json.hpp"
#include "postproc/seismic_json.hpp"
#include "postproc/circle_fit.hpp"
#include "postproc/failure_surface.hpp"
#include "postproc/figure_script.hpp"
#include "postproc/newmark.hpp"
#include "postproc/output.hpp"
#include "postproc/results.hpp"
#include "postproc/runout.hpp"
#include "postproc/slope_geometry.hpp"
#include "postproc/validation.hpp"

namespace fs = std::filesystem;

namespace talus::postproc {
namespace {

const std::set<std::string> kMetrics = {"runout", "failure_surface", "bishop", "spring_mass", "box_incline",
                                        "newmark_block"};

bool wants(const PostSettings& post, const std::string& metric) {
  return std::find(post.metrics.begin(), post.metrics.end(), metric) != post.metrics.end();
}

// Centre of mass of the selected particles at the given positions.
Eigen::Vector2d centre_of_mass(const Results& results, const std::vector<std::size_t>& which,
                               const std::vector<Eigen::Vector2d>& x_p) {
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();
  double mass = 0;
  for (std::size_t p : which) moment += results.mass[p] * x_p[p], mass += results.mass[p];
  return moment / mass;
}

// Everything computed for one run, in the scene's own coordinates (mirrored back).
struct Metrics {
  std::optional<SlopeProfile> profile;  // canonical frame
  Mirror mirror;
  double sliding_threshold = 0, column_width = 0;

  std::optional<RunoutMetrics> runout;
  std::optional<double> time_to_rest;
  std::vector<double> front_x, front_velocity;

  bool failure_done = false;
  double failed_area = 0;
  Polyline failure_surface, shear_band;
  std::optional<Circle> slip_circle;
  double slip_circle_rms = 0;
  std::optional<double> onset_time;

  bool bishop_done = false;
  std::optional<BishopResult> bishop;
  std::vector<std::pair<std::string, SoilStrength>> layers;  // per analysed body
  double surcharge = 0;  // N/m, the loads' total downward force on the analysed bodies
  std::optional<YieldCoefficient> k_y;  // with [seismic] or [base_motion] (seismic_json.hpp)
  std::optional<ShakenSlope> shaken;    // with [base_motion] and a k_y

  std::optional<SpringMassCheck> spring;
  std::optional<BoxInclineCheck> box;
  double box_friction = 0;
  std::optional<NewmarkBlockCheck> newmark;  // with box_friction
};

// The shaken slope's crest against Newmark's estimate from k_y (seismic_json.hpp, ShakenSlope).
ShakenSlope shaken_slope(const Results& results, const AnalysedBodies& ground, const AnalysedSlope& slope, double k_y) {
  const BaseMotion& motion = results.metadata.base_motion;
  const double toward_toe = slope.mirror.active ? -1.0 : 1.0;
  const NewmarkBlock block{k_y * results.metadata.run.gravity.norm(), 1.0};
  ShakenSlope out;
  out.newmark_displacement =
      newmark_sliding([&](double t) { return -toward_toe * motion.ground_acceleration(t).x(); }, block, motion.start,
                      std::max(results.frame_time.back(), motion.start), 1e-4)
          .final_displacement();
  const Eigen::Vector2d crest = slope.mirror.point(slope.profile.crest);
  std::size_t nearest = ground.particles.front();
  for (std::size_t p : ground.particles)
    if ((results.initial_position[p] - crest).norm() < (results.initial_position[nearest] - crest).norm()) nearest = p;
  const Eigen::Vector2d moved = results.position.back()[nearest] - results.initial_position[nearest];
  out.crest_displacement_toe = toward_toe * moved.x();
  out.crest_displacement = moved.norm();
  return out;
}

void slope_metrics(const Results& results, const AnalysedBodies& ground, const std::string& file, Metrics& m) {
  const PostSettings& post = results.metadata.post;
  double motion_x = 0;  // which way a level-topped body (a column) ran out
  for (std::size_t p : ground.particles) motion_x += results.position.back()[p].x() - results.initial_position[p].x();
  const AnalysedSlope slope =
      analysed_slope(results.metadata, ground, {file}, motion_x / static_cast<double>(ground.particles.size()));
  m.mirror = slope.mirror;
  m.profile = slope.profile;
  const SlopeProfile& profile = *m.profile;
  m.sliding_threshold = post.sliding_threshold * profile.height;

  std::vector<double> volume;
  for (std::size_t p : ground.particles) volume.push_back(results.volume[p]);
  const ColumnRule rule = column_rule_for(volume);
  m.column_width = rule.width;
  const auto x0 = canonical_positions(results.initial_position, ground.particles, m.mirror);
  const auto x1 = canonical_positions(results.position.back(), ground.particles, m.mirror);

  if (wants(post, "runout")) {
    m.runout = runout_metrics(profile, x0, x1, m.sliding_threshold, rule);
    m.time_to_rest = time_to_rest(results.history_time, results.kinetic_energy);
    for (std::size_t f = 0; f < results.frames(); ++f) {
      std::vector<Eigen::Vector2d> v;
      for (std::size_t p : ground.particles) {
        const Eigen::Vector2d& velocity = results.velocity[f][p];
        v.emplace_back(m.mirror.x(velocity.x()), velocity.y());
      }
      const DepositFront front =
          deposit_front(canonical_positions(results.position[f], ground.particles, m.mirror), v, profile.surface, rule);
      m.front_x.push_back(m.mirror.x(front.found ? front.tip.x() : profile.toe.x()));
      m.front_velocity.push_back(front.found ? front.velocity : 0.0);
    }
  }

  if (wants(post, "failure_surface")) {
    m.failure_done = true;
    SlipSurface slip = extract_slip_surface(x0, x0, x1, volume, m.sliding_threshold, rule.width, m.mirror);
    m.failed_area = slip.failed_area;
    m.slip_circle = slip.circle;
    m.slip_circle_rms = slip.circle_rms;
    m.failure_surface = std::move(slip.surface);
    std::vector<std::vector<Eigen::Vector2d>> frames;
    for (const auto& frame : results.position) frames.push_back(canonical_positions(frame, ground.particles, m.mirror));
    const auto onset = onset_frame(frames, x0, m.sliding_threshold);
    if (onset) {
      m.onset_time = results.frame_time[*onset];
      if (!results.plastic_strain.empty()) {
        std::vector<double> strain;
        for (std::size_t p : ground.particles) strain.push_back(results.plastic_strain[*onset][p]);
        m.shear_band = m.mirror.polyline(shear_band(x0, strain, rule.width));
      }
    }
  }

  if (wants(post, "bishop")) {
    m.bishop_done = true;
    const GroundLoads loads = ground_loads(ground, results.initial_position, results.load_force, results.volume);
    m.bishop = critical_circle(slope, results.metadata, ground, loads, {file});
    if (seismic_keys_due(results.metadata)) m.k_y = yield_coefficient(slope, results.metadata, ground, loads);
    if (m.k_y && results.metadata.base_motion.enabled()) m.shaken = shaken_slope(results, ground, slope, m.k_y->k_y);
    const double gravity = results.metadata.run.gravity.norm();
    for (int index : ground.indices) {
      const BodyInfo& info = results.metadata.bodies[index];
      const Material& material = results.metadata.materials[info.material];
      const CohesionFriction strength = *limit_equilibrium_strength(material);  // critical_circle checked it
      m.layers.push_back({info.name, {strength.cohesion, strength.friction_angle, material.density * gravity}});
    }
    for (const auto& f : loads.force) m.surcharge -= f.y();
  }
}

// The box of box_incline and newmark_block: its friction against the other body (the scene's
// default without one) into m.box_friction, and its centre-of-mass displacement at each frame.
std::vector<Eigen::Vector2d> box_displacements(const Results& results, const AnalysedBody& body, Metrics& m) {
  const auto& bodies = results.metadata.bodies;
  const std::string& box = bodies[body.index].name;
  const auto other = std::find_if(bodies.begin(), bodies.end(), [&](const BodyInfo& b) { return b.name != box; });
  m.box_friction = other == bodies.end() ? results.metadata.contact.friction
                                         : pair_friction(results.metadata.contact, box, other->name);
  const Eigen::Vector2d start = centre_of_mass(results, body.particles, results.initial_position);
  std::vector<Eigen::Vector2d> displacement;
  for (const auto& frame : results.position) displacement.push_back(centre_of_mass(results, body.particles, frame) - start);
  return displacement;
}

void validation_metrics(const Results& results, const AnalysedBody& body, Metrics& m) {
  const PostSettings& post = results.metadata.post;
  if (wants(post, "spring_mass")) {
    std::vector<double> centre_y;
    for (const auto& frame : results.position) centre_y.push_back(centre_of_mass(results, body.particles, frame).y());
    const double initial_y = centre_of_mass(results, body.particles, results.initial_position).y();
    m.spring = spring_mass_check(results.frame_time, centre_y, initial_y, post.spring_amplitude, post.spring_omega);
  }
  // box_displacements sets m.box_friction: called first, then read.
  if (wants(post, "box_incline")) {
    const std::vector<Eigen::Vector2d> displacement = box_displacements(results, body, m);
    m.box = box_incline_check(results.frame_time, displacement, post.incline_angle, results.metadata.run.gravity,
                              m.box_friction, results.metadata.run.gravity_ramp);
  }
  // The shaken box against Newmark's block; results.h5 holds its positions in the ground's frame.
  if (wants(post, "newmark_block")) {
    const std::vector<Eigen::Vector2d> displacement = box_displacements(results, body, m);
    m.newmark = newmark_block_check(results.frame_time, displacement, post.incline_angle,
                                    results.metadata.run.gravity.norm(), m.box_friction, results.metadata.base_motion);
  }
}

void write_point(JsonWriter& json, const std::string& key, const Eigen::Vector2d& p) {
  json.key(key).begin_array().value(p.x()).value(p.y()).end_array();
}

std::string metrics_json(const Results& results, const AnalysedBody& body, const AnalysedBodies& ground,
                         const std::string& results_path, const Metrics& m) {
  JsonWriter json;
  json.begin_object();
  json.key("scene").value(results.metadata.scene_name);
  json.key("body").value(results.metadata.bodies[body.index].name);
  if (!results.metadata.post.bodies.empty()) {
    json.key("bodies").begin_array();
    for (int index : ground.indices) json.value(results.metadata.bodies[index].name);
    json.end_array();
  }
  json.key("results_file").value(results_path);
  json.key("frames").value(static_cast<long>(results.frames()));
  if (results.metadata.base_motion.enabled()) write_ground_motion_keys(json, results.metadata.base_motion, results.frame_time.back());
  json.key("end_time_s").value(results.frame_time.back());
  json.key("run_complete").value(results.complete);
  json.key("metrics").begin_array();
  for (const auto& metric : results.metadata.post.metrics) json.value(metric);
  json.end_array();

  if (m.profile) {
    json.key("slope_height_m").value(m.profile->height);
    write_point(json, "crest_m", m.mirror.point(m.profile->crest));
    write_point(json, "toe_m", m.mirror.point(m.profile->toe));
    json.key("sliding_threshold_m").value(m.sliding_threshold);
    json.key("column_width_m").value(m.column_width);
  }
  if (m.runout) {
    json.key("runout_distance_m").value(m.runout->runout_distance);
    json.key("final_height_m").value(m.runout->final_height);
    json.key("crest_retreat_m").value(m.runout->crest_retreat);
    json.key("travel_angle_deg").value(m.runout->travel_angle_deg);
    json.key("deposit_found").value(m.runout->deposit_found);
    write_point(json, "crown_m", m.mirror.point(m.runout->crown));
    write_point(json, "deposit_tip_m", m.mirror.point(m.runout->tip));
    json.key("time_to_rest_s").value(m.time_to_rest);
  }
  if (m.failure_done) {
    json.key("failed_area_m2").value(m.failed_area);
    json.key("onset_time_s").value(m.onset_time);
    json.key("slip_circle").value(m.slip_circle);
    json.key("slip_circle_rms_m").value(m.slip_circle ? std::optional<double>(m.slip_circle_rms) : std::nullopt);
    json.key("failure_surface").value(m.failure_surface);
    json.key("shear_band").value(m.shear_band);
  }
  if (m.bishop_done) {
    write_bishop_keys(json, m.bishop);
    const auto soil = [&json](const SoilStrength& s) {
      json.key("cohesion_Pa").value(s.cohesion)
          .key("friction_angle_deg").value(s.friction_angle)
          .key("unit_weight_N_m3").value(s.unit_weight);
    };
    if (m.layers.size() == 1) {
      json.key("bishop_soil").begin_object();
      soil(m.layers.front().second);
      json.end_object();
    } else {
      json.key("bishop_layers").begin_array();
      for (const auto& [name, strength] : m.layers) {
        json.begin_object().key("body").value(name);
        soil(strength);
        json.end_object();
      }
      json.end_array();
    }
    if (!results.load_force.empty()) json.key("bishop_surcharge_N_m").value(m.surcharge);
    write_water_keys(json, results.metadata.water);
    if (seismic_keys_due(results.metadata)) write_seismic_keys(json, results.metadata, m.k_y, m.shaken);
  }
  if (m.spring) {
    json.key("spring_mass").begin_object()
        .key("amplitude_m").value(results.metadata.post.spring_amplitude)
        .key("omega_rad_s").value(results.metadata.post.spring_omega)
        .key("max_error_over_amplitude").value(m.spring->max_error_over_amplitude)
        .end_object();
  }
  if (m.newmark) {
    json.key("newmark_block").begin_object()
        .key("friction").value(m.box_friction)
        .key("angle_deg").value(results.metadata.post.incline_angle)
        .key("critical_acceleration_m_s2").value(m.newmark->block.critical_acceleration)
        .key("mpm_displacement_m").value(m.newmark->mpm_final)
        .key("newmark_displacement_m").value(m.newmark->newmark_final)
        .key("relative_error").value(m.newmark->relative_error)
        .end_object();
  }
  if (m.box) {
    json.key("box_incline").begin_object();
    json.key("angle_deg").value(results.metadata.post.incline_angle);
    json.key("friction").value(m.box_friction);
    json.key("acceleration_m_s2").value(m.box->acceleration);
    json.key("max_displacement_m").value(m.box->max_abs_displacement);
    json.key("checks").begin_array();
    for (std::size_t i = 0; i < m.box->check_times.size(); ++i)
      json.begin_object()
          .key("time_s").value(m.box->check_times[i])
          .key("mpm_m").value(m.box->mpm_at_check[i])
          .key("exact_m").value(m.box->exact_at_check[i])
          .key("relative_error").value(m.box->relative_error[i])
          .end_object();
    json.end_array().end_object();
  }
  json.end_object();
  return json.text();
}

std::string format(std::optional<double> value, int precision, const std::string& unit) {
  if (!value) return "n/a";
  std::ostringstream out;
  out << std::fixed << std::setprecision(precision) << *value << unit;
  return out.str();
}

void print_summary(const Metrics& m, std::ostream& log) {
  if (m.profile)
    log << "  slope height " << format(m.profile->height, 2, " m") << ", sliding threshold "
        << format(m.sliding_threshold, 3, " m") << "\n";
  if (m.runout)
    log << "  runout " << format(m.runout->runout_distance, 2, " m") << ", crest retreat "
        << format(m.runout->crest_retreat, 2, " m") << ", travel angle " << format(m.runout->travel_angle_deg, 1, " deg")
        << ", time to rest " << format(m.time_to_rest, 2, " s") << "\n";
  if (m.failure_done) {
    log << "  failed area " << format(m.failed_area, 2, " m^2") << ", slip circle ";
    if (m.slip_circle)
      log << "centre (" << format(m.slip_circle->centre.x(), 2, "") << ", " << format(m.slip_circle->centre.y(), 2, "")
          << ") m, R " << format(m.slip_circle->radius, 2, " m") << "\n";
    else
      log << "n/a\n";
  }
  if (m.shaken)
    log << "  shaken slope: crest moved " << format(m.shaken->crest_displacement, 3, " m") << " ("
        << format(m.shaken->crest_displacement_toe, 3, " m") << " towards the toe); Newmark's estimate from k_y = "
        << format(m.k_y->k_y, 3, "") << ": " << format(m.shaken->newmark_displacement, 3, " m") << "\n";
  if (m.bishop_done) {
    log << "  Bishop critical circle: ";
    if (m.bishop)
      log << "F = " << format(m.bishop->factor_of_safety, 3, "") << ", centre (" << format(m.bishop->circle.centre.x(), 2, "")
          << ", " << format(m.bishop->circle.centre.y(), 2, "") << ") m, R " << format(m.bishop->circle.radius, 2, " m")
          << ", " << to_string(m.bishop->kind) << " circle, " << m.bishop->circles_evaluated << " circles evaluated\n";
    else
      log << "no admissible circle\n";
  }
  if (m.spring) log << "  spring and mass: max |y - y_exact| / A = " << format(m.spring->max_error_over_amplitude, 4, "") << "\n";
  if (m.newmark)
    log << "  Newmark's block (mu " << format(m.box_friction, 2, "") << ", a_c " << format(m.newmark->block.critical_acceleration, 4, " m/s^2")
        << "): permanent displacement " << format(m.newmark->mpm_final, 4, " m") << " against Newmark's "
        << format(m.newmark->newmark_final, 4, " m") << ", error " << format(m.newmark->relative_error, 4, "") << "\n";
  if (m.box) {
    log << "  box on incline (mu " << format(m.box_friction, 2, "") << "):";
    for (std::size_t i = 0; i < m.box->check_times.size(); ++i)
      log << " t=" << format(m.box->check_times[i], 2, "") << " s err " << format(m.box->relative_error[i], 4, "");
    log << "\n";
  }
}

}  // namespace

int run_post(const std::string& results_path, const std::string& out_dir, std::ostream& log,
             const PostOptions& options) {
  const Results results = read_results(results_path);
  const PostSettings& post = results.metadata.post;
  for (const auto& metric : post.metrics)
    if (!kMetrics.count(metric))
      throw Error(located(results_path, "settings/post/metrics",
                          "unknown metric '" + metric + "' (expected runout, failure_surface, bishop, spring_mass, box_incline or newmark_block)"));
  const AnalysedBody body = analysed_body(results.metadata, results.body, {results_path});
  const AnalysedBodies ground = analysed_bodies(results.metadata, results.body, {results_path});

  Metrics m;
  const bool slope = wants(post, "runout") || wants(post, "failure_surface") || wants(post, "bishop");
  if (slope) slope_metrics(results, ground, results_path, m);
  validation_metrics(results, body, m);

  fs::create_directories(out_dir);
  const fs::path out(out_dir);
  write_file_atomically((out / "metrics.json").string(), metrics_json(results, body, ground, results_path, m));
  write_csv((out / "energy.csv").string(), {"time_s", "kinetic_J", "potential_J", "strain_J"},
            {results.history_time, results.kinetic_energy, results.potential_energy, results.strain_energy});
  if (m.runout)
    write_csv((out / "front.csv").string(), {"time_s", "front_x_m", "front_velocity_m_s"},
              {results.frame_time, m.front_x, m.front_velocity});
  if (results.metadata.base_motion.enabled()) write_ground_motion(results, (out / "ground_motion.csv").string());
  if (m.newmark)
    write_csv((out / "newmark_block.csv").string(), {"time_s", "mpm_m", "exact_m"},
              {m.newmark->time, m.newmark->mpm, m.newmark->newmark});
  if (m.spring)
    write_csv((out / "spring_mass.csv").string(), {"time_s", "mpm_m", "exact_m"},
              {m.spring->time, m.spring->settlement, m.spring->exact});
  if (m.box)
    write_csv((out / "box_incline.csv").string(), {"time_s", "mpm_m", "exact_m"},
              {m.box->time, m.box->along_slope, m.box->exact});

  log << "talus post: " << results.metadata.scene_name << ", "
      << (slope && ground.indices.size() > 1 ? "bodies " + body_names(results.metadata, ground)
                                             : "body '" + results.metadata.bodies[slope ? ground.indices.front() : body.index].name + "'")
      << ", " << results.frames() << " frames to t = " << format(results.frame_time.back(), 3, " s") << "\n";
  if (!results.complete) log << "  note: the run did not complete; metrics are of its last frame\n";
  print_summary(m, log);
  log << "  wrote " << (out / "metrics.json").string() << " and CSV histories\n";

  if (!options.figures) return 0;
  const std::string script = options.figures_script.empty() ? figures_script() : options.figures_script;
  std::vector<std::string> arguments{"--results", results_path, "--out", out_dir};
  if (post.animate) arguments.push_back("--animate");
  run_figure_script(script, arguments, log, options.python);
  return 0;
}

}  // namespace talus::postproc
