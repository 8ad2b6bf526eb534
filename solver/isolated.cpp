// Isolated particles (docs/transfer.md, "Isolated particles"). A particle alone in its element
// is a grain in free flight, not a piece of a continuum: the nodes it shares with a wall or with
// the body it left give it strain increments that no neighbour balances, and with a frictional
// material (tension cut off at the apex, compression kept) those increments ratchet up a
// compressive stress many times the overburden that the grain later releases in one step
// (measured on the column collapse: -20 kPa in a grain that left a 0.1 m column, whose weight
// gives at most 1.5 kPa). So an isolated particle carries no stress and keeps its volume.
// "Alone" needs particles smaller than their element: with one particle per cell every particle
// is alone, so a particle is isolated only when it also fills less than half of its element.
#include <atomic>

#include "solver/step.hpp"

namespace talus::solver {

void find_isolated_particles(const Mesh& mesh, const Particles& P, std::vector<int32_t>& element_count,
                             std::vector<uint8_t>& isolated, int threads) {
  const long elements = static_cast<long>(element_count.size());
  const long n = static_cast<long>(P.size());
  const long moving = static_cast<long>(P.moving_count);
#pragma omp parallel num_threads(threads)
  {
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) element_count[e] = 0;
    // Particles sorted by element come in runs of one cell: one atomic add per run.
    int32_t run_element = -1, run_count = 0;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < n; ++p) {
      const int32_t e = P.element[p];
      if (e != run_element) {
        if (run_element >= 0)
          std::atomic_ref<int32_t>(element_count[run_element]).fetch_add(run_count, std::memory_order_relaxed);
        run_element = e, run_count = 0;
      }
      ++run_count;
    }
    if (run_element >= 0)
      std::atomic_ref<int32_t>(element_count[run_element]).fetch_add(run_count, std::memory_order_relaxed);
#pragma omp barrier
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      const int32_t e = P.element[p];
      isolated[p] = element_count[e] == 1 && 2 * P.volume[p] < mesh.area[e];
    }
  }
}

}  // namespace talus::solver
