// Relocation: each moving particle's element after (A.12)'s move, found by a neighbour walk from
// the element it was in (the CFL step keeps it within about one element), and its stencil row.
// A particle that leaves the domain is reported, never dropped.
#include "solver/interpolation/interpolation.hpp"

namespace talus::solver {
namespace {

// The neighbour walk of every moving particle to its element; with a stencil, in the same pass,
// the particle's row from the walk's last weights, which are its stencil weights in that element.
// (The walk and the stencil were two passes; one runs 300 million fewer instructions over 150
// steps of the 48,812-particle slope, docs/benchmarks.md.) Returns the last particle that left
// the domain, or -1. A template, so that the walk alone tests nothing per particle.
template <bool kWithStencil>
long walk_to_elements(const Mesh& mesh, Particles& P, Stencil* stencil, int threads) {
  long lost = -1;
#pragma omp parallel num_threads(threads) reduction(max : lost)
  {
    // What the loop reads, taken once in the region (MeshView, StencilView).
    const MeshView tables(mesh);
    const long moving = static_cast<long>(P.moving_count);
    const Vec2* const position = P.x.data();
    int32_t* const element = P.element.data();
    StencilRows rows(stencil, &mesh, P.domain.data());
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      Vec3 w;
      const int32_t e = locate(tables, element[p], position[p], &w);
      if (e < 0) {
        lost = std::max(lost, p);
        continue;
      }
      element[p] = e;
      if constexpr (kWithStencil) rows.fill(static_cast<std::size_t>(p), position[p], e, w);
    }
  }
  return lost;
}

}  // namespace

long relocate_particles(const Mesh& mesh, Particles& P, Stencil& stencil, int threads) {
  return walk_to_elements<true>(mesh, P, &stencil, threads);
}

long locate_particles(const Mesh& mesh, Particles& P, int threads) {
  return walk_to_elements<false>(mesh, P, nullptr, threads);
}

}  // namespace talus::solver
