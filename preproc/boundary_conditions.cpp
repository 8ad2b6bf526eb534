#include "preproc/boundary_conditions.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace talus::preproc {
namespace {

// Normals whose cross product is below this are parallel (about 0.06 degrees apart).
constexpr double kParallel = 1e-3;

// Per node, the average of the unit normals of its segments. Segments of one curve need not be
// oriented alike, so each normal is flipped to agree with the running sum before it is added.
std::map<int32_t, Eigen::Vector2d> curve_normals(const std::vector<Eigen::Vector2d>& nodes,
                                                 const std::vector<std::array<int32_t, 2>>& segments) {
  std::map<int32_t, Eigen::Vector2d> sum;
  for (const auto& [a, b] : segments) {
    const Eigen::Vector2d tangent = (nodes[b] - nodes[a]).normalized();
    const Eigen::Vector2d normal(tangent.y(), -tangent.x());
    for (int32_t node : {a, b}) {
      auto [entry, inserted] = sum.try_emplace(node, Eigen::Vector2d::Zero());
      entry->second += entry->second.dot(normal) < 0 ? -normal : normal;
    }
  }
  for (auto& [node, n] : sum) n.normalize();
  return sum;
}

}  // namespace

NodeConstraints resolve_constraints(const std::vector<Eigen::Vector2d>& nodes, const std::vector<BoundaryCurve>& curves) {
  std::set<int32_t> fixed;
  std::map<int32_t, Eigen::Vector2d> rollers;
  for (const auto& curve : curves) {
    if (curve.type == BoundaryType::Fixed) {
      for (const auto& segment : curve.segments) fixed.insert(segment.begin(), segment.end());
      continue;
    }
    std::map<int32_t, Eigen::Vector2d> normals = curve_normals(nodes, curve.segments);
    if (curve.normal)
      for (auto& [node, n] : normals) n = curve.normal->normalized();
    for (const auto& [node, n] : normals) {
      const auto [entry, inserted] = rollers.try_emplace(node, n);
      const Eigen::Vector2d& m = entry->second;
      if (!inserted && std::abs(m.x() * n.y() - m.y() * n.x()) > kParallel) fixed.insert(node);
    }
  }

  NodeConstraints constraints;
  constraints.fixed_nodes.assign(fixed.begin(), fixed.end());
  for (const auto& [node, n] : rollers) {
    if (fixed.count(node)) continue;
    constraints.roller_nodes.push_back(node);
    constraints.roller_normals.push_back(n);
  }
  return constraints;
}

}  // namespace talus::preproc
