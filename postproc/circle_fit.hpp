// Least-squares circle through scattered points: the algebraic fit of Kasa (1976), which is
// linear and needs no start, refined by Gauss-Newton on the geometric distances
// |p_i - c| - r (the fit that is unbiased for points on a short arc, where Kasa's shrinks).
#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

namespace talus::postproc {

struct Circle {
  Eigen::Vector2d centre{0, 0};  // m
  double radius = 0;             // m
};

// Empty when fewer than 3 points or the points are collinear (no finite circle).
std::optional<Circle> fit_circle(const std::vector<Eigen::Vector2d>& points);

// Root-mean-square of |p_i - c| - r.
double circle_rms_distance(const Circle& circle, const std::vector<Eigen::Vector2d>& points);

}  // namespace talus::postproc
