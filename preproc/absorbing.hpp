// Absorbing boundaries resolved on the background mesh (docs/seismic.md): Lysmer and
// Kuhlemeyer's (1969) viscous dashpots, normal rho c_p and tangential rho c_s, lumped at the
// nodes of the scene's boundaries of type "absorbing".
#pragma once
#include <array>
#include <vector>

#include "common/scene/scene.hpp"
#include "preproc/boundary_conditions.hpp"

namespace talus::preproc {

// Per node of the absorbing curves: half the length of each of its segments, the length-weighted
// outward normal (away from the triangle on each segment), the impedances of the boundary's
// material (c_p = sqrt((K + 4 G / 3) / rho), c_s = sqrt(G / rho), plane strain) and, with a
// compliant base, whether the curve inputs the motion. A node on two absorbing curves takes both
// lengths and the first curve's impedances.
AbsorbingNodes absorbing_nodes(const std::vector<Eigen::Vector2d>& nodes, const std::vector<BoundaryCurve>& curves,
                               const std::vector<std::array<int32_t, 3>>& triangles, const Scene& scene);

}  // namespace talus::preproc
