// Mohr-Coulomb return mapping (common/materials/mohr_coulomb.hpp) on random steps. The reference
// quantities (principal stresses, f, the elastic stiffness, principal plastic strains) are
// recomputed here and in support/mohr_coulomb_reference.hpp with Eigen's 3x3 eigen-solver,
// independently of the closed forms in the material. Known stress paths and properties:
// mohr_coulomb_paths_test.cpp.
#include "common/materials/mohr_coulomb.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "support/mohr_coulomb_reference.hpp"

namespace talus {
namespace {

using testing::admissible_stress;
using testing::Case;
using testing::cases;
using testing::has_cut_off;
using testing::Principal;
using testing::principal;
using testing::stiffness;
using testing::strain_increment;
using testing::tensor;
using testing::yield;

// Counts of where the random returns ended, to show that every branch was exercised.
struct Coverage {
  int elastic = 0, plane = 0, compression_edge = 0, extension_edge = 0, apex = 0, cut_off = 0;
};

// Every check of one random step; see the test below for what is asserted.
void check_step(const MohrCoulombConstants& p, const Eigen::Vector4d& sigma_old,
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
    const MohrCoulombConstants& p = test_case.params;
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

}  // namespace
}  // namespace talus
