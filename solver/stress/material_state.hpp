// Materials as the solver uses them: parameters precomputed once from the scene's Material,
// and one stress update per particle chosen by a switch (no virtual calls in the hot loop).
#pragma once
#include <optional>

#include "common/scene/scene.hpp"
#include "common/materials/mohr_coulomb.hpp"
#include "solver/interpolation/mesh.hpp"

namespace talus::solver {

struct MaterialState {
  MaterialModel model = MaterialModel::LinearElastic;
  double density = 0;
  double shear_modulus = 0, bulk_modulus = 0;  // plane strain uses the 3D moduli
  double wave_speed = 0;                       // c_d = sqrt((K + 4G/3) / rho)
  MohrCoulombParams mohr_coulomb{};  // the peak strength
  // Strain softening (softening true): between eps_p = softening_start and softening_end (after
  // the element-size regularisation, setup.cpp) c, phi and psi go linearly from the peak values
  // to the residual ones; `residual` is the end point, `peak` and `residual_strength` the
  // (reduced) values interpolated in between.
  bool softening = false;
  double softening_start = 0, softening_end = 0;
  MohrCoulombParams residual{};
  struct Strength {
    double cohesion = 0, friction_angle = 0, dilation_angle = 0;  // Pa, deg, deg
  } peak, residual_strength;
  double youngs_modulus = 0, poisson_ratio = 0, tensile_strength = -1;
  // Undrained water: the pore water's stiffness over the porosity, K_w / n (Pa); 0 otherwise.
  double pore_stiffness = 0;
  // State variables the material keeps per particle besides the stress and eps_p, in
  // Particles::history (none for the materials so far).
  int history_width = 0;
};

MaterialState make_material(const Material& material);

// Sets the strength of a Mohr-Coulomb material divided by `factor` (none: the scene's): c / F,
// tan(phi) / F and tan(psi) / F (psi capped at phi), the tension cut-off / F, peak and residual
// alike (strength reduction, solver/strength_reduction.cpp).
void set_strength(MaterialState& state, const Material& material, std::optional<double> factor);

// The Mohr-Coulomb update of a softening material, its strength taken at the particle's eps_p
// before the step (explicit in the hardening variable). Returns d_gamma_p.
double softening_update(const MaterialState& material, Vec4& sigma, const Vec4& d_eps, double eps_p);

// Objective stress update of one particle: sigma is already rotated (Jaumann) by the caller;
// adds the material's response to the strain increment d_eps and the increment of equivalent
// plastic shear strain to eps_p (nothing for elastic materials). `history` points at the
// particle's history_width state variables (unused so far).
inline void update_stress(const MaterialState& material, Vec4& sigma, const Vec4& d_eps, double& eps_p,
                          double* history) {
  switch (material.model) {
    case MaterialModel::MohrCoulomb:
      eps_p += material.softening ? softening_update(material, sigma, d_eps, eps_p)
                                  : mohr_coulomb_update(material.mohr_coulomb, sigma, d_eps);
      return;
    case MaterialModel::LinearElastic:
    default: elastic_update(material.shear_modulus, material.bulk_modulus, sigma, d_eps); return;
  }
}

// Elastic energy density of a stress state, (s:s)/(4G) + p^2/(2K) with the 3D mean stress p.
double elastic_energy_density(const MaterialState& material, const Vec4& sigma);

}  // namespace talus::solver
