// Earthquakes in a scene (docs/seismic.md): the pseudo-static coefficients of [seismic], for
// Bishop's method and strength reduction, and the ground motion of [base_motion], which the
// solver applies to the whole model.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace talus {

// [seismic]: a pseudo-static inertial force on the ground, as fractions of g. k_h acts
// horizontally towards the slope's toe, k_v vertically, positive upwards (the weight becomes
// (1 - k_v) W).
struct SeismicSettings {
  double k_h = 0;
  double k_v = 0;
  bool enabled() const { return k_h != 0 || k_v != 0; }
};

// [base_motion]: the ground's acceleration a_g(t), as a record (t, a_x, a_y) interpolated
// linearly, or a sine a_x = amplitude sin(2 pi frequency (t - start)) of whole cycles. The
// record starts at `start` s of the run (zero before, and after its end).
//
// The model is solved in the frame that moves with the ground: the named boundaries and fixed
// bodies (all the model's constrained ones, so that the whole base moves rigidly) stay at rest
// in it, and every particle feels the inertial body force -a_g(t) besides gravity. This is the
// relative-displacement formulation of structural dynamics; the nodes of those boundaries and
// bodies then move with the ground velocity v_g in the fixed frame. Positions and velocities
// in results.h5 are relative to the ground; the ground's own displacement u_g(t) follows from
// the record (ground_displacement), and `talus post` writes it per frame.
//
// Baseline correction of a record: a constant acceleration is taken off the whole record so
// that the ground velocity at its end is zero (v_g(end) = 0, "zero final velocity"), and the
// solver applies the corrected record. The built-in sine of whole cycles needs none (its
// velocity returns to zero; its displacement keeps a drift of amplitude cycles / (f omega)).
enum class MotionType { Record, Sine };

// An absorbing boundary's nodes (Lysmer and Kuhlemeyer 1969), resolved when meshing: per node its
// share of the boundary's length (half of each of its segments), the unit outward normal (length
// weighted), the impedances rho c_p (normal) and rho c_s (tangential) of the boundary's material,
// and whether it inputs a compliant base's motion. Empty: no absorbing boundary.
struct AbsorbingNodes {
  std::vector<int32_t> node;
  std::vector<double> length;                // m
  std::vector<Eigen::Vector2d> normal;       // unit, out of the domain
  std::vector<Eigen::Vector2d> impedance;    // (rho c_p, rho c_s), Pa s/m
  std::vector<int32_t> input;                // 1: the compliant base's motion enters here
  bool empty() const { return node.empty(); }
};

struct BaseMotion {
  std::vector<std::string> boundaries;  // [boundaries.NAME] that move with the ground
  std::vector<std::string> bodies;      // fixed [bodies.NAME] that move with it
  MotionType type = MotionType::Record;
  std::string file;                     // the record's CSV as given in the scene (Record)
  std::vector<double> time;             // s, strictly increasing, from 0 (Record)
  std::vector<Eigen::Vector2d> acceleration;  // m/s^2 as read, before the baseline correction
  double amplitude = 0, frequency = 0;  // m/s^2, Hz (Sine)
  int cycles = 0;
  double start = 0;                     // s: the run time at which the record's t = 0 falls
  // A compliant base (base = "compliant"): the model stays in the fixed frame and the motion
  // enters through the listed absorbing boundaries as the stress of their dashpots against the
  // ground velocity, -rho c (v - v_g(t)) (Joyner and Chen 1975): with v_g the outcrop motion,
  // twice the incident wave, the wave going down leaves the model through the same dashpots.
  bool compliant = false;

  bool enabled() const { return type == MotionType::Sine ? amplitude != 0 : !time.empty(); }
  double duration() const;  // s, from the record's start to its end
  // The constant acceleration the baseline correction takes off the record (m/s^2).
  Eigen::Vector2d baseline() const;
  // The (corrected) ground acceleration, velocity and displacement at run time t.
  Eigen::Vector2d ground_acceleration(double t) const;
  Eigen::Vector2d ground_velocity(double t) const;
  Eigen::Vector2d ground_displacement(double t) const;
  double peak_acceleration() const;  // m/s^2, the largest |a_g|
};

// The first problem of a record's samples (times strictly increasing from >= 0, finite, at least
// two), as "row N: ..." (rows counted from 1); "" when sound.
std::string motion_record_problem(const std::vector<double>& time, const std::vector<Eigen::Vector2d>& acceleration);

// Reads a record from a CSV file: rows "t, a_x[, a_y]" (s, m/s^2), an optional header line of
// text first, '#' comments and blank lines skipped. Throws talus::Error naming `item` (the scene
// key) and the file's row.
void read_motion_csv(const std::string& path, const std::string& scene_file, const std::string& item,
                     std::vector<double>& time, std::vector<Eigen::Vector2d>& acceleration);

}  // namespace talus
