// Materials as the solver uses them: parameters precomputed once from the scene's Material,
// and one stress update per particle chosen by a switch (no virtual calls in the hot loop).
#pragma once
#include "common/scene.hpp"
#include "solver/mohr_coulomb.hpp"
#include "solver/mesh.hpp"

namespace talus::solver {

struct MaterialState {
  MaterialModel model = MaterialModel::LinearElastic;
  double density = 0;
  double shear_modulus = 0, bulk_modulus = 0;  // plane strain uses the 3D moduli
  double wave_speed = 0;                       // c_d = sqrt((K + 4G/3) / rho)
  MohrCoulombParams mohr_coulomb{};
  // State variables the material keeps per particle besides the stress and eps_p, in
  // Particles::history (none for the materials so far).
  int history_width = 0;
};

MaterialState make_material(const Material& material);

// Objective stress update of one particle: sigma is already rotated (Jaumann) by the caller;
// adds the material's response to the strain increment d_eps and the increment of equivalent
// plastic shear strain to eps_p (nothing for elastic materials). `history` points at the
// particle's history_width state variables (unused so far).
inline void update_stress(const MaterialState& material, Vec4& sigma, const Vec4& d_eps, double& eps_p,
                          double* history) {
  switch (material.model) {
    case MaterialModel::MohrCoulomb: eps_p += mohr_coulomb_update(material.mohr_coulomb, sigma, d_eps); return;
    case MaterialModel::LinearElastic:
    default: elastic_update(material.shear_modulus, material.bulk_modulus, sigma, d_eps); return;
  }
}

// Elastic energy density of a stress state, (s:s)/(4G) + p^2/(2K) with the 3D mean stress p.
double elastic_energy_density(const MaterialState& material, const Vec4& sigma);

}  // namespace talus::solver
