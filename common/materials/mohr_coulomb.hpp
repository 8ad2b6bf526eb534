// Elastic-perfectly plastic Mohr-Coulomb material, plane strain (design.md, "Mohr-Coulomb").
//
// Conventions
// - Tension positive, for stress and strain alike.
// - sigma = (sigma_xx, sigma_yy, sigma_zz, sigma_xy) as Eigen::Vector4d.
// - d_eps = (d_eps_xx, d_eps_yy, d_eps_zz, d_eps_xy) with the TENSOR shear component
//   (d_eps_xy = gamma_xy / 2, not the engineering gamma_xy). Plane strain gives d_eps_zz = 0;
//   a non-zero d_eps_zz is honoured all the same. z is always a principal direction.
// - Principal stresses are sorted sigma1 >= sigma2 >= sigma3 (sigma3 the most compressive).
// - Yield function    f = (sigma1 - sigma3) + (sigma1 + sigma3) sin(phi) - 2 c cos(phi) <= 0.
//   Plastic potential g = (sigma1 - sigma3) + (sigma1 + sigma3) sin(psi): non-associated when
//   psi < phi. Uniaxial compression therefore yields at q = 2 c cos(phi) / (1 - sin(phi)).
// - Equivalent plastic shear strain increment (what mohr_coulomb_update returns):
//     d_gamma_p = d_eps_p_max - d_eps_p_min,
//   the largest minus the smallest principal value of the plastic strain increment
//   d_eps_p = d_eps - D^-1 d_sigma (the engineering maximum plastic shear strain; for a return
//   to the Mohr-Coulomb plane it is 2 d_lambda). It is > 0 for every plastic step except a
//   purely isotropic trial returned to the apex or to the tension corner, whose plastic strain
//   is purely volumetric (d_gamma_p = 0 there).
// - Tension cut-off (tensile_strength >= 0): Rankine, sigma1 <= tensile_strength, applied as a
//   sequential correction: Mohr-Coulomb return from the elastic trial first, then an associated
//   Rankine return (plane sigma1 = t, edge sigma1 = sigma2 = t, or corner) from that state in the
//   same principal frame. With Poisson's ratio >= 0 (so Lame's lambda >= 0, enforced by from())
//   the Rankine correction never increases f, so the final stress satisfies both criteria.
//   d_gamma_p then measures the total plastic strain increment of both corrections.
//
// Return mapping in principal stress space after Clausen, Damkilde and Andersen (2006),
// "Efficient return algorithms for associated plasticity with multiple yield planes", Int. J.
// Numer. Meth. Engng 66: returns to the plane, to the edges sigma1 = sigma2 ("compression edge")
// and sigma2 = sigma3 ("extension edge") with Koiter's two multipliers, and to the apex
// sigma1 = sigma2 = sigma3 = c cot(phi). For psi < phi the corrector directions are D times the
// potential's gradients, so the region boundaries follow them (see mohr_coulomb.cpp); at the
// apex the stress is set to the apex point whatever psi is. With phi = 0 (Tresca) there is no
// apex and no division by sin(phi).
#pragma once
#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace talus {

struct MohrCoulombParams {   // built once from the material by from(), never in the hot loop
  double shear_modulus = 0, bulk_modulus = 0;              // G, K (Pa)
  double sin_phi = 0, cos_phi = 1, sin_psi = 0, cohesion = 0;  // friction, dilation, c (Pa)
  double tensile_strength = -1;  // Pa; < 0: no tension cut-off. from() caps it at c cot(phi).

  // Precomputed by from(); the names follow mohr_coulomb.cpp.
  double lame_lambda = 0;          // K - 2G/3
  double two_c_cos_phi = 0;        // 2 c cos(phi)
  double apex = 0;                 // c cot(phi); +infinity when phi = 0
  double plane_denominator = 0;    // a^T D b (plane return)
  double compression_coupling = 0; // a_1^T D b_2 for the edge sigma1 = sigma2
  double extension_coupling = 0;   // a_1^T D b_3 for the edge sigma2 = sigma3

  // Angles in degrees. Throws talus::Error naming the bad parameter unless E > 0,
  // 0 <= nu < 0.5, 0 <= phi < 90, 0 <= psi <= phi, c >= 0.
  static MohrCoulombParams from(double youngs_modulus, double poisson_ratio,
                                double friction_angle_deg, double cohesion,
                                double dilation_angle_deg, double tensile_strength);
  // The same without the guard, for values already known to be in range (a softening
  // material's strength between its checked peak and residual, solver/stress/material_state.cpp).
  static MohrCoulombParams unchecked(double youngs_modulus, double poisson_ratio, double friction_angle_deg,
                                     double cohesion, double dilation_angle_deg, double tensile_strength);
};

// Linear elastic trial: sigma += D d_eps, plane strain isotropic, D = lambda 1 (x) 1 + 2G I
// (tensor shear: sigma_xy += 2G d_eps_xy).
inline void elastic_update(double shear_modulus, double bulk_modulus, Eigen::Vector4d& sigma,
                           const Eigen::Vector4d& d_eps) {
  const double two_g = 2.0 * shear_modulus;
  const double lambda_trace =
      (bulk_modulus - two_g / 3.0) * (d_eps[0] + d_eps[1] + d_eps[2]);
  sigma[0] += lambda_trace + two_g * d_eps[0];
  sigma[1] += lambda_trace + two_g * d_eps[1];
  sigma[2] += lambda_trace + two_g * d_eps[2];
  sigma[3] += two_g * d_eps[3];
}

// f from the largest and smallest principal stresses (the middle one does not enter).
inline double yield_from_extremes(const MohrCoulombParams& p, double s_max, double s_min) {
  return (1.0 + p.sin_phi) * s_max - (1.0 - p.sin_phi) * s_min - p.two_c_cos_phi;
}

// The return mapping of an elastic trial stress that may lie outside the surface (or past the
// cut-off); d_gamma_p as defined above. mohr_coulomb_update's second half (mohr_coulomb.cpp).
double mohr_coulomb_return(const MohrCoulombParams& p, Eigen::Vector4d& sigma);

// Elastic trial then return mapping onto the Mohr-Coulomb surface (and the tension cut-off).
// Returns d_gamma_p as defined above (0 for an elastic step, and then sigma is exactly the
// elastic trial). No heap, no virtual calls. Inline up to the test that settles most particles
// (they stay well inside the surface), so that their stress stays in registers.
inline double mohr_coulomb_update(const MohrCoulombParams& p, Eigen::Vector4d& sigma,
                                  const Eigen::Vector4d& d_eps) {
  elastic_update(p.shear_modulus, p.bulk_modulus, sigma, d_eps);
  // f grows with Mohr's radius R (the largest principal stress rises, the smallest falls), so f
  // at an upper bound of R that needs no square root, |sigma_xx - sigma_yy| / 2 + |sigma_xy|
  // (raised by 1e-15, more than the rounding of R can add), settles them: f(R) <= f(bound) <= 0
  // in floating point too, the same decision.
  const double centre = 0.5 * (sigma[0] + sigma[1]);
  const double bound = (std::abs(0.5 * (sigma[0] - sigma[1])) + std::abs(sigma[3])) * (1.0 + 1e-15);
  const double upper = std::max(centre + bound, sigma[2]), lower = std::min(centre - bound, sigma[2]);
  if (yield_from_extremes(p, upper, lower) <= 0.0 && (p.tensile_strength < 0.0 || upper <= p.tensile_strength))
    return 0.0;
  return mohr_coulomb_return(p, sigma);
}

// f of a stress (Pa; > 0 outside the surface), for diagnostics and tests.
double mohr_coulomb_yield(const MohrCoulombParams& p, const Eigen::Vector4d& sigma);

}  // namespace talus
