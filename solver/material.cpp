#include "solver/material.hpp"

#include <cmath>

namespace talus::solver {

MaterialState make_material(const Material& material) {
  MaterialState state;
  state.model = material.model;
  state.density = material.density;
  const double E = material.youngs_modulus, nu = material.poisson_ratio;
  state.shear_modulus = E / (2 * (1 + nu));
  state.bulk_modulus = E / (3 * (1 - 2 * nu));
  state.wave_speed = std::sqrt((state.bulk_modulus + 4 * state.shear_modulus / 3) / material.density);
  if (material.model == MaterialModel::MohrCoulomb)
    state.mohr_coulomb = MohrCoulombParams::from(E, nu, material.friction_angle, material.cohesion,
                                                 material.dilation_angle, material.tensile_strength);
  return state;
}

double elastic_energy_density(const MaterialState& material, const Vec4& sigma) {
  const double p = (sigma[0] + sigma[1] + sigma[2]) / 3;
  const double sxx = sigma[0] - p, syy = sigma[1] - p, szz = sigma[2] - p;
  const double s_s = sxx * sxx + syy * syy + szz * szz + 2 * sigma[3] * sigma[3];
  return s_s / (4 * material.shear_modulus) + p * p / (2 * material.bulk_modulus);
}

}  // namespace talus::solver
