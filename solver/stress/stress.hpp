// The stress update of every particle, one loop with or without water (docs/water.md): the
// material's update on the effective stress, the pore pressure, the volume (step.hpp's phase
// list: update_stresses).
#pragma once
#include <vector>

#include "solver/step/simulation.hpp"
#include "solver/stress/material_state.hpp"

namespace talus::solver {

struct CellSums;  // step.hpp

// For every moving particle that is not isolated: the strain increment d_eps as EVS leaves it
// (StrainIncrement, step.hpp), the material's update over the step dt (with a water table on the
// effective stress sigma + u (1, 1, 1, 0), then the pore pressure u at time t, the end of the step,
// and the total stress sigma' - u I), and the volume V_p *= 1 + tr d_eps, capped at
// kMaxVolumeGrowth V_p(0). An isolated particle drops its stress and keeps its volume.
// Returns the last (largest index) particle whose state became non-finite or inverted, or -1.
long update_stresses(Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells, const Config& config,
                     double t, double dt, int threads);

// The elastic energy density of particle p's effective stress (energies(), diagnostics.cpp),
// with its own E and nu when it has them.
inline double elastic_energy_density(const Config& config, const Particles& P, std::size_t p) {
  const MaterialState& material = config.materials[config.material_of_body[P.body[p]]];
  if (!material.elastic_columns) return elastic_energy_density(material, effective_stress(P, p));
  const ParticleMaterial& own = material.of_particle(P.id[p]);
  return elastic_energy_density(own.shear_modulus, own.bulk_modulus, effective_stress(P, p));
}

}  // namespace talus::solver
