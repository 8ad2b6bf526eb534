// Enhanced volumetric strain against the volumetric locking of linear triangles (Detournay and
// Dzik 2006; seed section 4; design.md): the volumetric strain increment of each cell
// (volume-weighted over its particles) -> nodes (area-weighted over the cells with particles)
// -> back to each particle as the mean over its stencil's nodes (for linear triangles: its
// cell's three nodes) -> replaces the volumetric part of the particle's increment.
#include <omp.h>

#include "solver/step.hpp"

namespace talus::solver {

void enhance_volumetric_strain(const Mesh& mesh, const Particles& P, const Stencil& S,
                               const std::vector<int32_t>& active, EvsScratch& evs, std::vector<Vec4>& d_eps,
                               int threads) {
  evs_node_sums(mesh, P, active, evs, d_eps, threads);
  apply_evs(P, S, evs, d_eps, threads);
}

void evs_node_sums(const Mesh& mesh, const Particles& P, const std::vector<int32_t>& active, EvsScratch& evs,
                   const std::vector<Vec4>& d_eps, int threads) {
  const long moving = static_cast<long>(P.moving_count);
  const long elements = static_cast<long>(mesh.element_count());
  // Cell sums: each thread into its own arrays, then added in thread order (deterministic).
#pragma omp parallel num_threads(threads)
  {
    std::vector<double>& strain = evs.element_strain[omp_get_thread_num()];
    std::vector<double>& volume = evs.element_volume[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      const int32_t e = P.element[p];
      const double V = P.volume[p];
      strain[e] += V * (d_eps[p][0] + d_eps[p][1]);
      volume[e] += V;
    }
    const std::size_t team = evs.element_strain.size();
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) {
      double strain_sum = 0, volume_sum = 0;
      for (std::size_t t = 0; t < team; ++t) {
        strain_sum += evs.element_strain[t][e];
        volume_sum += evs.element_volume[t][e];
        evs.element_strain[t][e] = evs.element_volume[t][e] = 0;
      }
      evs.strain[e] = strain_sum;
      evs.volume[e] = volume_sum;
    }
  }
  for (int32_t i : active) evs.node_strain[i] = evs.node_area[i] = 0;
  for (long e = 0; e < elements; ++e) {
    if (evs.volume[e] <= 0) continue;
    const double strain = evs.strain[e] / evs.volume[e];
    for (int32_t i : mesh.triangles[e]) {
      evs.node_strain[i] += mesh.area[e] * strain;
      evs.node_area[i] += mesh.area[e];
    }
  }
}

void apply_evs(const Particles& P, const Stencil& S, const EvsScratch& evs, std::vector<Vec4>& d_eps, int threads) {
  const long moving = static_cast<long>(P.moving_count);
  const int W = S.width;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long p = 0; p < moving; ++p) {
    const int32_t* nodes = S.nodes(p);
    double smoothed = 0;
    for (int k = 0; k < W; ++k) smoothed += evs.node_strain[nodes[k]] / evs.node_area[nodes[k]];
    smoothed /= W;
    Vec4& d = d_eps[p];
    const double correction = 0.5 * (smoothed - (d[0] + d[1]));  // in-plane, so d_eps_zz stays 0
    d[0] += correction;
    d[1] += correction;
  }
}

}  // namespace talus::solver
