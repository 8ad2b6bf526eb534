// Boundary conditions resolved per node of the background mesh: fixed nodes, roller nodes
// with the unit normal along which their velocity is zero, and friction nodes with their
// outward unit normal and Coulomb coefficient.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/scene/scene.hpp"

namespace talus::preproc {

struct BoundaryCurve {
  std::string name;
  BoundaryType type = BoundaryType::Fixed;
  std::optional<Eigen::Vector2d> normal;              // the scene's normal (rollers, friction), else the curve's
  std::vector<std::array<int32_t, 2>> segments;       // the curve's mesh segments, node ids
  double friction = 0;                                // friction: Coulomb coefficient
};

struct NodeConstraints {
  std::vector<int32_t> fixed_nodes;             // sorted, unique
  std::vector<int32_t> roller_nodes;            // sorted, unique, none of them fixed
  std::vector<Eigen::Vector2d> roller_normals;  // unit, one per roller node
  std::vector<int32_t> friction_nodes;            // sorted, unique, neither fixed nor roller
  std::vector<Eigen::Vector2d> friction_normals;  // unit, out of the domain, one per friction node
  std::vector<double> friction_coefficients;      // one per friction node
};

// Nodes on several curves: fixed wins over roller; two rollers whose normals are not parallel
// fix the node. A roller's normal at a node, when the scene gives none, is the average of the
// unit normals of the node's segments on that curve. A friction curve is a roller that may
// separate and resists sliding (Coulomb): its normals point out of the domain (away from the
// triangle on each segment; `triangles` is the background mesh); with a roller or another
// friction curve of a different normal it fixes the node, with a parallel one it wins (the
// larger coefficient of two).
NodeConstraints resolve_constraints(const std::vector<Eigen::Vector2d>& nodes, const std::vector<BoundaryCurve>& curves,
                                    const std::vector<std::array<int32_t, 3>>& triangles = {});

}  // namespace talus::preproc
