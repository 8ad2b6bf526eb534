// Strain softening of the Mohr-Coulomb material (common/materials/mohr_coulomb.hpp, docs/water.md)
// at one material point, its state in the particle's history, strength reduction of peak and
// residual alike, the element-size regularisation (the undrained pore pressure: undrained_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "solver/step/step.hpp"
#include "solver/stress/material_state.hpp"

using namespace talus;
using namespace talus::solver;

namespace {

Material softening_sand() {
  Material m;
  m.name = "sand";
  m.density = 2000;
  m.youngs_modulus = 5e7;
  m.poisson_ratio = 0.3;
  MohrCoulomb::Parameters own;
  own.friction_angle = 35;
  own.cohesion = 10e3;
  own.dilation_angle = 0;
  own.residual_friction_angle = 20;
  own.residual_cohesion = 0;
  own.residual_dilation_angle = 0;
  own.softening_start = 0.01;
  own.softening_end = 0.05;
  m.model = own;
  return m;
}

const MohrCoulomb::Prepared& prepared(const MaterialState& state) {
  return std::get<MohrCoulomb::Prepared>(state.prepared);
}

// The prescribed strength in simple shear at mean in-plane stress p (< 0): with psi = 0 the
// plastic flow is isochoric, sigma_xx = sigma_yy = sigma_zz = p stay, and the shear stress on
// the yield surface is tau = c cos(phi) - p sin(phi), c and phi linear in eps_p between the
// softening strains.
double prescribed_tau(const Material& material, double eps_p, double p) {
  const MohrCoulomb::Parameters& m = parameters_of<MohrCoulomb>(material);
  const double s = std::clamp((eps_p - m.softening_start) / (m.softening_end - m.softening_start), 0.0, 1.0);
  const double c = m.cohesion + s * (m.residual_cohesion - m.cohesion);
  const double phi = (m.friction_angle + s * (m.residual_friction_angle - m.friction_angle)) * M_PI / 180;
  return c * std::cos(phi) - p * std::sin(phi);
}

}  // namespace

// Simple shear of one material point under an isotropic stress of -100 kPa, in increments of
// engineering shear strain 1e-5 to gamma = 0.1: once yielding, the shear stress follows the
// prescribed curve (within 1 % of the peak-to-residual drop at every step) and is residual
// (within 1 %) from the step where eps_p reaches softening_end on. The strain that drives the
// softening is the particle's one history variable, which follows eps_p exactly.
TEST(Softening, SimpleShearFollowsThePrescribedStrengthCurve) {
  const Material m = softening_sand();
  const MaterialState state = make_material(m);
  ASSERT_EQ(state.history_width, 1);
  ASSERT_TRUE(prepared(state).softens);
  const double p = -100e3;
  Vec4 sigma(p, p, p, 0);
  double eps_p = 0, history = 0;
  const double drop = prescribed_tau(m, 0, p) - prescribed_tau(m, 1, p);
  double worst = 0, tau_at_end = NAN;
  for (int k = 0; k < 10000; ++k) {
    update_stress(state.prepared, sigma, Vec4(0, 0, 0, 0.5e-5), 1e-4, eps_p, &history);
    ASSERT_EQ(history, eps_p);
    if (eps_p > 0) worst = std::max(worst, std::abs(sigma[3] - prescribed_tau(m, eps_p, p)));
    if (std::isnan(tau_at_end) && eps_p >= parameters_of<MohrCoulomb>(m).softening_end) tau_at_end = sigma[3];
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

// The strength follows the history variable, not eps_p: a particle whose history is already past
// softening_end yields at the residual strength while its eps_p is still 0.
TEST(Softening, TheHistoryVariableDrivesTheStrength) {
  const Material m = softening_sand();
  const MaterialState state = make_material(m);
  const double p = -100e3;
  Vec4 sigma(p, p, p, 0);
  double eps_p = 0, history = 0.06;
  for (int k = 0; k < 2000; ++k) update_stress(state.prepared, sigma, Vec4(0, 0, 0, 0.5e-5), 1e-4, eps_p, &history);
  const double residual = prescribed_tau(m, 1, p);
  EXPECT_NEAR(sigma[3], residual, 1e-6 * residual);
  EXPECT_GT(eps_p, 0);
  EXPECT_NEAR(history, 0.06 + eps_p, 1e-14);  // the same increments, summed from another start
  // Without softening keys: no history.
  Material plain = m;
  parameters_of<MohrCoulomb>(plain).softening_end = 0;
  EXPECT_EQ(make_material(plain).history_width, 0);
  EXPECT_FALSE(prepared(make_material(plain)).softens);
}

// Strength reduction divides peak and residual alike: c / F and tan(phi) / F at both ends.
TEST(Softening, StrengthReductionDividesPeakAndResidual) {
  const Material m = softening_sand();
  MaterialState state = make_material(m);
  reduce_strength(state, 1.5);
  const double phi_r = std::atan(std::tan(20 * M_PI / 180) / 1.5);
  EXPECT_NEAR(prepared(state).residual.sin_phi, std::sin(phi_r), 1e-12);
  EXPECT_NEAR(prepared(state).peak.cohesion, 10e3 / 1.5, 1e-9);
  EXPECT_NEAR(prepared(state).peak.sin_phi, std::sin(std::atan(std::tan(35 * M_PI / 180) / 1.5)), 1e-12);
}

// The regularisation scales the softening strains by reference size over element size.
TEST(Softening, RegularisationScalesTheStrainsWithElementSize) {
  Model model;
  model.nodes = {{0, 0}, {0.5, 0}, {0, 0.5}, {0.5, 0.5}};
  model.triangles = {{0, 1, 3}, {0, 3, 2}};
  model.neighbours = {{-1, 1, -1}, {-1, -1, 0}};
  Material m = softening_sand();
  parameters_of<MohrCoulomb>(m).softening_reference_size = 1.0;
  model.materials = {m};
  Config config;
  config.mesh = build_mesh(model);
  prepare_materials(config, model);
  EXPECT_NEAR(prepared(config.materials[0]).softening_start, 0.01 * 1.0 / 0.5, 1e-12);  // sqrt(2 A) = 0.5
  EXPECT_NEAR(prepared(config.materials[0]).softening_end, 0.05 * 1.0 / 0.5, 1e-12);
  // Strength reduction prepares the state again, regularised the same way.
  reduce_strength(config.materials[0], 1.3);
  EXPECT_NEAR(prepared(config.materials[0]).softening_end, 0.05 * 1.0 / 0.5, 1e-12);
}
