// Boundary conditions resolved per node of the background mesh: fixed nodes, and roller nodes
// with the unit normal along which their velocity is zero.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/scene.hpp"

namespace talus::preproc {

struct BoundaryCurve {
  std::string name;
  BoundaryType type = BoundaryType::Fixed;
  std::optional<Eigen::Vector2d> normal;              // the scene's normal (rollers), else the curve's
  std::vector<std::array<int32_t, 2>> segments;       // the curve's mesh segments, node ids
};

struct NodeConstraints {
  std::vector<int32_t> fixed_nodes;             // sorted, unique
  std::vector<int32_t> roller_nodes;            // sorted, unique, none of them fixed
  std::vector<Eigen::Vector2d> roller_normals;  // unit, one per roller node
};

// Nodes on several curves: fixed wins over roller; two rollers whose normals are not parallel
// fix the node. A roller's normal at a node, when the scene gives none, is the average of the
// unit normals of the node's segments on that curve.
NodeConstraints resolve_constraints(const std::vector<Eigen::Vector2d>& nodes, const std::vector<BoundaryCurve>& curves);

}  // namespace talus::preproc
