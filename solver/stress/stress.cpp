#include "solver/stress/stress.hpp"

#include <algorithm>
#include <cmath>

#include "solver/parallel/threads.hpp"
#include "solver/stress/water.hpp"

namespace talus::solver {
namespace {

// The loop for a scene with or without water (kWater), per-particle properties (kProperties)
// and materials' history variables (kHistory): chosen once per step, so that a run without them
// runs none of their code (not even the address of a particle's history row).
template <bool kWater, bool kProperties, bool kHistory>
long stress_loop(Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells, const Config& config,
                 double t, double dt, int threads) {
  const long moving = static_cast<long>(P.moving_count);
  const bool undrained = kWater && config.water.mode == WaterMode::Undrained;
  const WaterTableNow table = kWater ? WaterTableNow(config, t) : WaterTableNow{};
  // u times the normal components: a vector product, where a Vec4 built from scalars would go
  // through the stack and stall the store forwarding of its 16-byte loads.
  const Vec4 normal(1, 1, 1, 0);
  // Each body's material, resolved once: one load per particle.
  std::vector<const MaterialState*> state_of_body;
  for (int32_t m : config.material_of_body) state_of_body.push_back(&config.materials[m]);
  long bad = -1;
  OwnerFirstChunks chunks(moving, threads);
#pragma omp parallel num_threads(threads) reduction(max : bad)
  {
    // The arrays, read once (StressArrays, stress.hpp).
    const StressArrays a(P);
    const Vec4* const d = d_eps.data();
    const MaterialState* const* const material_of_body = state_of_body.data();
    const double* const initial_volume = config.initial_volume.data();
    double* const pore_pressure = kWater ? P.pore_pressure.data() : nullptr;
    double* const excess = undrained ? P.excess_pore_pressure.data() : nullptr;
    StrainIncrement increment(cells, P);
    // Plastic particles, which cost more, cluster in the sliding mass, so equal shares of
    // particles are unequal shares of work: each thread does its own share, then helps.
    chunks.for_each([&](long begin, long end) {
      for (long p = begin; p < end; ++p) {
        Vec4& sigma = a.sigma[p];  // with water total, effective in between (in place: a copy measured slower)
        [[maybe_unused]] double u = 0;
        if (increment.isolated(p)) {
          sigma.setZero();  // a grain in free flight (stress.hpp, is_isolated)
          // With APIC, no affine velocity from a held node (stress.hpp, reaches_held_node).
          if (!P.C.empty() && reaches_held_node(config.constraints, cells.stencil, p)) P.C[p].setZero();
          if constexpr (kWater) u = table.pore_pressure(a.x[p]);
        } else {
          const MaterialState& material = *material_of_body[a.body[p]];
          const Vec4 dp = increment(p, d[p]);
          if constexpr (kWater) sigma += pore_pressure[p] * normal;
          double* history = kHistory ? a.history + static_cast<std::size_t>(p) * a.history_width : nullptr;
          // A particle with its own properties has its own prepared state.
          const ParticleMaterial* own =
              kProperties && !material.row_of_id.empty() ? &material.of_particle(a.id[p]) : nullptr;
          update_stress(own ? own->prepared : material.prepared, sigma, dp, dt, a.eps_p[p], history);
          const double volumetric = dp[0] + dp[1] + dp[2];
          if constexpr (kWater) {
            // The new pore pressure after the material's call, so that less lives across it.
            u = table.pore_pressure(a.x[p]);
            if (undrained) {
              excess[p] -= (own ? own->pore_stiffness : material.pore_stiffness) * volumetric;
              u += excess[p];
            }
            sigma -= u * normal;
          }
          a.volume[p] = grown_volume(a.volume[p], volumetric, initial_volume, a.id[p]);
        }
        if constexpr (kWater) {
          pore_pressure[p] = u;
          if (!std::isfinite(sigma.sum() + a.x[p].sum() + a.v[p].sum() + u) || !(a.volume[p] > 0)) bad = std::max(bad, p);
        } else {
          if (!std::isfinite(sigma.sum() + a.x[p].sum() + a.v[p].sum()) || !(a.volume[p] > 0)) bad = std::max(bad, p);
        }
      }
    });
  }
  return bad;
}

// stress_loop<kWater, kProperties, kHistory> for the flags of this run.
template <bool... kFlags>
long dispatch(const bool* flags, Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells,
              const Config& config, double t, double dt, int threads) {
  if constexpr (sizeof...(kFlags) == 3) {
    return stress_loop<kFlags...>(P, d_eps, cells, config, t, dt, threads);
  } else {
    return *flags ? dispatch<kFlags..., true>(flags + 1, P, d_eps, cells, config, t, dt, threads)
                  : dispatch<kFlags..., false>(flags + 1, P, d_eps, cells, config, t, dt, threads);
  }
}

}  // namespace

long update_stresses(Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells, const Config& config,
                     double t, double dt, int threads) {
  const bool flags[3] = {config.water.enabled(), !P.properties.empty(), P.history_width > 0};
  return dispatch(flags, P, d_eps, cells, config, t, dt, threads);
}

}  // namespace talus::solver
