// The interpolation stencil: for every particle p, the nodes i it exchanges with, the weights
// N_ip and the weight gradients grad N_ip. It is computed once per step, after relocation (and
// after set-up and sorting), and every phase of the step, contact and EVS read only it: a new
// shape-function family is a new way to fill it, not a change to the phases.
//
// Row p holds `width` entries. A family whose particles touch fewer nodes than its width pads
// the row with weight 0 and gradient 0 on one of the particle's own nodes, which adds nothing
// anywhere. The particle's cell (the element that contains it, Particles::element) stays with
// the particles: relocation finds it, and EVS averages over cells.
#pragma once
#include <cstdint>
#include <vector>

#include "solver/mesh.hpp"
#include "solver/particles.hpp"

namespace talus::solver {

enum class ShapeFamily {
  LinearTriangle,  // the containing triangle's three linear shape functions (seed, A.3)
};

struct Stencil {
  ShapeFamily family = ShapeFamily::LinearTriangle;
  int width = 3;                // entries per particle
  std::vector<int32_t> node;    // [p * width + k]
  std::vector<double> N;        // N_ip
  std::vector<Vec2> dN;         // grad N_ip (1/m)

  // Entries of particle p start here.
  std::size_t row(std::size_t p) const { return p * static_cast<std::size_t>(width); }
};

// Sizes the stencil for `particles` particles of the family.
void reset_stencil(Stencil& stencil, ShapeFamily family, std::size_t particles);

// Fills rows [begin, end) from the particles' positions and elements.
void compute_stencil(const Mesh& mesh, const Particles& particles, std::size_t begin, std::size_t end,
                     Stencil& stencil);

// Fills row p only: the relocation loop calls it for each particle it has just located.
inline void compute_stencil_row(const Mesh& mesh, const Vec2& x, int32_t element, std::size_t p, Stencil& stencil) {
  // LinearTriangle is the only family so far; a second one switches on stencil.family here.
  const std::size_t r = stencil.row(p);
  const auto& nodes = mesh.triangles[element];
  const Vec3 w = mesh.weights(element, x);
  for (int k = 0; k < 3; ++k) {
    stencil.node[r + k] = nodes[k];
    stencil.N[r + k] = w[k];
    stencil.dN[r + k] = mesh.gradient(element, k);
  }
}

}  // namespace talus::solver
