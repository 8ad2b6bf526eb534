// The seismic keys of metrics.json (talus post) and fos.json (talus fos): written only for a
// model with [seismic] or [base_motion] (docs/seismic.md), so other files are unchanged.
#pragma once
#include <optional>

#include "common/model/model.hpp"
#include "postproc/output.hpp"
#include "postproc/pseudo_static.hpp"

namespace talus::postproc {

// Whether the keys are due, and with them Bishop's yield coefficient.
inline bool seismic_keys_due(const Model& model) { return model.seismic.enabled() || model.base_motion.enabled(); }

// The shaken slope against Newmark's estimate (talus post with [base_motion] and a k_y): Newmark's
// rigid block with a_c = k_y g (gain 1: the displacement along the inertial force, horizontal)
// under the record's inertial acceleration towards the toe, from the motion's start to the last
// frame; and the crest's displacement in the run, relative to the ground (the particle of the
// analysed bodies nearest the crest point, its displacement towards the toe and its magnitude).
struct ShakenSlope {
  double newmark_displacement = 0;      // m
  double crest_displacement_toe = 0;    // m, horizontal, towards the toe
  double crest_displacement = 0;        // m, magnitude
};

// seismic: {k_h, k_v, k_y, k_y_circle {xc_m, yc_m, r_m}} (k_y and its circle null when the slope
// has no resistance to spare, F <= 1 at k_h = 0, or no admissible circle; the circle in the
// scene's frame), and with a shaken slope newmark_displacement_m, crest_displacement_toe_m,
// crest_displacement_m.
void write_seismic_keys(JsonWriter& json, const Model& model, const std::optional<YieldCoefficient>& k_y,
                        const std::optional<ShakenSlope>& shaken = std::nullopt);

// ground_motion: {type, start_s, duration_s, peak_acceleration_m_s2, baseline_m_s2 [x, y],
// final_displacement_m [x, y] (the ground's, at the last frame), positions: "relative to the
// ground"}: results.h5 holds positions in the ground's frame, so every displacement, runout and
// slip surface of metrics.json is relative to the ground.
void write_ground_motion_keys(JsonWriter& json, const BaseMotion& motion, double last_time);

// ground_motion.csv: per frame time, the ground's displacement and velocity (m, m/s), the
// frame's absolute positions being its positions plus this displacement.
struct Results;
void write_ground_motion(const Results& results, const std::string& path);

}  // namespace talus::postproc
