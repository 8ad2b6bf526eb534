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
#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "solver/interpolation/lattice.hpp"
#include "solver/interpolation/mesh.hpp"
#include "solver/step/particles.hpp"

namespace talus::solver {

enum class ShapeFamily {
  LinearTriangle,    // the containing triangle's three linear shape functions (seed, A.3)
  QuadraticBspline,  // tensor-product quadratic B-splines on the grid pattern's lattice (bspline.cpp)
  LinearCpdi,        // the linear triangles averaged over a triangular domain per particle (fill_cpdi)
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
  // grad N_ip of a family whose gradients differ per particle (B-splines), [p * width + k]: the
  // stencil's own (a copy of the stencil copies it); empty otherwise.
  std::vector<Vec2> own_dN;
  // APIC's inverse inertia D_p^-1, diagonal (Jiang et al. 2015; quadratic B-splines 4 / h^2 per
  // axis); zero for linear shape functions, whose affine matrix is sum v_i grad N_ip^T
  // (to_particles.cpp, affine_matrix).
  Vec2 inverse_inertia = Vec2::Zero();
  // CPDI: each particle's own D_p^-1 = (sum_i S_ip (x_i - x_p)(x_i - x_p)^T)^-1 as (xx, xy, yx,
  // yy), [p]; the domain keeps D_p away from singular. Empty for the other families and without
  // `affine`.
  std::vector<Vec4> own_inverse_inertia;
  // The transfer carries an affine velocity (APIC), so CPDI's rows keep own_inverse_inertia;
  // with the other transfers it is neither sized nor filled. Set before reset_stencil.
  bool affine = false;
  // CPDI: the element each domain corner was found in, [3 p + c], when the row was filled with
  // the domain at its full size (every corner's element then shares a node with the particle's,
  // so its nodes are in the row); -1 when the domain was shrunk. move_domains interpolates the
  // corner velocities there instead of locating the corners again. Empty for the other families.
  std::vector<int32_t> corner_element;
  Lattice lattice;  // QuadraticBspline: the grid pattern's, with its ghost layer
  void share_gradients(std::shared_ptr<const std::vector<Vec2>> table) {
    row_dN = std::move(table);
    dN_ = row_dN ? row_dN->data() : nullptr;
  }

  // The `width` weights, node ids and gradients of particle p, in the order of its entries
  // (StencilView's, below).
  const double* weights(std::size_t p) const;
  const int32_t* nodes(std::size_t p) const;
  const Vec2* gradients(std::size_t p) const;
  const Vec2* gradient_table() const { return own_dN.empty() ? dN_ : own_dN.data(); }
  bool rows_per_particle() const { return family != ShapeFamily::LinearTriangle; }

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
    case 9: body(std::integral_constant<int, 9>{}); return;
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
  // `mesh` and `domain` (the particles' domain corners, Particles::domain): for CPDI, whose
  // corners are located in the mesh; the other families do not read them.
  StencilRows(Stencil* stencil, const Mesh* mesh = nullptr, const Vec2* domain = nullptr)
      : N_(stencil ? stencil->N.data() : nullptr), row_(stencil ? stencil->row.data() : nullptr),
        family_(stencil ? stencil->family : ShapeFamily::LinearTriangle),
        node_(stencil ? stencil->row_node.data() : nullptr),
        dN_(stencil && !stencil->own_dN.empty() ? stencil->own_dN.data() : nullptr),
        lattice_(stencil ? &stencil->lattice : nullptr), mesh_(mesh), domain_(domain),
        own_inverse_(stencil && !stencil->own_inverse_inertia.empty() ? stencil->own_inverse_inertia.data()
                                                                       : nullptr),
        corner_element_(stencil && !stencil->corner_element.empty() ? stencil->corner_element.data() : nullptr) {}
  void fill(std::size_t p, const Vec2& x, int32_t element, const Vec3& barycentric) const {
    if (family_ == ShapeFamily::QuadraticBspline) return fill_bspline(p, x);
    if (family_ == ShapeFamily::LinearCpdi) return fill_cpdi(p, x, element, barycentric);
    // Linear triangles: the weights are the barycentric ones and the row is the element's.
    double* N = N_ + p * 3;
    for (int k = 0; k < 3; ++k) N[k] = barycentric[k];
    row_[p] = element;  // the element's row of the tables reset_stencil built
  }

 private:
  // Quadratic B-splines (e.g. Steffen, Kirby and Berzins 2008): along each axis the particle at
  // lattice coordinate g (cells from the origin) reaches the three nodes b, b + 1, b + 2 with
  // b = floor(g - 1/2); with f = g - b in [1/2, 3/2) their weights are (3/2 - f)^2 / 2,
  // 3/4 - (f - 1)^2 and (f - 1/2)^2 / 2, which sum to 1 and are C1 across the cells. The 3 x 3
  // products are the weights, entry k = 3 b + a for node (b_x + a, b_y + b); the row is p's own.
  void fill_bspline(std::size_t p, const Vec2& x) const {
    const Lattice& L = *lattice_;
    double w[2][3], dw[2][3];
    int base[2];
    for (int d = 0; d < 2; ++d) {
      const double g = (x[d] - L.origin[d]) / L.spacing[d];
      base[d] = static_cast<int>(std::floor(g - 0.5));
      const double f = g - base[d];
      w[d][0] = 0.5 * (1.5 - f) * (1.5 - f);
      w[d][1] = 0.75 - (f - 1) * (f - 1);
      w[d][2] = 0.5 * (f - 0.5) * (f - 0.5);
      dw[d][0] = (f - 1.5) / L.spacing[d];
      dw[d][1] = -2 * (f - 1) / L.spacing[d];
      dw[d][2] = (f - 0.5) / L.spacing[d];
    }
    double* N = N_ + p * 9;
    int32_t* nodes = node_ + p * 9;
    Vec2* dN = dN_ + p * 9;
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        const int k = 3 * b + a;
        N[k] = w[0][a] * w[1][b];
        nodes[k] = L.id(base[0] + a, base[1] + b);
        dN[k] = Vec2(dw[0][a] * w[1][b], w[0][a] * dw[1][b]);
      }
    row_[p] = static_cast<int32_t>(p);
  }

  // CPDI on linear triangles (Sadeghirad, Brannon and Burghardt 2011; with triangular domains,
  // Sadeghirad, Brannon and Guilkey 2013): each particle has a triangular domain, its corners
  // y_c (Particles::domain) moved with the grid velocity (move_domains), so that domains that
  // tile the body at the start keep tiling it. With N_i(y_c) the linear shape functions at the
  // corners and lambda_c the domain's own barycentric functions,
  //   S_ip = 1/3 sum_c N_i(y_c),   grad S_ip = sum_c N_i(y_c) grad lambda_c,
  // the mean over the domain of the linear interpolant of N_i's corner values and its gradient:
  // a partition of unity that reproduces affine fields (sum_i x_i S_ip = the domain's centroid,
  // the particle; sum_i x_i grad S_ip^T = I) and whose gradient changes continuously as the
  // domain crosses an edge, which is what removes the cell-crossing error. A corner must lie in
  // an element that shares a node with the particle's (so that a rank's halo, the nodes of the
  // elements around its own, holds every node its particles reach); where one does not, or lies
  // outside the mesh, the domain shrinks about the particle for this step (by bisection, to
  // 1/64) until every corner does, and a particle on the boundary itself keeps the linear
  // weights of its element. Entries of the same node add; the rest pad the row.
  void fill_cpdi(std::size_t p, const Vec2& x, int32_t element, const Vec3& barycentric) const {
    constexpr int kWidth = 9;
    const MeshView mesh(*mesh_);
    double* N = N_ + p * kWidth;
    int32_t* nodes = node_ + p * kWidth;
    Vec2* dN = dN_ + p * kWidth;
    row_[p] = static_cast<int32_t>(p);
    const Vec2* corner = domain_ + p * 3;
    int32_t corner_element[3];
    Vec3 corner_weight[3];
    auto corners_at = [&](double scale, int32_t* ce, Vec3* cw) {
      const auto& own = mesh.triangles[element];
      for (int c = 0; c < 3; ++c) {
        const int32_t e = locate(mesh, element, Vec2(x + scale * (corner[c] - x)), &cw[c]);
        if (e < 0) return false;
        const auto& t = mesh.triangles[e];
        bool shares = false;
        for (int i = 0; i < 3 && !shares; ++i)
          for (int j = 0; j < 3; ++j) shares = shares || t[i] == own[j];
        if (!shares) return false;
        ce[c] = e;
      }
      return true;
    };
    double scale = 1;
    if (!corners_at(scale, corner_element, corner_weight)) {
      double inside = 0, outside = 1;
      int32_t trial_element[3];
      Vec3 trial_weight[3];
      for (int halving = 0; halving < 6; ++halving) {
        const double mid = 0.5 * (inside + outside);
        if (corners_at(mid, trial_element, trial_weight)) {
          inside = mid;
          for (int c = 0; c < 3; ++c) corner_element[c] = trial_element[c], corner_weight[c] = trial_weight[c];
        } else {
          outside = mid;
        }
      }
      scale = inside;
    }
    Vec2 y[3];
    for (int c = 0; c < 3; ++c) y[c] = x + scale * (corner[c] - x);
    const double twice_area = (y[1] - y[0]).x() * (y[2] - y[0]).y() - (y[1] - y[0]).y() * (y[2] - y[0]).x();
    const bool full_size = scale == 1 && std::abs(twice_area) > 0;
    for (int c = 0; c < 3; ++c) corner_element_[3 * p + c] = full_size ? corner_element[c] : -1;
    int used = 0;
    if (scale <= 0 || !(std::abs(twice_area) > 0)) {  // on the boundary: the element's linear weights
      for (int k = 0; k < 3; ++k) {
        N[k] = barycentric[k];
        nodes[k] = mesh.triangles[element][k];
        dN[k] = mesh.gradients[static_cast<std::size_t>(element) * 3 + k];
      }
      used = 3;
    } else {
      Vec2 grad_lambda[3];
      for (int c = 0; c < 3; ++c) {
        const Vec2& a = y[(c + 1) % 3];
        const Vec2& b = y[(c + 2) % 3];
        grad_lambda[c] = Vec2(a.y() - b.y(), b.x() - a.x()) / twice_area;
      }
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) {
          const int32_t node = mesh.triangles[corner_element[c]][k];
          const double n = corner_weight[c][k];
          int slot = 0;
          while (slot < used && nodes[slot] != node) ++slot;
          if (slot == used) {
            nodes[slot] = node;
            N[slot] = 0;
            dN[slot] = Vec2::Zero();
            ++used;
          }
          N[slot] += n / 3;
          dN[slot] += n * grad_lambda[c];
        }
    }
    for (int k = used; k < kWidth; ++k) {
      N[k] = 0;
      nodes[k] = nodes[0];
      dN[k] = Vec2::Zero();
    }
    // APIC's inertia D_p; where it is singular (a particle on the boundary at a node) the
    // inverse is zero and C_p falls to zero for that step.
    if (!own_inverse_) return;
    double dxx = 0, dxy = 0, dyy = 0;
    for (int k = 0; k < used; ++k) {
      const Vec2 r = mesh_->nodes[nodes[k]] - x;
      dxx += N[k] * r.x() * r.x(), dxy += N[k] * r.x() * r.y(), dyy += N[k] * r.y() * r.y();
    }
    const double det = dxx * dyy - dxy * dxy;
    own_inverse_[p] = Vec4::Zero();
    if (det > 1e-12 * (dxx + dyy) * (dxx + dyy)) own_inverse_[p] = Vec4(dyy, -dxy, -dxy, dxx) / det;
  }

  double* N_;
  int32_t* row_;
  ShapeFamily family_;
  int32_t* node_;
  Vec2* dN_;
  const Lattice* lattice_;
  const Mesh* mesh_;
  const Vec2* domain_;
  Vec4* own_inverse_;
  int32_t* corner_element_;
};

}  // namespace talus::solver
