#include "postproc/validation.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace talus::postproc {

SpringMassCheck spring_mass_check(const std::vector<double>& time, const std::vector<double>& centre_y,
                                  double initial_y, double amplitude, double omega) {
  SpringMassCheck check;
  check.time = time;
  double max_error = 0;
  for (std::size_t k = 0; k < time.size(); ++k) {
    const double settlement = initial_y - centre_y[k];
    const double exact = amplitude * (1 - std::cos(omega * time[k]));
    check.settlement.push_back(settlement);
    check.exact.push_back(exact);
    max_error = std::max(max_error, std::abs(settlement - exact));
  }
  check.max_error_over_amplitude = max_error / amplitude;
  return check;
}

BoxInclineCheck box_incline_check(const std::vector<double>& time, const std::vector<Eigen::Vector2d>& displacement,
                                  double angle_deg, const Eigen::Vector2d& gravity, double friction,
                                  double gravity_ramp) {
  BoxInclineCheck check;
  const double a = angle_deg * M_PI / 180.0;
  const double g = gravity.norm();
  check.acceleration = std::max(g * (std::sin(a) - friction * std::cos(a)), 0.0);
  const Eigen::Vector2d down = g > 0 ? Eigen::Vector2d(gravity / g) : Eigen::Vector2d(0, -1);
  const Eigen::Vector2d one_way = Eigen::Rotation2Dd(M_PI / 2 - a) * down;  // counter-clockwise
  const Eigen::Vector2d other_way = Eigen::Rotation2Dd(a - M_PI / 2) * down;
  const bool other = !displacement.empty() && displacement.back().dot(other_way) > displacement.back().dot(one_way);
  const Eigen::Vector2d downhill = other ? other_way : one_way;
  check.time = time;
  for (std::size_t k = 0; k < time.size(); ++k) {
    check.along_slope.push_back(displacement[k].dot(downhill));
    check.exact.push_back(ramped_slide(check.acceleration, gravity_ramp, time[k]));
    check.max_abs_displacement = std::max(check.max_abs_displacement, displacement[k].norm());
  }
  for (double t : {0.25, 0.5, 0.75, 1.0}) {
    const auto mpm = interpolate(time, check.along_slope, t);
    if (!mpm) continue;
    const double exact = ramped_slide(check.acceleration, gravity_ramp, t);
    check.check_times.push_back(t);
    check.mpm_at_check.push_back(*mpm);
    check.exact_at_check.push_back(exact);
    check.relative_error.push_back(exact > 0 ? std::optional<double>(std::abs(*mpm - exact) / exact)
                                             : std::nullopt);
  }
  return check;
}

double ramped_slide(double acceleration, double ramp, double t) {
  if (t >= ramp) return acceleration * (0.5 * t * t - 0.5 * ramp * t + ramp * ramp * (0.25 - 1.0 / (M_PI * M_PI)));
  return acceleration * (0.25 * t * t + ramp * ramp * (std::cos(M_PI * t / ramp) - 1.0) / (2.0 * M_PI * M_PI));
}

std::optional<double> interpolate(const std::vector<double>& t, const std::vector<double>& y, double at) {
  if (t.empty() || at < t.front() - 1e-12 || at > t.back() + 1e-12) return std::nullopt;
  const auto upper = std::lower_bound(t.begin(), t.end(), at);
  if (upper == t.begin()) return y.front();
  if (upper == t.end()) return y.back();
  const std::size_t i = upper - t.begin();
  const double span = t[i] - t[i - 1];
  if (!(span > 0)) return y[i];
  return y[i - 1] + (y[i] - y[i - 1]) * (at - t[i - 1]) / span;
}

}  // namespace talus::postproc
