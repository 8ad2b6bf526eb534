// The interpolation stencil: for every particle p, the nodes i it exchanges with, the weights
// N_ip and the weight gradients grad N_ip. It is computed once per step, after relocation (and
// after set-up and sorting), and every phase of the step, contact and EVS read only it: a new
// shape-function family is a new way to fill it, not a change to the phases.
//
// Each particle has `width` entries: weights of its own, and node ids and gradients that are a
// row of tables that particles may share (nodes(p) and gradients(p) point at row[p]'s). For
// linear triangles the nodes and the gradients are those of the element, so the tables have
// one row per element, built once, and a particle's row is its element: per particle only the
// weights and the row are stored, and the gradient table is the mesh's own (Mesh::gradients). A family whose nodes or gradients differ per particle (CPDI)
// keeps one row per particle and refills it with the weights. A family whose particles touch
// fewer nodes than its width pads a row with weight 0 and gradient 0 on one of the particle's
// own nodes, which adds nothing anywhere. The particle's cell (the element that contains it, Particles::element) stays with
// the particles: relocation finds it, and EVS averages over cells.
//
// Particles sorted by element come in runs that share a row. The phases use this: P2G and the
// remap's scatter sum a run's contributions and add them to each node once, the kinematics
// computes a run's velocity gradient once, EVS adds a cell's sums once per run. A family with a
// row per particle gets runs of one, which is the particle-by-particle loop.
#pragma once
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "solver/interpolation/mesh.hpp"
#include "solver/step/particles.hpp"

namespace talus::solver {

enum class ShapeFamily {
  LinearTriangle,  // the containing triangle's three linear shape functions (seed, A.3)
};

// The widest stencil a family may have: phases keep per-entry sums of a particle or a run of
// particles on the stack.
constexpr int kMaxStencilWidth = 16;

// Entries a phase keeps for a stencil of width W as with_width gives it: W itself when it is a
// compile-time constant (small arrays the compiler can keep in registers), else the widest.
template <class Width>
constexpr int entries_for() {
  if constexpr (std::is_integral_v<Width>) return kMaxStencilWidth;
  else return Width::value;
}

struct Stencil {
  ShapeFamily family = ShapeFamily::LinearTriangle;
  int width = 3;                  // entries per particle
  std::vector<double> N;          // N_ip, [p * width + k]
  std::vector<int32_t> row;       // [p]: p's row of the shared tables
  std::vector<int32_t> row_node;  // node ids, [row * width + k]
  // grad N_ip (1/m), [row * width + k]: shared, never written through (linear triangles: the
  // mesh's). A copy of the stencil shares it too, so the raw pointer the phases read stays valid.
  std::shared_ptr<const std::vector<Vec2>> row_dN;
  // APIC's inverse inertia, D_p^-1 = inverse_inertia I (Jiang et al. 2015; quadratic B-splines
  // 4 / h^2); 0 for linear shape functions, whose affine matrix is sum v_i grad N_ip^T
  // (to_particles.cpp, affine_matrix).
  double inverse_inertia = 0;
  void share_gradients(std::shared_ptr<const std::vector<Vec2>> table) {
    row_dN = std::move(table);
    dN_ = row_dN->data();
  }

  // The `width` weights, node ids and gradients of particle p, in the order of its entries
  // (StencilView's, below).
  const double* weights(std::size_t p) const;
  const int32_t* nodes(std::size_t p) const;
  const Vec2* gradients(std::size_t p) const;
  const Vec2* gradient_table() const { return dN_; }

 private:
  const Vec2* dN_ = nullptr;  // row_dN->data()
};

// Calls body(W) with the stencil's width W as a compile-time constant for the widths of the
// families so far (std::integral_constant, usable as an int), else as a plain int: the phases'
// loops over a particle's entries then unroll.
template <class Body>
void with_width(const Stencil& stencil, Body&& body) {
  switch (stencil.width) {
    case 3: body(std::integral_constant<int, 3>{}); return;
    default: body(stencil.width); return;
  }
}

// The stencil as a phase's loop reads it: its data pointers taken once, and its width W as
// with_width gives it. Read through the containers (or, inside a parallel region, through the
// region's shared variables), the compiler reloads every pointer after each store the loop
// makes that it cannot tell apart from them (a bool of the loop's own counts as any object).
template <class Width>
class StencilView {
 public:
  StencilView(const Stencil& stencil, Width width)
      : width_(width), N_(stencil.N.data()), row_(stencil.row.data()), row_node_(stencil.row_node.data()),
        dN_(stencil.gradient_table()) {}
  int32_t row(std::size_t p) const { return row_[p]; }
  const double* weights(std::size_t p) const { return N_ + p * static_cast<std::size_t>(width_); }
  const int32_t* nodes(std::size_t p) const { return row_node_ + offset(p); }
  const Vec2* gradients(std::size_t p) const { return dN_ + offset(p); }

 private:
  std::size_t offset(std::size_t p) const {
    return static_cast<std::size_t>(row_[p]) * static_cast<std::size_t>(width_);
  }
  Width width_;
  const double* N_;
  const int32_t* row_;
  const int32_t* row_node_;
  const Vec2* dN_;
};

// The stencil read entry by entry outside the hot loops; the layout is StencilView's alone.
inline const double* Stencil::weights(std::size_t p) const { return StencilView(*this, width).weights(p); }
inline const int32_t* Stencil::nodes(std::size_t p) const { return StencilView(*this, width).nodes(p); }
inline const Vec2* Stencil::gradients(std::size_t p) const { return StencilView(*this, width).gradients(p); }

// Fills particle p's entries from where it is: its position x, the element that contains it and
// x's barycentric weights there, which the relocation walk finds anyway (relocate.cpp,
// compute_stencil). StencilRows holds the stencil's data pointers, taken once (StencilView), for
// a loop that fills a row for every particle; a null stencil fills nothing.
class StencilRows {
 public:
  explicit StencilRows(Stencil* stencil)
      : N_(stencil ? stencil->N.data() : nullptr), row_(stencil ? stencil->row.data() : nullptr) {}
  void fill(std::size_t p, const Vec2& x, int32_t element, const Vec3& barycentric) const {
    // Linear triangles (the only family so far; a second one switches on Stencil::family here):
    // the weights are the barycentric ones and the row is the element's.
    double* N = N_ + p * 3;
    for (int k = 0; k < 3; ++k) N[k] = barycentric[k];
    row_[p] = element;  // the element's row of the tables reset_stencil built
  }

 private:
  double* N_;
  int32_t* row_;
};

}  // namespace talus::solver
