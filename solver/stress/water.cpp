#include "solver/stress/water.hpp"

#include <algorithm>
#include <cmath>

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

WaterTableNow::WaterTableNow(const Config& config, double t)
    : points(config.water.table.data()), count(config.water.table.size()),
      rise(config.water.rise.empty() ? 0.0 : config.water.rise_at(t)), unit_weight(config.water.unit_weight),
      fraction(gravity_fraction(config, t)) {}

}  // namespace talus::solver
