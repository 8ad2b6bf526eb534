// Strain softening of the Mohr-Coulomb material (solver/stress/material_state.hpp, docs/water.md) at one
// material point, strength reduction of peak and residual alike, the element-size
// regularisation (the undrained pore pressure: undrained_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "solver/stress/water.hpp"
#include "solver/step/step.hpp"

using namespace talus;
using namespace talus::solver;

namespace {

Material softening_sand() {
  Material m;
  m.name = "sand";
  m.model = MaterialModel::MohrCoulomb;
  m.density = 2000;
  m.youngs_modulus = 5e7;
  m.poisson_ratio = 0.3;
  m.friction_angle = 35;
  m.cohesion = 10e3;
  m.dilation_angle = 0;
  m.residual_friction_angle = 20;
  m.residual_cohesion = 0;
  m.residual_dilation_angle = 0;
  m.softening_start = 0.01;
  m.softening_end = 0.05;
  return m;
}

// The prescribed strength in simple shear at mean in-plane stress p (< 0): with psi = 0 the
// plastic flow is isochoric, sigma_xx = sigma_yy = sigma_zz = p stay, and the shear stress on
// the yield surface is tau = c cos(phi) - p sin(phi), c and phi linear in eps_p between the
// softening strains.
double prescribed_tau(const Material& m, double eps_p, double p) {
  const double s = std::clamp((eps_p - m.softening_start) / (m.softening_end - m.softening_start), 0.0, 1.0);
  const double c = m.cohesion + s * (m.residual_cohesion - m.cohesion);
  const double phi = (m.friction_angle + s * (m.residual_friction_angle - m.friction_angle)) * M_PI / 180;
  return c * std::cos(phi) - p * std::sin(phi);
}

}  // namespace

// Simple shear of one material point under an isotropic stress of -100 kPa, in increments of
// engineering shear strain 1e-5 to gamma = 0.1: once yielding, the shear stress follows the
// prescribed curve (within 1 % of the peak-to-residual drop at every step) and is residual
// (within 1 %) from the step where eps_p reaches softening_end on.
TEST(Softening, SimpleShearFollowsThePrescribedStrengthCurve) {
  const Material m = softening_sand();
  const MaterialState state = make_material(m);
  ASSERT_TRUE(state.softening);
  const double p = -100e3;
  Vec4 sigma(p, p, p, 0);
  double eps_p = 0;
  const double drop = prescribed_tau(m, 0, p) - prescribed_tau(m, 1, p);
  double worst = 0, tau_at_end = NAN;
  for (int k = 0; k < 10000; ++k) {
    update_stress(state, sigma, Vec4(0, 0, 0, 0.5e-5), eps_p, nullptr);
    if (eps_p > 0) worst = std::max(worst, std::abs(sigma[3] - prescribed_tau(m, eps_p, p)));
    if (std::isnan(tau_at_end) && eps_p >= m.softening_end) tau_at_end = sigma[3];
  }
  const double residual = prescribed_tau(m, 1, p);
  std::printf("simple shear: peak tau %.0f Pa, residual %.0f Pa, at softening_end %.0f Pa, worst deviation %.3e of "
              "the drop, final eps_p %.4f\n",
              prescribed_tau(m, 0, p), residual, tau_at_end, worst / drop, eps_p);
  EXPECT_LT(worst, 0.01 * drop);
  ASSERT_FALSE(std::isnan(tau_at_end));
  EXPECT_NEAR(tau_at_end, residual, 0.01 * residual);
  EXPECT_NEAR(sigma[3], residual, 1e-6 * residual);
  EXPECT_NEAR(sigma[0], p, 1e-6 * -p);  // no dilation: the normal stresses stay
}

// Strength reduction divides peak and residual alike: c / F and tan(phi) / F at both ends.
TEST(Softening, StrengthReductionDividesPeakAndResidual) {
  const Material m = softening_sand();
  MaterialState state = make_material(m);
  set_strength(state, m, 1.5);
  const double phi_r = std::atan(std::tan(20 * M_PI / 180) / 1.5);
  EXPECT_NEAR(state.residual.sin_phi, std::sin(phi_r), 1e-12);
  EXPECT_NEAR(state.mohr_coulomb.cohesion, 10e3 / 1.5, 1e-9);
  EXPECT_NEAR(state.mohr_coulomb.sin_phi, std::sin(std::atan(std::tan(35 * M_PI / 180) / 1.5)), 1e-12);
}

// The regularisation scales the softening strains by reference size over element size.
TEST(Softening, RegularisationScalesTheStrainsWithElementSize) {
  Model model;
  model.nodes = {{0, 0}, {0.5, 0}, {0, 0.5}, {0.5, 0.5}};
  model.triangles = {{0, 1, 3}, {0, 3, 2}};
  model.neighbours = {{-1, 1, -1}, {-1, -1, 0}};
  Material m = softening_sand();
  m.softening_reference_size = 1.0;
  model.materials = {m};
  Config config;
  config.mesh = build_mesh(model);
  config.materials = {make_material(m)};
  prepare_materials(config, model);
  EXPECT_NEAR(config.materials[0].softening_start, 0.01 * 1.0 / 0.5, 1e-12);  // sqrt(2 A) = 0.5
  EXPECT_NEAR(config.materials[0].softening_end, 0.05 * 1.0 / 0.5, 1e-12);
}
