#include "solver/stress/stress.hpp"

#include <cmath>

#include "solver/parallel/threads.hpp"

namespace talus::solver {

long update_stresses(Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells,
                     const std::vector<MaterialState>& materials, const std::vector<int32_t>& material_of_body,
                     const std::vector<double>& initial_volume, int threads) {
  const long moving = static_cast<long>(P.moving_count);
  long bad = -1;
  OwnerFirstChunks chunks(moving, threads);
#pragma omp parallel num_threads(threads) reduction(max : bad)
  {
    const StressArrays a(P);
    const Vec4* const d = d_eps.data();
    const MaterialState* const material_of = materials.data();
    const int32_t* const material_index = material_of_body.data();
    const double* const cap = initial_volume.data();
    StrainIncrement increment(cells, P);
    // Plastic particles, which cost more, cluster in the sliding mass, so equal shares of
    // particles are unequal shares of work: each thread does its own share, then helps.
    chunks.for_each([&](long begin, long end) {
      for (long p = begin; p < end; ++p) {
        Vec4& sigma = a.sigma[p];
        if (increment.isolated(p)) {
          sigma.setZero();  // a grain in free flight (step.hpp, is_isolated)
        } else {
          const MaterialState& material = material_of[material_index[a.body[p]]];
          const Vec4 dp = increment(p, d[p]);
          update_stress(material, sigma, dp, a.eps_p[p], a.history_of(p));
          a.volume[p] = grown_volume(a.volume[p], dp[0] + dp[1] + dp[2], cap, a.id[p]);
        }
        if (!std::isfinite(sigma.sum() + a.x[p].sum() + a.v[p].sum()) || !(a.volume[p] > 0)) bad = std::max(bad, p);
      }
    });
  }
  return bad;
}

}  // namespace talus::solver
