// The shape-function families: how each sizes the stencil's tables (stencil.hpp). Their entries
// are filled particle by particle by StencilRows::fill, from the relocation or compute_stencil.
#include "solver/interpolation/interpolation.hpp"

namespace talus::solver {

void reset_stencil(Stencil& stencil, ShapeFamily family, const Mesh& mesh, std::size_t particles) {
  stencil.family = family;
  if (family == ShapeFamily::QuadraticBspline) {
    // A row per particle: its 3 x 3 lattice nodes and their gradients, refilled with the weights.
    stencil.width = 9;
    stencil.row_dN.reset();
    stencil.share_gradients(nullptr);
    stencil.inverse_inertia = (4.0 / stencil.lattice.spacing.array().square()).matrix();  // D_p = h^2 / 4 per axis
    resize_rows(stencil, particles);
    return;
  }
  if (family == ShapeFamily::LinearCpdi) {
    // A row per particle: the nodes its domain's three corners reach (at most 3 x 3), refilled.
    stencil.width = 9;
    stencil.row_dN.reset();
    stencil.share_gradients(nullptr);
    stencil.inverse_inertia = Vec2::Zero();
    resize_rows(stencil, particles);
    return;
  }
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

void resize_rows(Stencil& stencil, std::size_t particles) {
  const std::size_t entries = particles * static_cast<std::size_t>(stencil.width);
  stencil.N.resize(entries, 0);
  stencil.row.resize(particles, 0);
  if (!stencil.rows_per_particle()) return;
  stencil.row_node.resize(entries, stencil.family == ShapeFamily::QuadraticBspline ? stencil.lattice.id(0, 0) : 0);
  stencil.own_dN.resize(entries, Vec2::Zero());
  if (stencil.family == ShapeFamily::LinearCpdi) {
    if (stencil.affine) stencil.own_inverse_inertia.resize(particles, Vec4::Zero());
    stencil.corner_element.resize(3 * particles, -1);
  }
}

void compute_stencil(const Mesh& mesh, const Particles& particles, std::size_t begin, std::size_t end,
                     Stencil& stencil, int threads) {
  const long first = static_cast<long>(begin), last = static_cast<long>(end);
  const StencilRows rows(&stencil, &mesh, particles.domain.data());
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long p = first; p < last; ++p) {
    const int32_t e = particles.element[p];
    rows.fill(static_cast<std::size_t>(p), particles.x[p], e, mesh.weights(e, particles.x[p]));
  }
}

}  // namespace talus::solver
