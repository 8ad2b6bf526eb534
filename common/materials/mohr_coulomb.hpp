// Elastic-perfectly plastic Mohr-Coulomb material with optional linear strain softening, plane
// strain (design.md, "Mohr-Coulomb"): the unit `MohrCoulomb` at the end of this file, and the
// return mapping it calls.
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
#include <optional>
#include <string_view>

#include "common/materials/linear_elastic.hpp"
#include "common/materials/parameter.hpp"

namespace talus {

// The constants of one Mohr-Coulomb strength that the return mapping reads, computed once by
// from() (never in the hot loop but for a softening particle between its peak and residual).
struct MohrCoulombConstants {
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
  // 0 <= nu < 0.5, 0 <= phi < 90, 0 <= psi <= phi, c >= 0 (the ranges of the unit's visitor).
  static MohrCoulombConstants from(double youngs_modulus, double poisson_ratio, double friction_angle_deg,
                                   double cohesion, double dilation_angle_deg, double tensile_strength);
  // The same without the guard, for values already checked (a material's, or a softening
  // particle's strength between its checked peak and residual).
  static MohrCoulombConstants unchecked(double youngs_modulus, double poisson_ratio, double friction_angle_deg,
                                        double cohesion, double dilation_angle_deg, double tensile_strength);
};

// Mohr's circle of the in-plane part of a plane-strain 4-vector (xx, yy, zz, xy), stress or
// strain: in-plane principal values centre +- radius; zz is the third principal value.
struct InPlaneCircle {
  double centre, half_difference, radius;
  explicit InPlaneCircle(const Eigen::Vector4d& v)
      : centre(0.5 * (v[0] + v[1])), half_difference(0.5 * (v[0] - v[1])),
        radius(std::sqrt(half_difference * half_difference + v[3] * v[3])) {}
};

// The largest and smallest of the three principal values of a plane-strain 4-vector.
struct PrincipalExtremes {
  double largest, smallest;
};
inline PrincipalExtremes principal_extremes(const Eigen::Vector4d& v) {
  const InPlaneCircle circle(v);
  return {std::max(circle.centre + circle.radius, v[2]), std::min(circle.centre - circle.radius, v[2])};
}

// f from the largest and smallest principal stresses (the middle one does not enter).
inline double yield_from_extremes(const MohrCoulombConstants& p, double s_max, double s_min) {
  return (1.0 + p.sin_phi) * s_max - (1.0 - p.sin_phi) * s_min - p.two_c_cos_phi;
}

// The return mapping of an elastic trial stress that may lie outside the surface (or past the
// cut-off); d_gamma_p as defined above. mohr_coulomb_update's second half (mohr_coulomb.cpp).
double mohr_coulomb_return(const MohrCoulombConstants& p, Eigen::Vector4d& sigma);

// Whether sigma is inside the surface (and the cut-off), decided without a square root: true
// settles most particles; false may still be inside, which mohr_coulomb_return then finds.
inline bool mohr_coulomb_surely_inside(const MohrCoulombConstants& p, const Eigen::Vector4d& sigma) {
  // f grows with Mohr's radius R (the largest principal stress rises, the smallest falls), so f
  // at an upper bound of R that needs no square root, |sigma_xx - sigma_yy| / 2 + |sigma_xy|
  // (raised by 1e-15, more than the rounding of R can add), settles them: f(R) <= f(bound) <= 0
  // in floating point too, the same decision.
  const double centre = 0.5 * (sigma[0] + sigma[1]);
  const double bound = (std::abs(0.5 * (sigma[0] - sigma[1])) + std::abs(sigma[3])) * (1.0 + 1e-15);
  const double upper = std::max(centre + bound, sigma[2]), lower = std::min(centre - bound, sigma[2]);
  return yield_from_extremes(p, upper, lower) <= 0.0 && (p.tensile_strength < 0.0 || upper <= p.tensile_strength);
}

// Elastic trial then return mapping onto the Mohr-Coulomb surface (and the tension cut-off).
// Returns d_gamma_p as defined above (0 for an elastic step, and then sigma is exactly the
// elastic trial). No heap, no virtual calls. Inline up to the test that settles most particles
// (they stay well inside the surface), so that their stress stays in registers.
inline double mohr_coulomb_update(const MohrCoulombConstants& p, Eigen::Vector4d& sigma,
                                  const Eigen::Vector4d& d_eps) {
  elastic_update(p.shear_modulus, p.bulk_modulus, sigma, d_eps);
  if (mohr_coulomb_surely_inside(p, sigma)) return 0.0;
  return mohr_coulomb_return(p, sigma);
}

// f of a stress (Pa; > 0 outside the surface), for diagnostics and tests.
double mohr_coulomb_yield(const MohrCoulombConstants& p, const Eigen::Vector4d& sigma);

// The unit (docs/architecture.md, "Materials"). Strain softening (softening_end > 0): between
// the plastic shear strains softening_start and softening_end c, phi and psi fall linearly from
// their peak values to the residual ones (docs/water.md); that strain is the particle's one
// history variable, advanced by each step's d_gamma_p.
struct MohrCoulomb {
  static constexpr std::string_view kName = "mohr_coulomb";

  struct Parameters {
    double friction_angle = 0;     // deg
    double cohesion = 0;           // Pa
    double dilation_angle = 0;     // deg
    double tensile_strength = -1;  // Pa; < 0: no tension cut-off (the cone's own apex limits tension)
    double softening_start = 0;    // -
    double softening_end = 0;      // -; 0: no softening
    double residual_cohesion = 0;        // Pa
    double residual_friction_angle = 0;  // deg
    double residual_dilation_angle = 0;  // deg
    double softening_reference_size = 0; // m; > 0: both strains scaled by it over the mean element size

    template <class Self, class Visit>
    static void visit(Self& p, Visit&& visit) {
      static constexpr const char* kEnd = "the plastic strain at which the strength is residual";
      visit(Parameter{.name = "friction_angle", .unit = "deg", .range = {0, 90, true, false}}, p.friction_angle);
      visit(Parameter{.name = "cohesion", .unit = "Pa", .range = {0, kUnbounded}}, p.cohesion);
      visit(Parameter{.name = "dilation_angle", .unit = "deg", .range = {0, p.friction_angle}, .fallback = 0.0},
            p.dilation_angle);
      visit(Parameter{.name = "tensile_strength", .unit = "Pa", .range = {-kUnbounded, kUnbounded},
                      .fallback = -1.0, .given = NumberRange{0, kUnbounded}},
            p.tensile_strength);
      visit(Parameter{.name = "softening_start", .unit = "-", .range = {0, kUnbounded}, .fallback = 0.0,
                      .needs = "softening_end", .needs_why = kEnd, .optional_in_file = true},
            p.softening_start);
      visit(Parameter{.name = "softening_end", .unit = "-", .range = {p.softening_start, kUnbounded, false},
                      .fallback = 0.0, .off = 0.0, .off_message = "got 0, expected a number > softening_start",
                      .optional_in_file = true},
            p.softening_end);
      visit(Parameter{.name = "residual_cohesion", .unit = "Pa", .range = {0, kUnbounded}, .fallback = p.cohesion,
                      .needs = "softening_end", .needs_why = kEnd, .optional_in_file = true},
            p.residual_cohesion);
      visit(Parameter{.name = "residual_friction_angle", .unit = "deg", .range = {0, 90, true, false},
                      .fallback = p.friction_angle, .needs = "softening_end", .needs_why = kEnd,
                      .optional_in_file = true},
            p.residual_friction_angle);
      visit(Parameter{.name = "residual_dilation_angle", .unit = "deg", .range = {0, p.residual_friction_angle},
                      .fallback = std::min(p.dilation_angle, p.residual_friction_angle), .needs = "softening_end",
                      .needs_why = kEnd, .optional_in_file = true},
            p.residual_dilation_angle);
      visit(Parameter{.name = "softening_reference_size", .unit = "m", .range = {0, kUnbounded}, .fallback = 0.0,
                      .needs = "softening_end", .needs_why = kEnd, .optional_in_file = true},
            p.softening_reference_size);
    }
  };
  // friction_angle > 0 or cohesion > 0, and with softening the same of the residual values.
  static std::optional<MaterialProblem> rules(const Parameters& p);

  struct Strength {
    double cohesion = 0, friction_angle = 0, dilation_angle = 0;  // Pa, deg, deg (psi capped at phi)
  };
  struct Prepared {
    MohrCoulombConstants peak;  // the strength up to softening_start, and the only one without softening
    bool softens = false;       // softening_end > 0 (a flag: the hot loop tests it with one instruction)
    double softening_start = 0, softening_end = 0;  // regularised by the element size
    MohrCoulombConstants residual;                  // from softening_end on
    Strength peak_strength, residual_strength;      // interpolated in between
    double youngs_modulus = 0, poisson_ratio = 0, tensile_strength = -1;
  };
  static Prepared prepare(const SharedParameters& shared, const Parameters& p, const PrepareContext& context);
  static int history_width(const Parameters& p) { return p.softening_end > 0 ? 1 : 0; }

  // The update of a softening particle, its strength taken at the plastic shear strain
  // `gamma` before the step (explicit in the hardening variable). Returns d_gamma_p.
  static double softening_update(const Prepared& s, Eigen::Vector4d& sigma, const Eigen::Vector4d& d_eps,
                                 double gamma);
  // Adds d_gamma_p to eps_p and, softening, to history[0] (the strain that drives it).
  static void update(const Prepared& s, Eigen::Vector4d& sigma, const Eigen::Vector4d& d_eps, double /*dt*/,
                     double& eps_p, double* history) {
    if (s.softens) {
      const double gamma = history[0];
      const double d_gamma = softening_update(s, sigma, d_eps, gamma);
      history[0] = gamma + d_gamma;
      eps_p += d_gamma;
      return;
    }
    eps_p += mohr_coulomb_update(s.peak, sigma, d_eps);
  }

  // Strength reduction by F (docs/fos.md): c / F, tan(phi) / F and tan(psi) / F (psi capped at
  // phi), the tension cut-off / F; peak and residual alike.
  static constexpr bool kHasStrength = true;
  static Parameters reduced(const Parameters& p, double factor);
  static std::optional<CohesionFriction> limit_equilibrium(const Parameters& p) {
    return CohesionFriction{p.cohesion, p.friction_angle};
  }
};

}  // namespace talus
