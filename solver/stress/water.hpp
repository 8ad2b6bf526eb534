// Pore pressure and effective stress (docs/water.md). With a water table the particles carry the
// TOTAL stress sigma (what the internal force uses) and the pore pressure u (positive in
// compression); the materials see the effective stress sigma' = sigma + u (1, 1, 1, 0).
//   drained:   u = f(t) gamma_w max(0, h(x, t) - y) at the particle's current position, f the
//              gravity ramp's fraction, h the table (with its rise) at the particle's x;
//   undrained: the same plus an excess du = -(K_w / n) d(eps_v) carried by the particle.
#pragma once
#include "solver/step/simulation.hpp"

namespace talus::solver {

// The hydrostatic pore pressure of a point at time t, the ramp included (Pa).
inline double hydrostatic_pore_pressure(const Config& config, const Vec2& x, double t) {
  return ramp_factor(t, config.gravity_ramp) * config.water.pore_pressure(x, t);
}

// The water table at one time, for the stress loop (stress.cpp): its points and rise, read
// without calls; pore_pressure(x) is hydrostatic_pore_pressure at that time.
struct WaterTableNow {
  WaterTableNow() = default;  // no table
  WaterTableNow(const Config& config, double t);
  // fraction x gamma_w x max(0, h(x) - y); inline, as the stress loop's per-particle call.
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

  const Eigen::Vector2d* points = nullptr;
  std::size_t count = 0;
  double rise = 0, unit_weight = 0, fraction = 0;
};

// Sizes and fills the pore-pressure fields of particles at time t (make_simulation).
void initial_pore_pressures(Particles& P, const Config& config, double t);

}  // namespace talus::solver
