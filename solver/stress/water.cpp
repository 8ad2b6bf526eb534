#include "solver/stress/water.hpp"

#include <algorithm>
#include <cmath>

namespace talus::solver {

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
      fraction(ramp_factor(t, config.gravity_ramp)) {}

}  // namespace talus::solver
