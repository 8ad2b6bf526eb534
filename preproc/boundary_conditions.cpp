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

// The normals of `normals` flipped to point away from the triangle on each of the curve's
// segments (a domain boundary segment has exactly one).
void point_outwards(const std::vector<Eigen::Vector2d>& nodes, const std::vector<std::array<int32_t, 2>>& segments,
                    const std::vector<std::array<int32_t, 3>>& triangles, std::map<int32_t, Eigen::Vector2d>& normals) {
  std::map<std::pair<int32_t, int32_t>, int32_t> third;  // edge (low, high) -> the opposite node
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
      third[{std::min(a, b), std::max(a, b)}] = t[k];
    }
  std::map<int32_t, double> inward;  // per node: the sum over its segments of normal . (inside - edge)
  for (const auto& [a, b] : segments) {
    const auto found = third.find({std::min(a, b), std::max(a, b)});
    if (found == third.end()) continue;
    const Eigen::Vector2d towards_inside = nodes[found->second] - 0.5 * (nodes[a] + nodes[b]);
    for (int32_t node : {a, b}) inward[node] += normals[node].dot(towards_inside);
  }
  for (auto& [node, n] : normals)
    if (inward[node] > 0) n = -n;
}

}  // namespace

NodeConstraints resolve_constraints(const std::vector<Eigen::Vector2d>& nodes, const std::vector<BoundaryCurve>& curves,
                                    const std::vector<std::array<int32_t, 3>>& triangles) {
  std::set<int32_t> fixed;
  std::map<int32_t, Eigen::Vector2d> rollers;
  std::map<int32_t, double> friction;  // the friction nodes among `rollers`, with their coefficient
  for (const auto& curve : curves) {
    if (curve.type == BoundaryType::Absorbing) continue;  // dashpots, not constraints (absorbing.hpp)
    if (curve.type == BoundaryType::Fixed) {
      for (const auto& segment : curve.segments) fixed.insert(segment.begin(), segment.end());
      continue;
    }
    std::map<int32_t, Eigen::Vector2d> normals = curve_normals(nodes, curve.segments);
    if (curve.normal)
      for (auto& [node, n] : normals) n = curve.normal->normalized();
    const bool frictional = curve.type == BoundaryType::Friction;
    if (frictional) point_outwards(nodes, curve.segments, triangles, normals);
    for (const auto& [node, n] : normals) {
      const auto [entry, inserted] = rollers.try_emplace(node, n);
      const Eigen::Vector2d& m = entry->second;
      if (!inserted && std::abs(m.x() * n.y() - m.y() * n.x()) > kParallel) fixed.insert(node);
      if (!frictional) continue;
      // A friction curve wins over a parallel roller: its normal points out of the domain.
      if (!inserted && !friction.count(node)) entry->second = n;
      friction[node] = std::max(friction[node], curve.friction);
    }
  }

  NodeConstraints constraints;
  constraints.fixed_nodes.assign(fixed.begin(), fixed.end());
  for (const auto& [node, n] : rollers) {
    if (fixed.count(node)) continue;
    const auto mu = friction.find(node);
    if (mu == friction.end()) {
      constraints.roller_nodes.push_back(node);
      constraints.roller_normals.push_back(n);
    } else {
      constraints.friction_nodes.push_back(node);
      constraints.friction_normals.push_back(n);
      constraints.friction_coefficients.push_back(mu->second);
    }
  }
  return constraints;
}

}  // namespace talus::preproc
