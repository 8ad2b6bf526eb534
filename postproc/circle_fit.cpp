#include "postproc/circle_fit.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace talus::postproc {
namespace {

// Kasa: minimise sum (x^2 + y^2 + D x + E y + F)^2, linear in (D, E, F). Points are shifted to
// their centroid and scaled first so that the normal equations stay well conditioned.
std::optional<Circle> kasa_fit(const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& origin,
                               double scale) {
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd a(n, 3);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d q = (points[i] - origin) / scale;
    a.row(i) << q.x(), q.y(), 1.0;
    b(i) = -q.squaredNorm();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  if (qr.rank() < 3) return std::nullopt;
  const Eigen::Vector3d def = qr.solve(b);
  const Eigen::Vector2d centre(-0.5 * def(0), -0.5 * def(1));
  const double r2 = centre.squaredNorm() - def(2);
  if (!(r2 > 0) || !std::isfinite(r2)) return std::nullopt;
  return Circle{origin + scale * centre, scale * std::sqrt(r2)};
}

}  // namespace

std::optional<Circle> fit_circle(const std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 3) return std::nullopt;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  for (const auto& p : points) origin += p;
  origin /= static_cast<double>(points.size());
  double scale = 0;
  for (const auto& p : points) scale = std::max(scale, (p - origin).norm());
  if (!(scale > 0)) return std::nullopt;

  std::optional<Circle> start = kasa_fit(points, origin, scale);
  if (!start) return std::nullopt;

  // Gauss-Newton on r_i = |p_i - c| - R with unknowns (c_x, c_y, R).
  Circle circle = *start;
  const Eigen::Index n = static_cast<Eigen::Index>(points.size());
  for (int iteration = 0; iteration < 100; ++iteration) {
    Eigen::MatrixXd jacobian(n, 3);
    Eigen::VectorXd residual(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector2d d = points[i] - circle.centre;
      const double distance = std::max(d.norm(), 1e-300);
      residual(i) = distance - circle.radius;
      jacobian.row(i) << -d.x() / distance, -d.y() / distance, -1.0;
    }
    const Eigen::Vector3d step = jacobian.colPivHouseholderQr().solve(-residual);
    if (!step.allFinite()) break;
    circle.centre += step.head<2>();
    circle.radius += step(2);
    if (step.norm() < 1e-12 * scale) break;
  }
  // Gauss-Newton can wander off when the points barely curve; keep whichever fits better.
  if (!(circle.radius > 0) || !circle.centre.allFinite() ||
      circle_rms_distance(circle, points) > circle_rms_distance(*start, points))
    return start;
  return circle;
}

double circle_rms_distance(const Circle& circle, const std::vector<Eigen::Vector2d>& points) {
  if (points.empty()) return 0;
  double sum = 0;
  for (const auto& p : points) {
    const double r = (p - circle.centre).norm() - circle.radius;
    sum += r * r;
  }
  return std::sqrt(sum / static_cast<double>(points.size()));
}

}  // namespace talus::postproc
