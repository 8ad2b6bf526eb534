#include "preproc/absorbing.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace talus::preproc {

AbsorbingNodes absorbing_nodes(const std::vector<Eigen::Vector2d>& nodes, const std::vector<BoundaryCurve>& curves,
                               const std::vector<std::array<int32_t, 3>>& triangles, const Scene& scene) {
  AbsorbingNodes out;
  if (std::none_of(curves.begin(), curves.end(), [](const BoundaryCurve& c) { return c.type == BoundaryType::Absorbing; }))
    return out;
  std::map<std::pair<int32_t, int32_t>, int32_t> third;  // edge (sorted) -> the triangle's other vertex
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
      third[{std::min(a, b), std::max(a, b)}] = t[k];
    }
  std::map<int32_t, std::size_t> slot;
  for (const auto& curve : curves) {
    if (curve.type != BoundaryType::Absorbing) continue;
    const Boundary& boundary =
        *std::find_if(scene.boundaries.begin(), scene.boundaries.end(), [&](const Boundary& b) { return b.name == curve.name; });
    const Material& material = scene.materials[scene.material_index(boundary.material)];
    const double rho = material.density, G = material.shear_modulus();
    const double K = material.youngs_modulus / (3 * (1 - 2 * material.poisson_ratio));
    const Eigen::Vector2d impedance(std::sqrt((K + 4 * G / 3) * rho), std::sqrt(G * rho));  // rho c = sqrt(M rho)
    const auto& listed = scene.base_motion.boundaries;
    const int input = scene.base_motion.compliant && std::find(listed.begin(), listed.end(), curve.name) != listed.end();
    for (const auto& [a, b] : curve.segments) {
      const Eigen::Vector2d edge = nodes[b] - nodes[a];
      Eigen::Vector2d normal(edge.y(), -edge.x());
      normal.normalize();
      const auto found = third.find({std::min(a, b), std::max(a, b)});
      if (found != third.end() && normal.dot(nodes[found->second] - nodes[a]) > 0) normal = -normal;
      for (int32_t node : {a, b}) {
        const auto [entry, added] = slot.try_emplace(node, out.node.size());
        if (added) {
          out.node.push_back(node);
          out.length.push_back(0);
          out.normal.push_back(Eigen::Vector2d::Zero());
          out.impedance.push_back(impedance);
          out.input.push_back(input);
        }
        out.length[entry->second] += 0.5 * edge.norm();
        out.normal[entry->second] += 0.5 * edge.norm() * normal;
      }
    }
  }
  for (auto& n : out.normal) n.normalize();
  return out;
}

}  // namespace talus::preproc
