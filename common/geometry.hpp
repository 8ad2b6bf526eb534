// Plane geometry shared by the stages.
#pragma once
#include <Eigen/Core>
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

}  // namespace talus
