// The validation scenes' comparisons with their analytical solutions (docs/validation in
// shared/validation.md): the spring and mass (seed section 2) and the box sliding on an incline
// (seed section 3). Inputs are plain time series of one body's centre of mass.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

namespace talus::postproc {

struct SpringMassCheck {
  std::vector<double> time;        // s
  std::vector<double> settlement;  // m, downward positive: y_c(0) - y_c(t)
  std::vector<double> exact;       // m, A (1 - cos(omega t))
  double max_error_over_amplitude = 0;
};

// centre_y: the body's centre-of-mass height at each frame time; initial_y: before the first step.
SpringMassCheck spring_mass_check(const std::vector<double>& time, const std::vector<double>& centre_y,
                                  double initial_y, double amplitude, double omega);

struct BoxInclineCheck {
  double acceleration = 0;          // m/s^2 along the slope: g (sin a - mu cos a), >= 0
  std::vector<double> time;         // s
  std::vector<double> along_slope;  // m, centre-of-mass displacement projected down the slope
  std::vector<double> exact;        // m, a t^2 / 2 (with gravity ramped over T, ramped_slide)
  std::vector<double> check_times;  // s: 0.25, 0.5, 0.75, 1.0 (those inside the record)
  std::vector<double> mpm_at_check, exact_at_check;
  // |mpm - exact| / exact at each check time; empty optionals when exact = 0 (mu >= tan a: the
  // box must stay put, judged by max_abs_displacement instead).
  std::vector<std::optional<double>> relative_error;
  double max_abs_displacement = 0;  // m
};

// displacement: the box's centre-of-mass displacement from its initial position at each frame
// time; gravity: the scene's gravity vector (m/s^2). The downhill direction is gravity's
// direction turned by 90 - a degrees either way, whichever the box's final displacement points
// along more (counter-clockwise when it has not moved): with gravity (0, -g) it is (cos a, -sin a)
// or (-cos a, -sin a), a slope rotated in the plane; with gravity tilted by a, g (sin a, -cos a),
// it is (1, 0), a level slab in the slope's own frame (geometries/box_incline_level.toml).
// gravity_ramp: the scene's run.gravity_ramp T (s; 0 for none), over which gravity, and with it
// the box's acceleration, rises as (1 - cos(pi t / T)) / 2.
BoxInclineCheck box_incline_check(const std::vector<double>& time, const std::vector<Eigen::Vector2d>& displacement,
                                  double angle_deg, const Eigen::Vector2d& gravity, double friction,
                                  double gravity_ramp);

// The distance from rest at time t of a slide whose acceleration rises from 0 to a as
// (1 - cos(pi t / T)) / 2 over the first T seconds and stays a after (a t^2 / 2 when T = 0):
// a (t^2 / 4 + T^2 (cos(pi t / T) - 1) / (2 pi^2)) for t < T, a (t^2 / 2 - T t / 2 + T^2 / 4 - T^2 / pi^2) after.
double ramped_slide(double acceleration, double ramp, double t);

// Linear interpolation of samples (t_i, y_i) at t; empty outside [t_0, t_last].
std::optional<double> interpolate(const std::vector<double>& t, const std::vector<double>& y, double at);

}  // namespace talus::postproc
