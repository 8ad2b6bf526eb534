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
  apply_evs(P, S, active, evs, d_eps, threads);
}

void evs_adjacency(const Mesh& mesh, EvsScratch& evs) {
  evs.node_first.assign(mesh.node_count() + 1, 0);
  for (const auto& triangle : mesh.triangles)
    for (int32_t i : triangle) ++evs.node_first[static_cast<std::size_t>(i) + 1];
  for (std::size_t i = 0; i < mesh.node_count(); ++i) evs.node_first[i + 1] += evs.node_first[i];
  evs.node_elements.resize(static_cast<std::size_t>(evs.node_first.back()));
  std::vector<int32_t> next(evs.node_first.begin(), evs.node_first.end() - 1);
  for (std::size_t e = 0; e < mesh.element_count(); ++e)  // ascending: each node's list is sorted
    for (int32_t i : mesh.triangles[e]) evs.node_elements[static_cast<std::size_t>(next[i]++)] = static_cast<int32_t>(e);
}

void evs_node_sums(const Mesh& mesh, const Particles& P, const std::vector<int32_t>& active, EvsScratch& evs,
                   const std::vector<Vec4>& d_eps, int threads) {
  const long moving = static_cast<long>(P.moving_count);
  const long elements = static_cast<long>(mesh.element_count());
  const long nodes = static_cast<long>(active.size());
  // Cell sums: each thread into its own arrays, then added in thread order (deterministic).
#pragma omp parallel num_threads(threads)
  {
    std::vector<double>& strain = evs.element_strain[omp_get_thread_num()];
    std::vector<double>& volume = evs.element_volume[omp_get_thread_num()];
    // Particles sorted by element come in runs of one cell: each run's sums are added once.
    int32_t run_element = -1;
    double run_strain = 0, run_volume = 0;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < moving; ++p) {
      const int32_t e = P.element[p];
      if (e != run_element) {
        if (run_element >= 0) strain[run_element] += run_strain, volume[run_element] += run_volume;
        run_element = e, run_strain = 0, run_volume = 0;
      }
      const double V = P.volume[p];
      run_strain += V * (d_eps[p][0] + d_eps[p][1]);
      run_volume += V;
    }
    if (run_element >= 0) strain[run_element] += run_strain, volume[run_element] += run_volume;
#pragma omp barrier
    const std::size_t team = evs.element_strain.size();
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) {
      double strain_sum = 0, volume_sum = 0;
      for (std::size_t t = 0; t < team; ++t) {
        strain_sum += evs.element_strain[t][e];
        volume_sum += evs.element_volume[t][e];
        evs.element_strain[t][e] = evs.element_volume[t][e] = 0;
      }
      evs.strain[e] = volume_sum > 0 ? strain_sum / volume_sum : 0;  // the cell average
      evs.volume[e] = volume_sum;
    }
    // Area-weighted at the nodes: each active node gathers its cells with particles, in
    // ascending element order (the order of a scatter over the elements).
#pragma omp for schedule(static)
    for (long k = 0; k < nodes; ++k) {
      const int32_t i = active[k];
      double node_strain = 0, node_area = 0;
      for (int32_t j = evs.node_first[i]; j < evs.node_first[i + 1]; ++j) {
        const int32_t e = evs.node_elements[j];
        if (evs.volume[e] <= 0) continue;
        node_strain += mesh.area[e] * evs.strain[e];
        node_area += mesh.area[e];
      }
      evs.node_strain[i] = node_strain;
      evs.node_area[i] = node_area;
    }
  }
}

void apply_evs(const Particles& P, const Stencil& S, const std::vector<int32_t>& active, EvsScratch& evs,
               std::vector<Vec4>& d_eps, int threads) {
  const long moving = static_cast<long>(P.moving_count);
  const long nodes = static_cast<long>(active.size());
  const int W = S.width;
#pragma omp parallel num_threads(threads)
  {
    // A node without particle volume around it (active for a fixed body only) is read by no
    // moving particle.
#pragma omp for schedule(static)
    for (long k = 0; k < nodes; ++k) {
      const int32_t i = active[k];
      evs.node_mean[i] = evs.node_area[i] > 0 ? evs.node_strain[i] / evs.node_area[i] : 0;
    }
    // The mean over a stencil row's nodes, once per run of particles that share the row.
    int32_t run_row = -1;
    double smoothed = 0;
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      if (S.row[p] != run_row) {
        run_row = S.row[p];
        const int32_t* nodes_of_p = S.nodes(p);
        smoothed = 0;
        for (int k = 0; k < W; ++k) smoothed += evs.node_mean[nodes_of_p[k]];
        smoothed /= W;
      }
      Vec4& d = d_eps[p];
      const double correction = 0.5 * (smoothed - (d[0] + d[1]));  // in-plane, so d_eps_zz stays 0
      d[0] += correction;
      d[1] += correction;
    }
  }
}

}  // namespace talus::solver
