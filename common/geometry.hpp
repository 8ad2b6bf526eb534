// Plane geometry shared by the stages.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace talus {

// Signed area of a closed loop (the last vertex joins the first), positive when it runs
// counter-clockwise, by the shoelace formula.
inline double signed_area(const std::vector<Eigen::Vector2d>& loop) {
  double twice_area = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Eigen::Vector2d& a = loop[i];
    const Eigen::Vector2d& b = loop[(i + 1) % n];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * twice_area;
}

// Even-odd rule by ray casting along +x: inside when a ray from p crosses the loops' edges an
// odd number of times (outer loops, holes, islands in holes). Plain floating point, for checks
// and benchmarks; preproc::Region is the exact one the seeding uses.
inline bool inside_loops(const std::vector<std::vector<Eigen::Vector2d>>& loops, const Eigen::Vector2d& p) {
  bool odd = false;
  for (const auto& loop : loops)
    for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
      const Eigen::Vector2d& a = loop[i];
      const Eigen::Vector2d& b = loop[j];
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()))
        odd = !odd;
    }
  return odd;
}

// The height at x of a polyline of (x, y) points (at least one) with x not decreasing, linear
// between its points and held level beyond its ends; at a vertical step (two points at one x)
// the height just beyond it (of the later point).
inline double polyline_height(const std::vector<Eigen::Vector2d>& points, double x) {
  if (x <= points.front().x()) return points.front().y();
  if (x >= points.back().x()) return points.back().y();
  const auto upper = std::upper_bound(points.begin(), points.end(), x,
                                      [](double value, const Eigen::Vector2d& p) { return value < p.x(); });
  const Eigen::Vector2d& b = *upper;
  const Eigen::Vector2d& a = *(upper - 1);
  return a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
}

}  // namespace talus
