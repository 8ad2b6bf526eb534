// Mohr-Coulomb return mapping (solver/mohr_coulomb.hpp). The reference quantities (principal
// stresses, f, the elastic stiffness, principal plastic strains) are recomputed here with
// Eigen's 3x3 eigen-solver, independently of the closed forms in the material.
#include "solver/mohr_coulomb.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "common/error.hpp"

namespace talus {
namespace {

constexpr double pi = 3.14159265358979323846;

Eigen::Matrix3d tensor(const Eigen::Vector4d& v) {
  Eigen::Matrix3d m;
  m << v[0], v[3], 0.0, v[3], v[1], 0.0, 0.0, 0.0, v[2];
  return m;
}

// Eigenvalues and eigenvectors sorted largest first.
struct Principal {
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
};
Principal principal(const Eigen::Vector4d& v) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(tensor(v));
  Principal result;
  for (int i = 0; i < 3; ++i) {  // Eigen sorts ascending
    result.values[i] = solver.eigenvalues()[2 - i];
    result.vectors.col(i) = solver.eigenvectors().col(2 - i);
  }
  return result;
}

double yield(const MohrCoulombParams& p, const Eigen::Vector4d& sigma) {
  const Eigen::Vector3d s = principal(sigma).values;
  return (s[0] - s[2]) + (s[0] + s[2]) * p.sin_phi - 2.0 * p.cohesion * p.cos_phi;
}

// Plane strain isotropic D acting on (xx, yy, zz, xy) with the tensor shear strain.
Eigen::Matrix4d stiffness(const MohrCoulombParams& p) {
  const double g = p.shear_modulus, lambda = p.bulk_modulus - 2.0 * g / 3.0;
  Eigen::Matrix4d d = Eigen::Matrix4d::Zero();
  d.topLeftCorner<3, 3>().setConstant(lambda);
  for (int i = 0; i < 3; ++i) d(i, i) += 2.0 * g;
  d(3, 3) = 2.0 * g;
  return d;
}

Eigen::Vector4d rotated(const Eigen::Vector4d& v, double angle) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r.topLeftCorner<2, 2>() << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  const Eigen::Matrix3d m = r * tensor(v) * r.transpose();
  return Eigen::Vector4d(m(0, 0), m(1, 1), m(2, 2), m(0, 1));
}

struct Case {
  std::string name;
  MohrCoulombParams params;
};

std::vector<Case> cases() {
  const double e = 20e6, c = 10e3;
  return {
      {"associated", MohrCoulombParams::from(e, 0.3, 30, c, 30, -1)},
      {"non_dilatant", MohrCoulombParams::from(e, 0.3, 30, c, 0, -1)},
      {"partly_dilatant", MohrCoulombParams::from(e, 0.25, 35, c, 10, -1)},
      {"poisson_zero", MohrCoulombParams::from(e, 0.0, 20, c, 20, -1)},
      {"tresca", MohrCoulombParams::from(e, 0.3, 0, 2 * c, 0, -1)},
      {"associated_cut_off", MohrCoulombParams::from(e, 0.3, 30, c, 30, 5e3)},
      {"non_dilatant_zero_tension", MohrCoulombParams::from(e, 0.3, 30, c, 0, 0)},
      {"tresca_cut_off", MohrCoulombParams::from(e, 0.3, 0, 2 * c, 0, 10e3)},
  };
}

bool has_cut_off(const MohrCoulombParams& p) { return p.tensile_strength >= 0; }

// A random stress inside both criteria, by rejection.
Eigen::Vector4d admissible_stress(const MohrCoulombParams& p, std::mt19937& random) {
  const double c = p.cohesion;
  std::uniform_real_distribution<double> normal(-12 * c, 3 * c), shear(-3 * c, 3 * c);
  for (;;) {
    const Eigen::Vector4d sigma(normal(random), normal(random), normal(random), shear(random));
    if (yield(p, sigma) > 0) continue;
    if (has_cut_off(p) && principal(sigma).values[0] > p.tensile_strength) continue;
    return sigma;
  }
}

// A random strain increment whose size spans elastic steps to ones far past the apex.
Eigen::Vector4d strain_increment(const MohrCoulombParams& p, std::mt19937& random) {
  std::uniform_real_distribution<double> unit(-1, 1), exponent(-3, 1.5);
  const double size = p.cohesion / p.shear_modulus * std::pow(10.0, exponent(random));
  Eigen::Vector4d d_eps(unit(random), unit(random), unit(random), unit(random));
  d_eps *= size;
  if (unit(random) < 0) d_eps[2] = 0;  // mostly plane strain, but the zz slot is general
  if (unit(random) > 0.5) d_eps.head<3>().array() += size * (1 + unit(random));  // towards the apex
  return d_eps;
}

// Counts of where the random returns ended, to show that every branch was exercised.
struct Coverage {
  int elastic = 0, plane = 0, compression_edge = 0, extension_edge = 0, apex = 0, cut_off = 0;
};

// Every check of one random step; see the test below for what is asserted.
void check_step(const MohrCoulombParams& p, const Eigen::Vector4d& sigma_old,
                const Eigen::Vector4d& d_eps, const Eigen::Vector4d& sigma, double d_gamma,
                Coverage& coverage) {
  Eigen::Vector4d trial = sigma_old;
  elastic_update(p.shear_modulus, p.bulk_modulus, trial, d_eps);
  const Principal trial_principal = principal(trial);
  const double scale = p.cohesion + trial_principal.values.cwiseAbs().maxCoeff();
  const double tol = 1e-10 * scale;
  const bool cut = has_cut_off(p);
  const double f_trial = yield(p, trial);
  const double over_cut = cut ? trial_principal.values[0] - p.tensile_strength : -1.0;

  ASSERT_TRUE(sigma.allFinite() && std::isfinite(d_gamma));
  const Principal now = principal(sigma);
  const Eigen::Vector3d s = now.values;
  const double f = yield(p, sigma);
  EXPECT_LE(f, tol);
  if (cut) {
    EXPECT_LE(s[0], p.tensile_strength + tol);
  }

  if (f_trial < -tol && over_cut < -tol) {  // clearly elastic
    ++coverage.elastic;
    for (int i = 0; i < 4; ++i) EXPECT_EQ(sigma[i], trial[i]);
    EXPECT_EQ(d_gamma, 0.0);
    return;
  }
  if (f_trial <= tol && over_cut <= tol) return;  // on the surface: either answer is right

  const bool on_cut_off = cut && std::abs(s[0] - p.tensile_strength) <= tol;
  EXPECT_TRUE(std::abs(f) <= tol || on_cut_off) << "f = " << f;

  // Plastic strain increment d_eps - D^-1 d_sigma, as a tensor.
  const Eigen::Vector4d plastic =
      d_eps - stiffness(p).partialPivLu().solve(sigma - sigma_old);
  const Eigen::Matrix3d plastic_tensor = tensor(plastic);
  const Principal e = principal(plastic);
  const double strain_tol = 1e-8 * (d_eps.cwiseAbs().maxCoeff() + scale / p.shear_modulus);
  EXPECT_NEAR(d_gamma, e.values[0] - e.values[2], strain_tol);
  if (trial_principal.values[0] - trial_principal.values[2] > tol) {
    EXPECT_GT(d_gamma, 0.0);
  }
  // Coaxial with the stress (isotropy of the return).
  const Eigen::Matrix3d sigma_tensor = tensor(sigma);
  EXPECT_LE((sigma_tensor * plastic_tensor - plastic_tensor * sigma_tensor).norm(),
            1e-8 * scale * (plastic_tensor.norm() + strain_tol));

  if (on_cut_off) {
    ++coverage.cut_off;
    return;
  }
  if (s[0] - s[2] <= tol) {  // apex: sigma1 = sigma2 = sigma3 = c cot(phi)
    ++coverage.apex;
    EXPECT_GT(p.sin_phi, 0.0);
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(sigma[i], p.apex, tol);
    EXPECT_NEAR(sigma[3], 0.0, tol);
    // Only trials that no edge return can reach belong here (Clausen et al. 2006: the apex
    // region is bounded by the planes through the apex spanned by D b_1, D b_2 and by D b_1,
    // D b_3). With the plastic strain e = D^-1 (trial - apex) sorted like the trial's stresses
    // and k = (1 + sin psi) / (1 - sin psi), the normals b_1 x b_2 ~ (1, 1, k) and
    // b_1 x b_3 ~ (1, k, k) give e1 + e2 + k e3 >= 0 and e1 + k (e2 + e3) >= 0. For psi = 0
    // both say that the trial's mean stress is past the apex.
    const double k = (1 + p.sin_psi) / (1 - p.sin_psi);
    EXPECT_GE(e.values[0] + e.values[1] + k * e.values[2], -strain_tol);
    EXPECT_GE(e.values[0] + k * (e.values[1] + e.values[2]), -strain_tol);
    if (p.sin_psi == 0.0) {
      EXPECT_GE(trial.head<3>().mean(), p.apex - tol);
    }
    return;
  }
  // Flow rule d_eps_p = sum dl_i b_i with b_1 = (1 + sin psi, 0, -(1 - sin psi)) on the
  // plane; on the compression edge add b_2 = (0, 1 + sin psi, -(1 - sin psi)), on the extension
  // edge b_3 = (1 + sin psi, -(1 - sin psi), 0), all dl_i >= 0. Hence, with e_v the plastic
  // volumetric strain:
  //   plane or extension edge:   e_v (1 + sin psi) =  2 sin psi e_max, e_max along sigma1;
  //   plane or compression edge: e_v (1 - sin psi) = -2 sin psi e_min, e_min along sigma3;
  //   plane: e_mid = 0 and e_v = sin psi (e_max - e_min); psi = 0 gives e_v = 0 everywhere.
  const double sin_psi = p.sin_psi, e_v = plastic_tensor.trace();
  const bool plane_or_extension = s[0] - s[1] > tol, plane_or_compression = s[1] - s[2] > tol;
  if (sin_psi == 0.0) {
    EXPECT_NEAR(e_v, 0.0, strain_tol);
  }
  if (plane_or_extension) {
    EXPECT_NEAR(e_v * (1 + sin_psi), 2 * sin_psi * e.values[0], strain_tol);
    const Eigen::Vector3d v = now.vectors.col(0);
    EXPECT_NEAR(v.dot(plastic_tensor * v), e.values[0], strain_tol);
    EXPECT_GE(e.values[0], -strain_tol);
  }
  if (plane_or_compression) {
    EXPECT_NEAR(e_v * (1 - sin_psi), -2 * sin_psi * e.values[2], strain_tol);
    const Eigen::Vector3d v = now.vectors.col(2);
    EXPECT_NEAR(v.dot(plastic_tensor * v), e.values[2], strain_tol);
    EXPECT_LE(e.values[2], strain_tol);
  }
  if (plane_or_extension && plane_or_compression) {
    ++coverage.plane;
    EXPECT_NEAR(e.values[1], 0.0, strain_tol);
    EXPECT_NEAR(e_v, sin_psi * (e.values[0] - e.values[2]), strain_tol);
  } else if (plane_or_extension) {
    ++coverage.extension_edge;
  } else {
    ++coverage.compression_edge;
  }
}

// Thousands of random steps per parameter set: admissible result, on the surface when the
// trial was plastic, elastic steps untouched, d_gamma_p by its definition, flow rule.
TEST(MohrCoulomb, RandomStepsStayAdmissibleAndFollowTheFlowRule) {
  for (const Case& test_case : cases()) {
    SCOPED_TRACE(test_case.name);
    const MohrCoulombParams& p = test_case.params;
    std::mt19937 random(20240611);
    std::uniform_real_distribution<double> unit(0, 1);
    Coverage coverage;
    Eigen::Vector4d sigma = admissible_stress(p, random);
    for (int step = 0; step < 6000; ++step) {
      // Half the steps continue the path (often from a state on the surface).
      if (unit(random) < 0.5) sigma = admissible_stress(p, random);
      const Eigen::Vector4d sigma_old = sigma;
      const Eigen::Vector4d d_eps = strain_increment(p, random);
      const double d_gamma = mohr_coulomb_update(p, sigma, d_eps);
      check_step(p, sigma_old, d_eps, sigma, d_gamma, coverage);
      if (::testing::Test::HasFailure()) return;  // one report, not thousands
    }
    EXPECT_GT(coverage.elastic, 100);
    EXPECT_GT(coverage.plane, 100);
    EXPECT_GT(coverage.compression_edge, 10);
    EXPECT_GT(coverage.extension_edge, 10);
    if (p.sin_phi > 0 && !has_cut_off(p)) {
      EXPECT_GT(coverage.apex, 10);
    }
    if (p.sin_phi == 0) {
      EXPECT_EQ(coverage.apex, 0);
    }
    if (has_cut_off(p)) {
      EXPECT_GT(coverage.cut_off, 10);
    }
    std::printf("%-26s elastic %d plane %d compression edge %d extension edge %d apex %d cut-off %d\n",
                test_case.name.c_str(), coverage.elastic, coverage.plane, coverage.compression_edge,
                coverage.extension_edge, coverage.apex, coverage.cut_off);
  }
}

TEST(MohrCoulomb, ElasticUpdateIsPlaneStrainHooke) {
  const MohrCoulombParams p = MohrCoulombParams::from(20e6, 0.3, 30, 10e3, 0, -1);
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
      const MohrCoulombParams p = MohrCoulombParams::from(e, 0.3, phi, c, psi, -1);
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

// Isotropic tension past c cot(phi) from several starts returns to the apex exactly (the
// tension cut-off lowers it to the tensile strength); Tresca has no apex and stays elastic.
TEST(MohrCoulomb, IsotropicTensionReturnsToTheApex) {
  const double c = 10e3;
  for (const double psi : {0.0, 30.0}) {
    const MohrCoulombParams p = MohrCoulombParams::from(20e6, 0.3, 30, c, psi, -1);
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

  const MohrCoulombParams cut = MohrCoulombParams::from(20e6, 0.3, 30, c, 30, 2e3);
  Eigen::Vector4d sigma(-2 * c, -4 * c, -3 * c, 0.5 * c);
  EXPECT_GT(mohr_coulomb_update(cut, sigma, Eigen::Vector4d(1e-2, 1e-2, 1e-2, 0)), 0.0);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(sigma[i], 2e3);
  // A cut-off above the apex is capped to it.
  EXPECT_DOUBLE_EQ(MohrCoulombParams::from(20e6, 0.3, 30, c, 30, 1e9).tensile_strength,
                   c / std::tan(30 * pi / 180));

  const MohrCoulombParams tresca = MohrCoulombParams::from(20e6, 0.3, 0, c, 0, -1);
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
  const MohrCoulombParams p = MohrCoulombParams::from(20e6, 0.3, 30, 10e3, 0, 3e3);
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
    const MohrCoulombParams& p = test_case.params;
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
  EXPECT_THROW(MohrCoulombParams::from(0, 0.3, 30, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombParams::from(2e7, 0.5, 30, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombParams::from(2e7, -0.1, 30, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombParams::from(2e7, 0.3, 90, 1e4, 0, -1), Error);
  EXPECT_THROW(MohrCoulombParams::from(2e7, 0.3, 30, 1e4, 35, -1), Error);
  EXPECT_THROW(MohrCoulombParams::from(2e7, 0.3, 30, -1, 0, -1), Error);
  EXPECT_NO_THROW(MohrCoulombParams::from(2e7, 0.3, 30, 0, 30, -1));
}

}  // namespace
}  // namespace talus
