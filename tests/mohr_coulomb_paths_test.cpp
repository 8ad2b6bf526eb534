// Mohr-Coulomb return mapping (common/materials/mohr_coulomb.hpp) on known stress paths: plane strain
// Hooke, uniaxial compression, isotropic tension to the apex, the tension cut-off, rotation
// invariance and refused parameters. Reference quantities: support/mohr_coulomb_reference.hpp.
#include "common/materials/mohr_coulomb.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "support/mohr_coulomb_reference.hpp"
#include "support/simple_shear.hpp"

namespace talus {
namespace {

using testing::admissible_stress;
using testing::Case;
using testing::cases;
using testing::pi;
using testing::rotated;
using testing::stiffness;
using testing::strain_increment;
using testing::yield;

TEST(MohrCoulomb, ElasticUpdateIsPlaneStrainHooke) {
  const MohrCoulombConstants p = MohrCoulombConstants::from(20e6, 0.3, 30, 10e3, 0, -1);
  const Eigen::Vector4d sigma_old(-3e3, -5e3, -4e3, 1e3);
  const Eigen::Vector4d d_eps(1e-4, -2e-4, 0.0, 3e-5);
  Eigen::Vector4d sigma = sigma_old;
  elastic_update(p.shear_modulus, p.bulk_modulus, sigma, d_eps);
  const Eigen::Vector4d expected = sigma_old + stiffness(p) * d_eps;
  EXPECT_LE((sigma - expected).cwiseAbs().maxCoeff(), 1e-9);
  // E = 20 MPa, nu = 0.3: lambda = 11.538 MPa, G = 7.692 MPa; sigma_zz gets lambda tr(d_eps).
  EXPECT_NEAR(sigma[2] - sigma_old[2], 20e6 * 0.3 / (1.3 * 0.4) * (-1e-4), 1e-6);
  EXPECT_NEAR(sigma[3] - sigma_old[3], 20e6 / 1.3 * 3e-5, 1e-6);
}

// Uniaxial compression sigma_yy = -q: f changes sign at q = 2c cos(phi) / (1 - sin(phi)), and a
// strain-driven uniaxial stress test (lateral stresses held at zero) plateaus exactly there.
TEST(MohrCoulomb, UniaxialCompressionYieldsAtTheTextbookStrength) {
  for (const double phi : {30.0, 0.0}) {
    for (const double psi : {0.0, phi}) {
      SCOPED_TRACE("phi " + std::to_string(phi) + " psi " + std::to_string(psi));
      const double c = 10e3, e = 20e6;
      const MohrCoulombConstants p = MohrCoulombConstants::from(e, 0.3, phi, c, psi, -1);
      const double q_y = 2 * c * std::cos(phi * pi / 180) / (1 - std::sin(phi * pi / 180));
      const auto uniaxial = [](double q) { return Eigen::Vector4d(0, -q, 0, 0); };
      EXPECT_LT(mohr_coulomb_yield(p, uniaxial(q_y * (1 - 1e-9))), 0.0);
      EXPECT_GT(mohr_coulomb_yield(p, uniaxial(q_y * (1 + 1e-9))), 0.0);
      EXPECT_LT(yield(p, uniaxial(q_y * (1 - 1e-9))), 0.0);
      EXPECT_GT(yield(p, uniaxial(q_y * (1 + 1e-9))), 0.0);
      Eigen::Vector4d below = uniaxial(0.999 * q_y), above = uniaxial(1.001 * q_y);
      EXPECT_EQ(mohr_coulomb_update(p, below, Eigen::Vector4d::Zero()), 0.0);
      EXPECT_EQ(below, uniaxial(0.999 * q_y));
      EXPECT_GT(mohr_coulomb_update(p, above, Eigen::Vector4d::Zero()), 0.0);
      EXPECT_NEAR(yield(p, above), 0.0, 1e-9 * q_y);

      // Axial strain steps of 1/8 of the yield strain; the lateral strain u (xx = zz by
      // symmetry) is found by bisection so that sigma_xx = 0 after the step.
      const double d_axial = -q_y / e / 8;
      Eigen::Vector4d sigma = Eigen::Vector4d::Zero();
      for (int step = 1; step <= 16; ++step) {
        const auto after = [&](double u) {
          Eigen::Vector4d s = sigma;
          mohr_coulomb_update(p, s, Eigen::Vector4d(u, d_axial, u, 0));
          return s;
        };
        double low = -10 * std::abs(d_axial), high = 10 * std::abs(d_axial);
        ASSERT_LT(after(low)[0], 0.0);
        ASSERT_GT(after(high)[0], 0.0);
        for (int i = 0; i < 200 && high - low > 0; ++i) {
          const double mid = 0.5 * (low + high);
          if (mid == low || mid == high) break;
          (after(mid)[0] < 0 ? low : high) = mid;
        }
        sigma = after(0.5 * (low + high));
        EXPECT_NEAR(sigma[0], 0.0, 1e-9 * q_y);
        EXPECT_NEAR(sigma[2], 0.0, 1e-9 * q_y);
        EXPECT_NEAR(sigma[3], 0.0, 1e-9 * q_y);
        // Elastic up to step 8 (sigma_yy = E eps_yy), then the plateau at -q_y.
        EXPECT_NEAR(sigma[1], step <= 8 ? e * d_axial * step : -q_y, 1e-8 * q_y) << step;
      }
    }
  }
}

// Simple shear under a constant normal stress (support/simple_shear.hpp). Once the sample flows
// steadily, the ratio of shear to normal stress on the horizontal plane is
//   tau_xy / p = sin(phi) cos(psi) / (1 - sin(phi) sin(psi))
// (Davis 1968, "Theories of plasticity and the failure of soil masses"): tan(phi) for associated
// flow, sin(phi) for the non-dilatant flow of a granular material at its critical state. A friction
// coefficient measured as that ratio (a shear box, the slope a layer flows down steadily) is
// therefore sin(phi), not tan(phi), of the plane-strain Mohr-Coulomb angle with psi = 0
// (docs/column.md, "Which friction angle").
TEST(MohrCoulomb, SteadySimpleShearMobilisesDavissStressRatio) {
  const double phi = 32, e = 20e6, p_normal = 50e3;
  for (const double psi : {0.0, 16.0, 32.0}) {
    SCOPED_TRACE("psi " + std::to_string(psi));
    const MohrCoulombConstants p = MohrCoulombConstants::from(e, 0.3, phi, 0, psi, -1);
    const double s = std::sin(phi * pi / 180), davis = s * std::cos(psi * pi / 180) / (1 - s * std::sin(psi * pi / 180));
    const double d_gamma = p_normal / e / 20;  // tensor shear increments of 1/20 of a yield strain
    const Eigen::Vector4d sigma = testing::sheared_under_normal_stress(
        [&](Eigen::Vector4d& stress, const Eigen::Vector4d& d_eps) { mohr_coulomb_update(p, stress, d_eps); },
        Eigen::Vector4d(-0.5 * p_normal, -p_normal, -0.5 * p_normal, 0), p_normal, d_gamma, 4000);  // k0 = 0.5
    const double ratio = sigma[3] / p_normal;
    EXPECT_NEAR(sigma[1], -p_normal, 1e-9 * p_normal);
    EXPECT_NEAR(ratio, davis, 1e-4);
    // What the test tells apart: sin 32 = 0.530 and tan 32 = 0.625.
    if (psi == 0) {
      EXPECT_NEAR(ratio, s, 1e-4);
    }
    if (psi == phi) {
      EXPECT_NEAR(ratio, std::tan(phi * pi / 180), 1e-4);
    }
  }
}

// Isotropic tension past c cot(phi) from several starts returns to the apex exactly (the
// tension cut-off lowers it to the tensile strength); Tresca has no apex and stays elastic.
TEST(MohrCoulomb, IsotropicTensionReturnsToTheApex) {
  const double c = 10e3;
  for (const double psi : {0.0, 30.0}) {
    const MohrCoulombConstants p = MohrCoulombConstants::from(20e6, 0.3, 30, c, psi, -1);
    const double apex = c / std::tan(30 * pi / 180);
    const double e_iso = 2 * apex / (3 * p.bulk_modulus);
    for (const Eigen::Vector4d& start :
         {Eigen::Vector4d(0, 0, 0, 0), Eigen::Vector4d(-5 * c, -5 * c, -5 * c, 0),
          Eigen::Vector4d(-2 * c, -4 * c, -3 * c, 0.5 * c)}) {
      Eigen::Vector4d sigma = start;
      const double d_gamma = mohr_coulomb_update(p, sigma, Eigen::Vector4d(e_iso * 3, e_iso * 3, e_iso * 3, 0));
      for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(sigma[i], apex);
      EXPECT_EQ(sigma[3], 0.0);
      // A purely isotropic trial leaves no plastic shear; a deviatoric one does.
      const bool deviatoric = start[0] != start[1] || start[3] != 0;
      if (deviatoric) {
        EXPECT_GT(d_gamma, 0.0);
      }
      else EXPECT_NEAR(d_gamma, 0.0, 1e-15);
    }
    // Plane strain: the in-plane tension alone reaches the apex as well.
    Eigen::Vector4d sigma = Eigen::Vector4d::Zero();
    mohr_coulomb_update(p, sigma, Eigen::Vector4d(10 * e_iso, 10 * e_iso, 0, 0));
    for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(sigma[i], apex);
  }

  const MohrCoulombConstants cut = MohrCoulombConstants::from(20e6, 0.3, 30, c, 30, 2e3);
  Eigen::Vector4d sigma(-2 * c, -4 * c, -3 * c, 0.5 * c);
  EXPECT_GT(mohr_coulomb_update(cut, sigma, Eigen::Vector4d(1e-2, 1e-2, 1e-2, 0)), 0.0);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(sigma[i], 2e3);
  // A cut-off above the apex is capped to it.
  EXPECT_DOUBLE_EQ(MohrCoulombConstants::from(20e6, 0.3, 30, c, 30, 1e9).tensile_strength,
                   c / std::tan(30 * pi / 180));

  const MohrCoulombConstants tresca = MohrCoulombConstants::from(20e6, 0.3, 0, c, 0, -1);
  EXPECT_EQ(tresca.apex, std::numeric_limits<double>::infinity());
  sigma = Eigen::Vector4d(1e3, 2e3, 1.5e3, 0);
  const Eigen::Vector4d d_eps(1e-2, 1e-2, 1e-2, 0);
  Eigen::Vector4d trial = sigma;
  elastic_update(tresca.shear_modulus, tresca.bulk_modulus, trial, d_eps);
  EXPECT_EQ(mohr_coulomb_update(tresca, sigma, d_eps), 0.0);
  EXPECT_EQ(sigma, trial);
}

// Uniaxial tension with the cut-off: sigma1 ends at the tensile strength, the rest inside.
TEST(MohrCoulomb, TensionCutOffCapsTheMajorStress) {
  const MohrCoulombConstants p = MohrCoulombConstants::from(20e6, 0.3, 30, 10e3, 0, 3e3);
  Eigen::Vector4d sigma(0, -1e3, -1e3, 0);
  // Trial (5385, 1308, 1308) Pa: inside Mohr-Coulomb, past the cut-off in xx only.
  const double d_gamma = mohr_coulomb_update(p, sigma, Eigen::Vector4d(2e-4, 0, 0, 0));
  EXPECT_DOUBLE_EQ(sigma[0], 3e3);
  EXPECT_LT(yield(p, sigma), 0.0);
  // Plane Rankine return: d_eps_p = (dl, 0, 0), so d_gamma_p = dl and the lateral stresses lose
  // lambda dl from the elastic trial.
  const double lambda = p.bulk_modulus - 2 * p.shear_modulus / 3;
  const double trial_yy = -1e3 + lambda * 2e-4;
  EXPECT_NEAR(sigma[1], trial_yy - lambda * d_gamma, 1e-9 * 1e4);
  EXPECT_NEAR(sigma[1], sigma[2], 1e-9);
}

// Rotating the start stress and the strain increment rotates the result.
TEST(MohrCoulomb, RigidRotationInvariance) {
  for (const Case& test_case : cases()) {
    SCOPED_TRACE(test_case.name);
    const MohrCoulombConstants& p = test_case.params;
    std::mt19937 random(7);
    std::uniform_real_distribution<double> angle(-pi, pi);
    int plastic = 0;
    for (int i = 0; i < 1000; ++i) {
      const Eigen::Vector4d start = admissible_stress(p, random);
      const Eigen::Vector4d d_eps = strain_increment(p, random);
      const double theta = angle(random);
      Eigen::Vector4d sigma = start, sigma_rotated = rotated(start, theta);
      const double d_gamma = mohr_coulomb_update(p, sigma, d_eps);
      const double d_gamma_rotated = mohr_coulomb_update(p, sigma_rotated, rotated(d_eps, theta));
      const double scale = p.cohesion + sigma.cwiseAbs().maxCoeff() +
                           p.shear_modulus * d_eps.cwiseAbs().maxCoeff();
      EXPECT_LE((sigma_rotated - rotated(sigma, theta)).cwiseAbs().maxCoeff(), 1e-10 * scale);
      EXPECT_NEAR(d_gamma_rotated, d_gamma, 1e-10 * (d_gamma + d_eps.cwiseAbs().maxCoeff()));
      plastic += d_gamma > 0;
    }
    EXPECT_GT(plastic, 100);
  }
}

TEST(MohrCoulomb, BadParametersAreRefused) {
  EXPECT_THROW(MohrCoulombConstants::from(0, 0.3, 30, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombConstants::from(2e7, 0.5, 30, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombConstants::from(2e7, -0.1, 30, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombConstants::from(2e7, 0.3, 90, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombConstants::from(2e7, 0.3, 30, 1e4, 35, -1), Error);
  EXPECT_THROW(MohrCoulombConstants::from(2e7, 0.3, 30, -1, 0, -1), Error);
  EXPECT_NO_THROW(MohrCoulombConstants::from(2e7, 0.3, 30, 0, 30, -1));
}

}  // namespace
}  // namespace talus
