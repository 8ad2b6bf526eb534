// The background mesh as the solver uses it: linear triangles with their precomputed shape
// functions and neighbours for the relocation walk (the nodes' boundary conditions are
// solver/boundary's).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "common/model/model.hpp"

namespace talus::solver {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;  // stress or strain: (xx, yy, zz, xy), tension positive

// Linear triangles. For element e, the shape function of local node k at x is
//   N_k(x) = constant[e][k] + gradient(e, k).x x + gradient(e, k).y y,
// its gradient constant over the element. The gradients are one table, [e * 3 + k], that the
// linear-triangle stencil reads as its own (stencil.hpp): held once, shared by both.
struct Mesh {
  std::vector<Vec2> nodes;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<std::array<int32_t, 3>> neighbours;  // across the edge opposite local node k; -1: boundary
  std::vector<Vec3> constant;
  std::shared_ptr<const std::vector<Vec2>> gradients;  // grad N_k (1/m) of element e at [e * 3 + k]
  std::vector<double> area;
  double h_min = 0;  // smallest element height (twice the area over the longest edge)

  std::size_t node_count() const { return nodes.size(); }
  std::size_t element_count() const { return triangles.size(); }

  Vec3 weights(int32_t e, const Vec2& x) const {
    return barycentric(constant[e], gradients->data() + static_cast<std::size_t>(e) * 3, x);
  }
  Vec2 gradient(int32_t e, int k) const { return (*gradients)[static_cast<std::size_t>(e) * 3 + k]; }
  // The N_k(x) of an element from its constants and its three gradients.
  static Vec3 barycentric(const Vec3& c, const Vec2* g, const Vec2& x) {
    return {c[0] + g[0].x() * x.x() + g[0].y() * x.y(), c[1] + g[1].x() * x.x() + g[1].y() * x.y(),
            c[2] + g[2].x() * x.x() + g[2].y() * x.y()};
  }
};

// The tables of a Mesh that locate() reads, their data pointers taken once: a loop that calls
// locate() for every particle and stores what it finds (the relocation) would otherwise reload
// them through the containers after each store.
struct MeshView {
  explicit MeshView(const Mesh& mesh)
      : constant(mesh.constant.data()), gradients(mesh.gradients->data()), neighbours(mesh.neighbours.data()),
        triangles(mesh.triangles.data()), elements(mesh.element_count()) {}
  Vec3 weights(int32_t e, const Vec2& x) const {
    return Mesh::barycentric(constant[e], gradients + static_cast<std::size_t>(e) * 3, x);
  }
  std::size_t element_count() const { return elements; }

  const Vec3* constant;
  const Vec2* gradients;
  const std::array<int32_t, 3>* neighbours;
  const std::array<int32_t, 3>* triangles;
  std::size_t elements;
};

Mesh build_mesh(const Model& model);

// Walks from element `start` towards x across the edge of the most negative barycentric
// weight. Returns the containing element, or -1 when the walk leaves the domain; `weights`
// (when given) receives x's barycentric weights in the element returned. Inline: the
// relocation calls it for every particle every step.
// `mesh`: a Mesh or a MeshView.
template <class MeshTables>
inline int32_t locate(const MeshTables& mesh, int32_t start, const Vec2& x, Vec3* weights = nullptr) {
  // Barycentric weights slightly below zero still count as inside, so a particle on an edge
  // does not bounce between its two elements.
  constexpr double kTolerance = -1e-12;
  int32_t e = start;
  for (std::size_t hops = 0; hops <= mesh.element_count(); ++hops) {
    const Vec3 w = mesh.weights(e, x);
    int k;
    if (w.minCoeff(&k) >= kTolerance) {
      if (weights) *weights = w;
      return e;
    }
    e = mesh.neighbours[e][k];
    if (e < 0) return -1;
  }
  return -1;
}

}  // namespace talus::solver
