#include "solver/stress/water.hpp"

#include <algorithm>
#include <cmath>

#include "solver/parallel/threads.hpp"
#include "solver/stress/stress.hpp"

namespace talus::solver {

double gravity_fraction(const Config& config, double t) {
  if (t >= config.gravity_ramp) return 1;
  return 0.5 * (1 - std::cos(M_PI * t / config.gravity_ramp));
}

void initial_pore_pressures(Particles& P, const Config& config, double t) {
  if (!config.water.enabled()) return;
  const std::size_t n = P.size();
  P.pore_pressure.resize(n);
  for (std::size_t p = 0; p < n; ++p) P.pore_pressure[p] = hydrostatic_pore_pressure(config, P.x[p], t);
  if (config.water.mode == WaterMode::Undrained) P.excess_pore_pressure.assign(n, 0);
}

void prepare_materials(Config& config, const Model& model) {
  // Element size for the regularisation: the mean of sqrt(2 A), the leg of a right isosceles
  // triangle of the same area.
  double size = 0;
  for (double area : config.mesh.area) size += std::sqrt(2 * area);
  size /= std::max<std::size_t>(config.mesh.area.size(), 1);
  for (std::size_t i = 0; i < config.materials.size(); ++i) {
    MaterialState& state = config.materials[i];
    const Material& material = model.materials[i];
    if (state.softening && material.softening_reference_size > 0 && size > 0) {
      const double scale = material.softening_reference_size / size;
      state.softening_start = material.softening_start * scale;
      state.softening_end = material.softening_end * scale;
    }
    if (config.water.enabled() && config.water.mode == WaterMode::Undrained && material.porosity > 0) {
      state.pore_stiffness = config.water.bulk_modulus / material.porosity;
      // The undrained mixture is stiffer: its P-wave speed sets the time step.
      state.wave_speed = std::sqrt((state.bulk_modulus + state.pore_stiffness + 4 * state.shear_modulus / 3) /
                                   material.density);
    }
  }
}

namespace {

// The table at one time, for the particle loop: its points and the rise, read without calls.
struct TableNow {
  const Eigen::Vector2d* points;
  std::size_t count;
  double rise, unit_weight, fraction;

  // fraction x gamma_w x max(0, h(x) - y): WaterSettings::pore_pressure times the ramp.
  double pore_pressure(const Vec2& x) const {
    double h;
    if (x.x() <= points[0].x()) {
      h = points[0].y();
    } else if (x.x() >= points[count - 1].x()) {
      h = points[count - 1].y();
    } else {
      std::size_t k = 1;
      while (points[k].x() < x.x()) ++k;
      const Eigen::Vector2d& a = points[k - 1];
      const Eigen::Vector2d& b = points[k];
      h = a.y() + (b.y() - a.y()) * (x.x() - a.x()) / (b.x() - a.x());
    }
    const double depth = h + rise - x.y();
    return depth > 0 ? fraction * unit_weight * depth : 0.0;
  }
};

}  // namespace

long update_stresses_with_water(Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells,
                                const Config& config, double t, int threads) {
  const long moving = static_cast<long>(P.moving_count);
  const bool undrained = config.water.mode == WaterMode::Undrained;
  const WaterSettings& water = config.water;
  const TableNow table{water.table.data(), water.table.size(), water.rise.empty() ? 0.0 : water.rise_at(t),
                       water.unit_weight, gravity_fraction(config, t)};
  // u times the normal components: a vector product, where a Vec4 built from scalars would go
  // through the stack and stall the store forwarding of its 16-byte loads.
  const Vec4 normal(1, 1, 1, 0);
  long bad = -1;
  OwnerFirstChunks chunks(moving, threads);
#pragma omp parallel num_threads(threads) reduction(max : bad)
  {
    // The arrays, read once (StressArrays, step.hpp).
    const StressArrays a(P);
    const Vec4* const d = d_eps.data();
    const MaterialState* const materials = config.materials.data();
    const int32_t* const material_of_body = config.material_of_body.data();
    const double* const initial_volume = config.initial_volume.data();
    double* const pore_pressure = P.pore_pressure.data();
    double* const excess = undrained ? P.excess_pore_pressure.data() : nullptr;
    StrainIncrement increment(cells, P);
    chunks.for_each([&](long begin, long end) {  // own share first (parallel.hpp)
      for (long p = begin; p < end; ++p) {
        Vec4& sigma = a.sigma[p];  // total; effective in between (in place: a copy measured slower)
        double u;
        if (increment.isolated(p)) {
          sigma.setZero();  // a grain in free flight (step.hpp, is_isolated)
          u = table.pore_pressure(a.x[p]);
        } else {
          const MaterialState& material = materials[material_of_body[a.body[p]]];
          const Vec4 dp = increment(p, d[p]);
          sigma += pore_pressure[p] * normal;
          update_stress(material, sigma, dp, a.eps_p[p], a.history_of(p));
          // The new pore pressure after the material's call, so that less lives across it.
          const double volumetric = dp[0] + dp[1] + dp[2];
          u = table.pore_pressure(a.x[p]);
          if (undrained) {
            excess[p] -= material.pore_stiffness * volumetric;
            u += excess[p];
          }
          sigma -= u * normal;
          a.volume[p] = grown_volume(a.volume[p], volumetric, initial_volume, a.id[p]);
        }
        pore_pressure[p] = u;
        if (!std::isfinite(sigma.sum() + a.x[p].sum() + a.v[p].sum() + u) || !(a.volume[p] > 0)) bad = std::max(bad, p);
      }
    });
  }
  return bad;
}

}  // namespace talus::solver
