// Pore pressure and effective stress (docs/water.md). With a water table the particles carry the
// TOTAL stress sigma (what the internal force uses) and the pore pressure u (positive in
// compression); the materials see the effective stress sigma' = sigma + u (1, 1, 1, 0).
//   drained:   u = f(t) gamma_w max(0, h(x, t) - y) at the particle's current position, f the
//              gravity ramp's fraction, h the table (with its rise) at the particle's x;
//   undrained: the same plus an excess du = -(K_w / n) d(eps_v) carried by the particle.
#pragma once
#include "solver/step/simulation.hpp"

namespace talus::solver {

struct CellSums;  // step.hpp

// The gravity ramp's fraction at time t: (1 - cos(pi t / T)) / 2 until T, then 1.
double gravity_fraction(const Config& config, double t);

// The hydrostatic pore pressure of a point at time t, the ramp included (Pa).
inline double hydrostatic_pore_pressure(const Config& config, const Vec2& x, double t) {
  return gravity_fraction(config, t) * config.water.pore_pressure(x, t);
}

// update_stresses (step.hpp) for a scene with water: the material update on the effective
// stress, then the new pore pressure at time t (the end of the step) and the total stress.
// Returns the largest particle index with a non-finite state or a non-positive volume, or -1.
long update_stresses_with_water(Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells,
                                const Config& config, double t, int threads);

// Sizes and fills the pore-pressure fields of particles at time t (make_simulation).
void initial_pore_pressures(Particles& P, const Config& config, double t);

// Water settings of the materials once the mesh is known (make_simulation): the undrained pore
// stiffness K_w / n and its wave speed, and the softening strains' element-size regularisation.
void prepare_materials(Config& config, const Model& model);

}  // namespace talus::solver
