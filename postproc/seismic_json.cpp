#include "postproc/seismic_json.hpp"

#include "postproc/results.hpp"

namespace talus::postproc {

void write_seismic_keys(JsonWriter& json, const Model& model, const std::optional<YieldCoefficient>& k_y,
                        const std::optional<ShakenSlope>& shaken) {
  json.key("seismic").begin_object();
  json.key("k_h").value(model.seismic.k_h).key("k_v").value(model.seismic.k_v);
  json.key("k_y").value(k_y ? std::optional<double>(k_y->k_y) : std::nullopt);
  json.key("k_y_circle");
  if (k_y && k_y->circle) {
    const Circle& c = k_y->circle->circle;
    json.begin_object().key("xc_m").value(c.centre.x()).key("yc_m").value(c.centre.y()).key("r_m").value(c.radius).end_object();
  } else {
    json.null();
  }
  if (shaken)
    json.key("newmark_displacement_m").value(shaken->newmark_displacement)
        .key("crest_displacement_toe_m").value(shaken->crest_displacement_toe)
        .key("crest_displacement_m").value(shaken->crest_displacement);
  json.end_object();
}

void write_ground_motion_keys(JsonWriter& json, const BaseMotion& motion, double last_time) {
  const Eigen::Vector2d baseline = motion.baseline(), u = motion.ground_displacement(last_time);
  json.key("ground_motion").begin_object();
  json.key("type").value(motion.type == MotionType::Sine ? "sine" : "record");
  json.key("start_s").value(motion.start).key("duration_s").value(motion.duration());
  json.key("peak_acceleration_m_s2").value(motion.peak_acceleration());
  json.key("baseline_m_s2").begin_array().value(baseline.x()).value(baseline.y()).end_array();
  json.key("final_displacement_m").begin_array().value(u.x()).value(u.y()).end_array();
  json.key("positions").value("relative to the ground");
  json.end_object();
}

void write_ground_motion(const Results& results, const std::string& path) {
  const BaseMotion& motion = results.metadata.base_motion;
  std::vector<double> ux, uy, vx, vy;
  for (double t : results.frame_time) {
    const Eigen::Vector2d u = motion.ground_displacement(t), v = motion.ground_velocity(t);
    ux.push_back(u.x()), uy.push_back(u.y()), vx.push_back(v.x()), vy.push_back(v.y());
  }
  write_csv(path, {"time_s", "ground_ux_m", "ground_uy_m", "ground_vx_m_s", "ground_vy_m_s"},
            {results.frame_time, ux, uy, vx, vy});
}

}  // namespace talus::postproc
