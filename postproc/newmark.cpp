#include "postproc/newmark.hpp"

#include <algorithm>
#include <cmath>

namespace talus::postproc {

NewmarkBlock incline_block(double mu, double theta_deg, double g) {
  const double c = std::cos(theta_deg * M_PI / 180), s = std::sin(theta_deg * M_PI / 180);
  return {g * (mu * c - s) / (c + mu * s), c + mu * s};
}

NewmarkHistory newmark_sliding(const std::function<double(double)>& a_drive, const NewmarkBlock& block, double t0,
                               double t1, double dt, int every) {
  NewmarkHistory out;
  double v = 0, d = 0;
  const long steps = static_cast<long>(std::ceil((t1 - t0) / dt));
  auto relative = [&](double t) { return block.gain * (a_drive(t) - block.critical_acceleration); };
  out.time.push_back(t0), out.displacement.push_back(0), out.velocity.push_back(0);
  double a0 = relative(t0);
  for (long k = 0; k < steps; ++k) {
    const double t = t0 + k * dt, h = std::min(dt, t1 - t);
    const double a1 = relative(t + h);
    if (v > 0 || a0 > 0 || a1 > 0) {
      double v1 = v + 0.5 * (a0 + a1) * h;
      double used = h;
      if (v1 < 0) {  // sticks within the step: where the (linear) velocity reaches zero
        const double slope = (a1 - a0) / h;
        // v + a0 s + slope s^2 / 2 = 0 for the first s in (0, h]; bisection keeps it simple and exact enough.
        double lo = 0, hi = h;
        for (int i = 0; i < 60; ++i) {
          const double mid = 0.5 * (lo + hi);
          (v + a0 * mid + 0.5 * slope * mid * mid > 0 ? lo : hi) = mid;
        }
        used = 0.5 * (lo + hi);
        d += v * used + 0.5 * a0 * used * used + slope * used * used * used / 6;
        v1 = 0;
      } else {
        d += 0.5 * (v + v1) * h;
      }
      v = std::max(v1, 0.0);
    }
    a0 = a1;
    if ((k + 1) % every == 0 || k + 1 == steps)
      out.time.push_back(t + h), out.displacement.push_back(d), out.velocity.push_back(v);
  }
  return out;
}

}  // namespace talus::postproc

namespace talus::postproc {

NewmarkBlockCheck newmark_block_check(const std::vector<double>& time, const std::vector<Eigen::Vector2d>& displacement,
                                      double angle_deg, double gravity, double mu, const BaseMotion& motion) {
  NewmarkBlockCheck out;
  out.block = incline_block(mu, angle_deg, gravity);
  if (time.empty()) return out;
  const Eigen::Vector2d down(std::cos(angle_deg * M_PI / 180), -std::sin(angle_deg * M_PI / 180));
  // The box's position when the motion starts: the last frame at or before it.
  std::size_t first = 0;
  while (first + 1 < time.size() && time[first + 1] <= motion.start + 1e-12) ++first;
  const double t0 = std::max(time[first], motion.start);
  const NewmarkHistory history = newmark_sliding(
      [&motion](double t) { return -motion.ground_acceleration(t).x(); }, out.block, t0, time.back(), 1e-5, 1);
  for (std::size_t k = first; k < time.size(); ++k) {
    out.time.push_back(time[k]);
    out.mpm.push_back((displacement[k] - displacement[first]).dot(down));
    // The history is sampled every 1e-5 s: the sample at or just after the frame's time.
    const std::size_t at = std::min<std::size_t>(
        std::lower_bound(history.time.begin(), history.time.end(), time[k] - 1e-9) - history.time.begin(),
        history.time.size() - 1);
    out.newmark.push_back(history.displacement[at]);
  }
  out.mpm_final = out.mpm.back();
  out.newmark_final = history.final_displacement();
  out.relative_error = out.newmark_final > 0 ? std::abs(out.mpm_final - out.newmark_final) / out.newmark_final : 0.0;
  return out;
}

}  // namespace talus::postproc
