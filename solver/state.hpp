// The solver's data: background mesh with precomputed element geometry, particles as a
// struct of arrays, and grid fields as dense per-node arrays. Plain data, no behaviour beyond
// small inline accessors: the phases of the step (step.hpp) operate on it.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "common/model.hpp"

namespace talus::solver {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;  // stress or strain: (xx, yy, zz, xy), tension positive

// Linear triangles. For element e, the shape function of local node k at x is
//   N_k(x) = shape[e](k,0) + shape[e](k,1) x + shape[e](k,2) y,
// so its gradient, constant over the element, is (shape[e](k,1), shape[e](k,2)).
struct Mesh {
  std::vector<Vec2> nodes;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<std::array<int32_t, 3>> neighbours;  // across the edge opposite local node k; -1: boundary
  std::vector<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> shape;
  std::vector<double> area;
  double h_min = 0;  // smallest element height (twice the area over the longest edge)

  std::size_t node_count() const { return nodes.size(); }
  std::size_t element_count() const { return triangles.size(); }

  Vec3 weights(int32_t e, const Vec2& x) const {
    const auto& c = shape[e];
    return {c(0, 0) + c(0, 1) * x.x() + c(0, 2) * x.y(), c(1, 0) + c(1, 1) * x.x() + c(1, 2) * x.y(),
            c(2, 0) + c(2, 1) * x.x() + c(2, 2) * x.y()};
  }
  Vec2 gradient(int32_t e, int k) const { return {shape[e](k, 1), shape[e](k, 2)}; }
};

Mesh build_mesh(const Model& model);

// Walks from element `start` towards x across the edge of the most negative barycentric
// weight. Returns the containing element, or -1 when the walk leaves the domain.
int32_t locate(const Mesh& mesh, int32_t start, const Vec2& x);

// Particles: one array per field. Particles of fixed bodies are kept after all the others
// (indices [moving_count, size)), so the update loops run over [0, moving_count) only.
struct Particles {
  std::vector<Vec2> x, v;             // position (m), velocity (m/s)
  std::vector<double> m, volume;      // mass (kg/m), volume (m^2 per m thickness)
  std::vector<Vec4> sigma;            // Cauchy stress (Pa)
  std::vector<double> eps_p;          // equivalent plastic shear strain (-)
  std::vector<Vec4> d_eps;            // this step's strain increment (scratch)
  std::vector<int32_t> body, element;
  std::vector<int32_t> id;            // index in the model's (and the results') order
  std::size_t moving_count = 0;

  std::size_t size() const { return x.size(); }
};

// Node fields of the whole system. Reset each step only where active.
struct Grid {
  std::vector<double> m;   // lumped mass (A.6)
  std::vector<Vec2> p;     // momentum
  std::vector<Vec2> f;     // total force, internal (A.8) plus external (A.7)
  std::vector<Vec2> a;     // acceleration
  std::vector<Vec2> v;     // velocity after the remap (A.11)
  std::vector<Vec2> mass_gradient;  // sum m_p grad N_ip: the outward normal (contact only)
  std::vector<int32_t> active;  // nodes touched by particles this step
};

// Per-node boundary constraints: 0 free, 1 fixed, 2 roller along `normal`.
struct Constraints {
  std::vector<uint8_t> kind;
  std::vector<Vec2> normal;
};

Constraints build_constraints(const Model& model);

}  // namespace talus::solver
