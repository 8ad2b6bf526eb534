// The cell passes (interpolation.hpp). Each element's particle count, for the isolated-particle
// rule, and enhanced volumetric strain's sums (Detournay and Dzik 2006; seed section 4; design.md): the
// volumetric strain increment of each cell (volume-weighted over its particles) -> nodes
// (area-weighted over the cells with particles); the stress update takes the mean over each
// particle's stencil nodes (StrainIncrement) as the volumetric part of its increment.
#include <omp.h>

#include <atomic>

#include "solver/interpolation/interpolation.hpp"

namespace talus::solver {

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

void sum_cells(const Mesh& mesh, const Particles& P, bool evs_on, const std::vector<int32_t>& active,
               std::vector<int32_t>& element_count, EvsScratch& evs, const std::vector<Vec4>& d_eps, int threads) {
  const long n = static_cast<long>(P.size());
  const long moving = static_cast<long>(P.moving_count);
  const long elements = static_cast<long>(mesh.element_count());
  const long nodes = static_cast<long>(active.size());
#pragma omp parallel num_threads(threads)
  {
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) element_count[e] = 0;
    // Particles sorted by element come in runs of one cell: each run's count and sums are added
    // once. The strain sums go into each thread's own arrays, then are added in thread order
    // (deterministic); the counts, integers, atomically.
    double* const strain = evs_on ? evs.element_strain[omp_get_thread_num()].data() : nullptr;
    double* const volume = evs_on ? evs.element_volume[omp_get_thread_num()].data() : nullptr;
    // What the sweeps read, taken once in the region (StencilView).
    int32_t* const count = element_count.data();
    const int32_t* const element = P.element.data();
    const double* const particle_volume = P.volume.data();
    const Vec4* const increment = d_eps.data();
    const bool with_strain = evs_on;
    int32_t run_element = -1, run_count = 0;
    double run_strain = 0, run_volume = 0;
    const auto flush = [&](bool sums) {
      if (run_element < 0) return;
      std::atomic_ref<int32_t>(count[run_element]).fetch_add(run_count, std::memory_order_relaxed);
      if (sums) strain[run_element] += run_strain, volume[run_element] += run_volume;
    };
#pragma omp for schedule(static) nowait
    for (long p = 0; p < moving; ++p) {
      const int32_t e = element[p];
      if (e != run_element) {
        flush(with_strain);
        run_element = e, run_count = 0, run_strain = 0, run_volume = 0;
      }
      ++run_count;
      if (with_strain) {
        const double V = particle_volume[p];
        run_strain += V * (increment[p][0] + increment[p][1]);
        run_volume += V;
      }
    }
    flush(with_strain);
    // The fixed bodies' particles (after the moving ones) count, but carry no strain.
    run_element = -1, run_count = 0;
#pragma omp for schedule(static) nowait
    for (long p = moving; p < n; ++p) {
      const int32_t e = element[p];
      if (e != run_element) {
        flush(false);
        run_element = e, run_count = 0;
      }
      ++run_count;
    }
    flush(false);
    if (evs_on) {
#pragma omp barrier
      const std::size_t team = evs.element_strain.size();
#pragma omp for schedule(static)
      for (long e = 0; e < elements; ++e) {
        // An element without particles, which had no EVS volume at the last step either, has
        // nothing to add: no thread summed into it, and its mean and volume are already zero.
        // (Most of a runout scene's mesh is empty.)
        if (element_count[e] == 0 && evs.volume[e] == 0) continue;
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
}

void full_cell_scales(const Mesh& mesh, const Particles& P, double full_fill,
                      std::vector<std::vector<double>>& cell_volume, std::vector<double>& scale, int threads) {
  const long n = static_cast<long>(P.size());
  const long elements = static_cast<long>(mesh.element_count());
#pragma omp parallel num_threads(threads)
  {
    // Each thread sums into its own array (a run of one cell at a time); the arrays are then
    // added in thread order, so the factors do not depend on the schedule.
    std::vector<double>& volume = cell_volume[omp_get_thread_num()];
    int32_t run_element = -1;
    double run_volume = 0;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      const int32_t e = P.element[p];
      if (e != run_element) {
        if (run_element >= 0) volume[run_element] += run_volume;
        run_element = e, run_volume = 0;
      }
      run_volume += P.volume[p];
    }
    if (run_element >= 0) volume[run_element] += run_volume;
#pragma omp barrier
    const std::size_t team = cell_volume.size();
    std::vector<double>& fill = cell_volume[0];  // the sums, then each cell's fill
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) {
      double sum = fill[e];
      for (std::size_t t = 1; t < team; ++t) sum += cell_volume[t][e], cell_volume[t][e] = 0;
      fill[e] = sum / mesh.area[e];
    }
    // Full: the cell and each cell across its edges (inside the mesh) are filled to full_fill.
    // A cell that lost a particle to its neighbour stays full; a cell at a free surface does not.
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) {
      bool full = fill[e] >= full_fill;
      for (int k = 0; k < 3 && full; ++k) {
        const int32_t across = mesh.neighbours[e][k];
        full = across < 0 || fill[across] >= full_fill;
      }
      scale[e] = full ? 1.0 / fill[e] : 1.0;
    }
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) fill[e] = 0;
  }
}

void evs_node_means(const std::vector<int32_t>& active, EvsScratch& evs, int threads) {
  const long nodes = static_cast<long>(active.size());
  // A node without particle volume around it (active for a fixed body only) is read by no
  // moving particle.
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < nodes; ++k) {
    const int32_t i = active[k];
    evs.node_mean[i] = evs.node_area[i] > 0 ? evs.node_strain[i] / evs.node_area[i] : 0;
  }
}

}  // namespace talus::solver
