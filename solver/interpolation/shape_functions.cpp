// The shape-function families: how each fills the stencil (stencil.hpp).
#include "solver/interpolation/interpolation.hpp"

namespace talus::solver {

void reset_stencil(Stencil& stencil, ShapeFamily family, const Mesh& mesh, std::size_t particles) {
  stencil.family = family;
  stencil.width = 3;
  stencil.N.assign(particles * stencil.width, 0);
  stencil.row.assign(particles, 0);
  // Linear triangles: row e holds element e's nodes and the gradients of their shape functions,
  // the mesh's table itself.
  stencil.row_node.resize(mesh.element_count() * stencil.width);
  for (std::size_t e = 0; e < mesh.element_count(); ++e)
    for (int k = 0; k < 3; ++k) stencil.row_node[e * 3 + k] = mesh.triangles[e][k];
  stencil.share_gradients(mesh.gradients);
}

void compute_stencil(const Mesh& mesh, const Particles& particles, std::size_t begin, std::size_t end,
                     Stencil& stencil, int threads) {
  const long first = static_cast<long>(begin), last = static_cast<long>(end);
  const StencilRows rows(&stencil);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long p = first; p < last; ++p) {
    const int32_t e = particles.element[p];
    rows.fill(static_cast<std::size_t>(p), particles.x[p], e, mesh.weights(e, particles.x[p]));
  }
}

}  // namespace talus::solver
