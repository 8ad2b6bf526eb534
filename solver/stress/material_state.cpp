#include "solver/stress/material_state.hpp"

#include <algorithm>
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
  state.youngs_modulus = E;
  state.poisson_ratio = nu;
  state.tensile_strength = material.tensile_strength;
  if (material.model == MaterialModel::MohrCoulomb) {
    state.softening = material.softening_end > 0;
    state.softening_start = material.softening_start;
    state.softening_end = material.softening_end;
    set_strength(state, material, std::nullopt);
  }
  return state;
}

namespace {

// As strength reduction always computed it: degrees(atan(tan(radians(angle)) / F)).
// (No factor: the angle as given.)
double reduced_angle(double degrees, std::optional<double> factor) {
  return factor ? std::atan(std::tan(degrees * M_PI / 180.0) / *factor) * 180.0 / M_PI : degrees;
}

MohrCoulombParams params_of(const MaterialState& s, const MaterialState::Strength& strength) {
  return MohrCoulombParams::from(s.youngs_modulus, s.poisson_ratio, strength.friction_angle, strength.cohesion,
                                 std::min(strength.dilation_angle, strength.friction_angle), s.tensile_strength);
}

}  // namespace

void set_strength(MaterialState& state, const Material& m, std::optional<double> reduction) {
  const double factor = reduction.value_or(1);
  const double phi = reduced_angle(m.friction_angle, reduction);
  state.tensile_strength = m.tensile_strength < 0 ? m.tensile_strength : m.tensile_strength / factor;
  state.peak = {m.cohesion / factor, phi, std::min(reduced_angle(m.dilation_angle, reduction), phi)};
  state.mohr_coulomb = params_of(state, state.peak);
  if (!state.softening) return;
  const double residual_phi = reduced_angle(m.residual_friction_angle, reduction);
  state.residual_strength = {m.residual_cohesion / factor, residual_phi,
                             std::min(reduced_angle(m.residual_dilation_angle, reduction), residual_phi)};
  state.residual = params_of(state, state.residual_strength);
}

double softening_update(const MaterialState& material, Vec4& sigma, const Vec4& d_eps, double eps_p) {
  if (eps_p <= material.softening_start) return mohr_coulomb_update(material.mohr_coulomb, sigma, d_eps);
  if (eps_p >= material.softening_end) return mohr_coulomb_update(material.residual, sigma, d_eps);
  const double s = (eps_p - material.softening_start) / (material.softening_end - material.softening_start);
  const MaterialState::Strength& a = material.peak;
  const MaterialState::Strength& b = material.residual_strength;
  const MaterialState::Strength now{a.cohesion + s * (b.cohesion - a.cohesion),
                                    a.friction_angle + s * (b.friction_angle - a.friction_angle),
                                    a.dilation_angle + s * (b.dilation_angle - a.dilation_angle)};
  const MohrCoulombParams params =
      MohrCoulombParams::unchecked(material.youngs_modulus, material.poisson_ratio, now.friction_angle, now.cohesion,
                                   std::min(now.dilation_angle, now.friction_angle), material.tensile_strength);
  return mohr_coulomb_update(params, sigma, d_eps);
}

double elastic_energy_density(const MaterialState& material, const Vec4& sigma) {
  const double p = (sigma[0] + sigma[1] + sigma[2]) / 3;
  const double sxx = sigma[0] - p, syy = sigma[1] - p, szz = sigma[2] - p;
  const double s_s = sxx * sxx + syy * syy + szz * szz + 2 * sigma[3] * sigma[3];
  return s_s / (4 * material.shear_modulus) + p * p / (2 * material.bulk_modulus);
}

}  // namespace talus::solver
