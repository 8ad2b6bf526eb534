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

namespace {

// Spreads the 16 low bits of v to the even bits of the result.
uint32_t spread_bits(uint32_t v) {
  v &= 0xffff;
  v = (v | (v << 8)) & 0x00ff00ff;
  v = (v | (v << 4)) & 0x0f0f0f0f;
  v = (v | (v << 2)) & 0x33333333;
  v = (v | (v << 1)) & 0x55555555;
  return v;
}

// Orders the triangles along a Morton (Z-order) curve through their centroids and numbers the
// nodes in the order the triangles first name them. The solver's particles follow the element
// order and its grid phases the node order, so this puts the nodes a run of particles touches
// next to each other in memory, and the nodes that one thread's particles touch in the node
// range the same thread handles.
void order_along_a_curve(BackgroundMesh& mesh) {
  const std::size_t count = mesh.triangles.size();
  Eigen::Vector2d low = mesh.nodes.front(), high = mesh.nodes.front();
  for (const auto& x : mesh.nodes) low = low.cwiseMin(x), high = high.cwiseMax(x);
  const Eigen::Vector2d extent = (high - low).cwiseMax(Eigen::Vector2d::Constant(1e-300));
  // The curve key in the high 32 bits and the triangle in the low ones: one sort of plain
  // integers, ties in the original order.
  const auto cell = [](double u) { return static_cast<uint32_t>(std::clamp(u, 0.0, 1.0) * 65535.0); };
  std::vector<uint64_t> keyed(count);
  for (std::size_t e = 0; e < count; ++e) {
    const auto& t = mesh.triangles[e];
    const Eigen::Vector2d c = (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]]) / 3.0;
    const Eigen::Vector2d unit = (c - low).cwiseQuotient(extent);
    const uint64_t key = spread_bits(cell(unit.x())) | (spread_bits(cell(unit.y())) << 1);
    keyed[e] = (key << 32) | static_cast<uint64_t>(e);
  }
  std::sort(keyed.begin(), keyed.end());

  std::vector<int32_t> new_node(mesh.nodes.size(), -1);
  std::vector<Eigen::Vector2d> nodes;
  nodes.reserve(mesh.nodes.size());
  std::vector<std::array<int32_t, 3>> triangles;
  triangles.reserve(count);
  for (const uint64_t k : keyed) {
    std::array<int32_t, 3> t = mesh.triangles[k & 0xffffffffu];
    for (int32_t& i : t) {
      if (new_node[i] < 0) {
        new_node[i] = static_cast<int32_t>(nodes.size());
        nodes.push_back(mesh.nodes[i]);
      }
      i = new_node[i];
    }
    triangles.push_back(t);
  }
  mesh.nodes.swap(nodes);
  mesh.triangles.swap(triangles);
  for (int32_t& id : mesh.node_of_tag)
    if (id >= 0) id = new_node[id];
}

}  // namespace

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
  order_along_a_curve(mesh);
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
