#include "preproc/background_mesh.hpp"

#include <algorithm>
#include <unordered_map>

#include "common/error.hpp"

namespace talus::preproc {

bool find_neighbours(const std::vector<std::array<int32_t, 3>>& triangles,
                     std::vector<std::array<int32_t, 3>>& neighbours) {
  neighbours.assign(triangles.size(), {-1, -1, -1});
  // Edge (low, high) -> the first triangle and local vertex opposite it that were seen.
  std::unordered_map<uint64_t, std::pair<int32_t, int>> first_owner;
  first_owner.reserve(3 * triangles.size());
  for (int32_t e = 0; e < static_cast<int32_t>(triangles.size()); ++e)
    for (int k = 0; k < 3; ++k) {
      const auto [low, high] = std::minmax(triangles[e][(k + 1) % 3], triangles[e][(k + 2) % 3]);
      const uint64_t key = (static_cast<uint64_t>(low) << 32) | static_cast<uint32_t>(high);
      const auto [found, inserted] = first_owner.try_emplace(key, e, k);
      if (inserted) continue;
      const auto [other, other_k] = found->second;
      if (neighbours[other][other_k] >= 0) return false;  // a third triangle on one edge
      neighbours[e][k] = other;
      neighbours[other][other_k] = e;
    }
  return true;
}

BackgroundMesh background_mesh(const GeoMesh& geo, const PhysicalGroup& domain) {
  std::vector<TriangleTags> tagged;
  for (int surface : domain.entities) {
    if (geo.surfaces_with_other_elements.count(surface))
      throw Error(located(geo.path, "physical surface \"" + domain.name + "\"",
                          "surface " + std::to_string(surface) +
                              " is meshed with elements other than triangles (remove Recombine/Transfinite "
                              "quadrangles: the solver needs linear triangles)"));
    const auto found = geo.surface_triangles.find(surface);
    if (found != geo.surface_triangles.end()) tagged.insert(tagged.end(), found->second.begin(), found->second.end());
  }
  if (tagged.empty())
    throw Error(located(geo.path, "physical surface \"" + domain.name + "\"", "has no triangles after meshing"));

  BackgroundMesh mesh;
  mesh.node_of_tag.assign(geo.node_position.size(), -1);
  for (const auto& triangle : tagged)
    for (NodeTag tag : triangle) mesh.node_of_tag[tag] = 0;
  for (NodeTag tag = 0; tag < mesh.node_of_tag.size(); ++tag)
    if (mesh.node_of_tag[tag] == 0) {
      mesh.node_of_tag[tag] = static_cast<int32_t>(mesh.nodes.size());
      mesh.nodes.push_back(geo.node_position[tag]);
    } else {
      mesh.node_of_tag[tag] = -1;
    }

  mesh.triangles.reserve(tagged.size());
  for (const auto& triangle : tagged) {
    std::array<int32_t, 3> t{mesh.node(triangle[0]), mesh.node(triangle[1]), mesh.node(triangle[2])};
    const Eigen::Vector2d a = mesh.nodes[t[0]], b = mesh.nodes[t[1]], c = mesh.nodes[t[2]];
    const double twice_area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (twice_area < 0) std::swap(t[1], t[2]);
    mesh.triangles.push_back(t);
  }
  if (!find_neighbours(mesh.triangles, mesh.neighbours))
    throw Error(located(geo.path, "physical surface \"" + domain.name + "\"",
                        "an edge is shared by more than two triangles (overlapping surfaces in the domain?)"));
  return mesh;
}

std::vector<std::array<std::size_t, 2>> boundary_edges(const BackgroundMesh& mesh) {
  std::vector<std::array<std::size_t, 2>> edges;
  for (std::size_t e = 0; e < mesh.triangles.size(); ++e)
    for (int k = 0; k < 3; ++k)
      if (mesh.neighbours[e][k] < 0)
        edges.push_back({static_cast<std::size_t>(mesh.triangles[e][(k + 1) % 3]),
                         static_cast<std::size_t>(mesh.triangles[e][(k + 2) % 3])});
  return edges;
}

}  // namespace talus::preproc
