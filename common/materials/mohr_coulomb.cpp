// Mohr-Coulomb return mapping in principal stress space; conventions in mohr_coulomb.hpp.
//
// Notation (Clausen, Damkilde and Andersen 2006, section 3, with tension positive):
// sorted principal stresses s = (s1, s2, s3), principal elastic stiffness D = lambda 1 1^T + 2G I,
//   f_1 = a1 s1 - a3 s3 - 2c cos(phi)   gradient a_1 = (a1, 0, -a3), a1 = 1 + sin(phi), a3 = 1 - sin(phi)
//   g_1 gradient b_1 = (b1, 0, -b3),    b1 = 1 + sin(psi), b3 = 1 - sin(psi).
// The edge sigma1 = sigma2 adds f_2 = a1 s2 - a3 s3 - ... (b_2 = (0, b1, -b3)); the edge
// sigma2 = sigma3 adds f_3 = a1 s1 - a3 s2 - ... (b_3 = (b1, -b3, 0)).
// Every return is s = s_trial - D d_eps_p with d_eps_p a non-negative combination of the active
// b's, so the code computes d_eps_p in principal axes and corrects s from it.
#include "common/materials/mohr_coulomb.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/error.hpp"

namespace talus {
namespace {

constexpr double degrees_to_radians = 3.14159265358979323846 / 180.0;

// s -= D e for principal vectors.
inline void subtract_elastic(const MohrCoulombConstants& p, const double e[3], double s[3]) {
  const double lambda_trace = p.lame_lambda * (e[0] + e[1] + e[2]);
  for (int i = 0; i < 3; ++i) s[i] -= lambda_trace + 2.0 * p.shear_modulus * e[i];
}

// e += D^-1 x, with D^-1 = (I - lambda / (3K) 1 1^T) / (2G) (3 lambda + 2G = 3K).
inline void add_compliance(const MohrCoulombConstants& p, const double x[3], double e[3]) {
  const double volumetric = p.lame_lambda / (3.0 * p.bulk_modulus) * (x[0] + x[1] + x[2]);
  for (int i = 0; i < 3; ++i) e[i] += (x[i] - volumetric) / (2.0 * p.shear_modulus);
}

// Koiter's rule on an edge: [m n; n m] (dl_1, dl_2) = (f_1, f_2), M_ij = a_i^T D b_j.
// m^2 - n^2 > 0 always: m - n = 2G(1 + sin phi)(1 + sin psi) on the compression edge and
// 2G(1 - sin phi)(1 - sin psi) on the extension edge, both positive for phi < 90.
inline void solve_edge(double m, double n, double f_1, double f_2, double& dl_1, double& dl_2) {
  const double inverse_det = 1.0 / ((m - n) * (m + n));
  dl_1 = (m * f_1 - n * f_2) * inverse_det;
  dl_2 = (m * f_2 - n * f_1) * inverse_det;
}

// Mohr-Coulomb return of the sorted trial s (f_1(s) > 0); adds the plastic strain to e_p.
//
// Region tests. Clausen et al. (2006) choose the return from the signs of the trial's distance
// to the boundary planes through each edge spanned by the plane corrector D b_1 (p_I, p_II in
// their notation). The plane return lands on the edge exactly when the trial is on such a
// boundary, so "the plane return keeps s1 >= s2 >= s3" is the same test and needs no extra
// vectors; it holds for non-associated flow since it is built from D b_1. Past a boundary, the
// edge crossed first along the plane return path -d_lambda D b_1 is the candidate (s1 - s2 falls
// at rate 2G b1, s2 - s3 at 2G b3; the same choice as de Souza Neto, Peric and Owen 2008, ch. 8,
// Mohr-Coulomb "right/left edge"). The edge
// return is valid while it stays on the compression side of the apex (the order is kept, the
// boundary t = 0 of Clausen et al.); beyond it the stress goes to the apex.
void return_to_mohr_coulomb(const MohrCoulombConstants& p, double s[3], double e_p[3]) {
  const double b1 = 1.0 + p.sin_psi, b3 = 1.0 - p.sin_psi;
  const double f_1 = yield_from_extremes(p, s[0], s[2]);

  const double d_lambda = f_1 / p.plane_denominator;
  double plane[3] = {s[0], s[1], s[2]};
  const double plane_strain[3] = {b1 * d_lambda, 0.0, -b3 * d_lambda};
  subtract_elastic(p, plane_strain, plane);
  if (plane[0] >= plane[1] && plane[1] >= plane[2]) {
    for (int i = 0; i < 3; ++i) s[i] = plane[i], e_p[i] += plane_strain[i];
    return;
  }

  double edge[3] = {s[0], s[1], s[2]};
  double edge_strain[3];
  bool valid;
  if (b3 * (s[0] - s[1]) <= b1 * (s[1] - s[2])) {
    // Compression edge sigma1 = sigma2: surfaces f_1 and f_2.
    const double f_2 = yield_from_extremes(p, s[1], s[2]);
    double dl_1, dl_2;
    solve_edge(p.plane_denominator, p.compression_coupling, f_1, f_2, dl_1, dl_2);
    edge_strain[0] = b1 * dl_1;
    edge_strain[1] = b1 * dl_2;
    edge_strain[2] = -b3 * (dl_1 + dl_2);
    subtract_elastic(p, edge_strain, edge);
    valid = edge[1] >= edge[2];
  } else {
    // Extension edge sigma2 = sigma3: surfaces f_1 and f_3.
    const double f_3 = yield_from_extremes(p, s[0], s[1]);
    double dl_1, dl_3;
    solve_edge(p.plane_denominator, p.extension_coupling, f_1, f_3, dl_1, dl_3);
    edge_strain[0] = b1 * (dl_1 + dl_3);
    edge_strain[1] = -b3 * dl_3;
    edge_strain[2] = -b3 * dl_1;
    subtract_elastic(p, edge_strain, edge);
    valid = edge[0] >= edge[1];
  }
  // Without friction the edges are parallel to the hydrostatic axis: no apex to go past.
  if (valid || p.sin_phi == 0.0) {
    for (int i = 0; i < 3; ++i) s[i] = edge[i], e_p[i] += edge_strain[i];
    return;
  }

  // Apex: the only stress state left; the plastic strain is whatever D^-1 leaves over.
  const double excess[3] = {s[0] - p.apex, s[1] - p.apex, s[2] - p.apex};
  add_compliance(p, excess, e_p);
  s[0] = s[1] = s[2] = p.apex;
}

// Associated Rankine return, sigma1 <= t, of the sorted s (s1 > t); adds to e_p. Same three
// cases as above with a = b = unit vectors: plane s1 = t, edge s1 = s2 = t, corner.
void return_to_tension_cutoff(const MohrCoulombConstants& p, double s[3], double e_p[3]) {
  const double t = p.tensile_strength;
  const double lambda = p.lame_lambda, g = p.shear_modulus;
  const double over_1 = s[0] - t, over_2 = s[1] - t;

  const double d_lambda = over_1 / (lambda + 2.0 * g);  // e_1^T D e_1 = lambda + 2G
  if (s[1] - lambda * d_lambda <= t) {
    s[0] = t;
    s[1] -= lambda * d_lambda;
    s[2] -= lambda * d_lambda;
    e_p[0] += d_lambda;
    return;
  }

  // [lambda + 2G, lambda; lambda, lambda + 2G] (dl_1, dl_2) = (s1 - t, s2 - t).
  const double inverse_det = 1.0 / (4.0 * g * (lambda + g));
  const double dl_1 = ((lambda + 2.0 * g) * over_1 - lambda * over_2) * inverse_det;
  const double dl_2 = ((lambda + 2.0 * g) * over_2 - lambda * over_1) * inverse_det;
  const double s_3 = s[2] - lambda * (dl_1 + dl_2);
  if (s_3 <= t) {
    s[0] = s[1] = t;
    s[2] = s_3;
    e_p[0] += dl_1;
    e_p[1] += dl_2;
    return;
  }

  const double excess[3] = {s[0] - t, s[1] - t, s[2] - t};
  add_compliance(p, excess, e_p);
  s[0] = s[1] = s[2] = t;
}

}  // namespace

MohrCoulombConstants MohrCoulombConstants::from(double youngs_modulus, double poisson_ratio,
                                                double friction_angle_deg, double cohesion,
                                                double dilation_angle_deg, double tensile_strength) {
  // A guard by the unit's ranges. nu >= 0 keeps lambda >= 0, which the sequential tension
  // cut-off relies on (header).
  SharedParameters shared;
  shared.youngs_modulus = youngs_modulus;
  shared.poisson_ratio = poisson_ratio;
  MohrCoulomb::Parameters own;
  own.friction_angle = friction_angle_deg;
  own.cohesion = cohesion;
  own.dilation_angle = dilation_angle_deg;
  auto guard = [](const Parameter& parameter, double value) {
    const std::string_view key = parameter.name;
    if (key == "density" || key == "tensile_strength" || key.find("soften") != key.npos || key.find("residual") == 0)
      return;  // not among the constants' arguments, or any value is valid
    if (const std::string problem = parameter.problem(value); !problem.empty())
      throw Error("Mohr-Coulomb material: " + std::string(key) + ": " + problem);
  };
  SharedParameters::visit_elastic(shared, guard);
  MohrCoulomb::Parameters::visit(own, guard);
  return unchecked(youngs_modulus, poisson_ratio, friction_angle_deg, cohesion, dilation_angle_deg, tensile_strength);
}

MohrCoulombConstants MohrCoulombConstants::unchecked(double youngs_modulus, double poisson_ratio,
                                               double friction_angle_deg, double cohesion,
                                               double dilation_angle_deg, double tensile_strength) {
  MohrCoulombConstants p;
  p.shear_modulus = youngs_modulus / (2.0 * (1.0 + poisson_ratio));
  p.bulk_modulus = youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio));
  p.lame_lambda = p.bulk_modulus - 2.0 * p.shear_modulus / 3.0;
  const double phi = friction_angle_deg * degrees_to_radians;
  p.sin_phi = std::sin(phi);
  p.cos_phi = std::cos(phi);
  p.sin_psi = std::sin(dilation_angle_deg * degrees_to_radians);
  p.cohesion = cohesion;
  p.two_c_cos_phi = 2.0 * cohesion * p.cos_phi;
  p.apex = p.sin_phi > 0 ? cohesion * p.cos_phi / p.sin_phi
                         : std::numeric_limits<double>::infinity();
  // Mohr-Coulomb alone already bounds sigma1 by the apex, so a higher cut-off never acts;
  // capping it keeps the tension corner inside the Mohr-Coulomb surface.
  p.tensile_strength = tensile_strength < 0 ? -1.0 : std::min(tensile_strength, p.apex);

  // M_ij = a_i^T D b_j (Clausen et al. 2006, eq. for the line return), with sum(a) = 2 sin phi,
  // sum(b) = 2 sin psi: a^T D b = 4 lambda sin phi sin psi + 2G a.b.
  const double a1 = 1.0 + p.sin_phi, a3 = 1.0 - p.sin_phi;
  const double b1 = 1.0 + p.sin_psi, b3 = 1.0 - p.sin_psi;
  const double volumetric = 4.0 * p.lame_lambda * p.sin_phi * p.sin_psi;
  p.plane_denominator = volumetric + 2.0 * p.shear_modulus * (a1 * b1 + a3 * b3);
  p.compression_coupling = volumetric + 2.0 * p.shear_modulus * a3 * b3;
  p.extension_coupling = volumetric + 2.0 * p.shear_modulus * a1 * b1;
  return p;
}

double mohr_coulomb_return(const MohrCoulombConstants& p, Eigen::Vector4d& sigma) {
  const bool cut_off = p.tensile_strength >= 0.0;

  // zz is the third principal stress beside the in-plane pair.
  const InPlaneCircle circle(sigma);
  const double in_plane_max = circle.centre + circle.radius;
  const double in_plane_min = circle.centre - circle.radius;
  const double zz = sigma[2];

  // f needs only the extreme principal stresses, so the elastic case exits before sorting.
  const double s_max = std::max(in_plane_max, zz), s_min = std::min(in_plane_min, zz);
  const bool inside_mohr_coulomb = yield_from_extremes(p, s_max, s_min) <= 0.0;
  if (inside_mohr_coulomb && (!cut_off || s_max <= p.tensile_strength)) return 0.0;

  // Sorted s1 >= s2 >= s3, remembering the slot of zz (the in-plane pair stays in order).
  const int zz_slot = zz >= in_plane_max ? 0 : (zz <= in_plane_min ? 2 : 1);
  double s[3];
  if (zz_slot == 0) s[0] = zz, s[1] = in_plane_max, s[2] = in_plane_min;
  else if (zz_slot == 1) s[0] = in_plane_max, s[1] = zz, s[2] = in_plane_min;
  else s[0] = in_plane_max, s[1] = in_plane_min, s[2] = zz;

  double e_p[3] = {0.0, 0.0, 0.0};
  if (!inside_mohr_coulomb) return_to_mohr_coulomb(p, s, e_p);
  if (cut_off && s[0] > p.tensile_strength) return_to_tension_cutoff(p, s, e_p);

  // Back to Cartesian with the trial's in-plane eigenvectors: (cos 2theta, sin 2theta) of the
  // major in-plane direction; any direction will do for a circle of zero radius.
  const double new_max = zz_slot == 0 ? s[1] : s[0];
  const double new_min = zz_slot == 2 ? s[1] : s[2];
  const double cos_2theta = circle.radius > 0.0 ? circle.half_difference / circle.radius : 1.0;
  const double sin_2theta = circle.radius > 0.0 ? sigma[3] / circle.radius : 0.0;
  const double new_centre = 0.5 * (new_max + new_min);
  const double new_radius = 0.5 * (new_max - new_min);
  sigma[0] = new_centre + new_radius * cos_2theta;
  sigma[1] = new_centre - new_radius * cos_2theta;
  sigma[2] = s[zz_slot];
  sigma[3] = new_radius * sin_2theta;

  return std::max({e_p[0], e_p[1], e_p[2]}) - std::min({e_p[0], e_p[1], e_p[2]});
}

double mohr_coulomb_yield(const MohrCoulombConstants& p, const Eigen::Vector4d& sigma) {
  const PrincipalExtremes s = principal_extremes(sigma);
  return yield_from_extremes(p, s.largest, s.smallest);
}

std::optional<MaterialProblem> MohrCoulomb::rules(const Parameters& p) {
  if (p.friction_angle == 0 && p.cohesion == 0)
    return MaterialProblem{"cohesion", "a Mohr-Coulomb material needs friction_angle > 0 or cohesion > 0"};
  if (p.softening_end > 0 && p.residual_friction_angle == 0 && p.residual_cohesion == 0)
    return MaterialProblem{"residual_cohesion",
                           "a softening material needs residual_friction_angle > 0 or residual_cohesion > 0"};
  return std::nullopt;
}

MohrCoulomb::Prepared MohrCoulomb::prepare(const SharedParameters& shared, const Parameters& p,
                                           const PrepareContext& context) {
  Prepared s;
  s.youngs_modulus = shared.youngs_modulus;
  s.poisson_ratio = shared.poisson_ratio;
  s.tensile_strength = p.tensile_strength;
  auto constants = [&](const Strength& strength) {
    return MohrCoulombConstants::unchecked(s.youngs_modulus, s.poisson_ratio, strength.friction_angle,
                                           strength.cohesion, strength.dilation_angle, s.tensile_strength);
  };
  s.peak_strength = {p.cohesion, p.friction_angle, std::min(p.dilation_angle, p.friction_angle)};
  s.peak = constants(s.peak_strength);
  if (p.softening_end > 0) {
    s.softens = true;
    s.softening_start = p.softening_start;
    s.softening_end = p.softening_end;
    // Regularisation: the strains scale with the reference size over the element size, so that
    // the energy a shear band dissipates does not depend on the mesh.
    if (p.softening_reference_size > 0 && context.element_size > 0) {
      const double scale = p.softening_reference_size / context.element_size;
      s.softening_start = p.softening_start * scale;
      s.softening_end = p.softening_end * scale;
    }
    s.residual_strength = {p.residual_cohesion, p.residual_friction_angle,
                           std::min(p.residual_dilation_angle, p.residual_friction_angle)};
    s.residual = constants(s.residual_strength);
  }
  return s;
}

double MohrCoulomb::softening_update(const Prepared& s, Eigen::Vector4d& sigma, const Eigen::Vector4d& d_eps,
                                     double gamma) {
  if (gamma <= s.softening_start) return mohr_coulomb_update(s.peak, sigma, d_eps);
  if (gamma >= s.softening_end) return mohr_coulomb_update(s.residual, sigma, d_eps);
  const double t = (gamma - s.softening_start) / (s.softening_end - s.softening_start);
  const Strength& a = s.peak_strength;
  const Strength& b = s.residual_strength;
  const Strength now{a.cohesion + t * (b.cohesion - a.cohesion),
                     a.friction_angle + t * (b.friction_angle - a.friction_angle),
                     a.dilation_angle + t * (b.dilation_angle - a.dilation_angle)};
  const MohrCoulombConstants constants =
      MohrCoulombConstants::unchecked(s.youngs_modulus, s.poisson_ratio, now.friction_angle, now.cohesion,
                                      std::min(now.dilation_angle, now.friction_angle), s.tensile_strength);
  return mohr_coulomb_update(constants, sigma, d_eps);
}

MohrCoulomb::Parameters MohrCoulomb::reduced(const Parameters& p, double factor) {
  // degrees(atan(tan(radians(angle)) / F)), as strength reduction has always computed it.
  auto angle = [factor](double degrees) { return std::atan(std::tan(degrees * M_PI / 180.0) / factor) * 180.0 / M_PI; };
  Parameters r = p;
  r.friction_angle = angle(p.friction_angle);
  r.cohesion = p.cohesion / factor;
  r.dilation_angle = std::min(angle(p.dilation_angle), r.friction_angle);
  r.tensile_strength = p.tensile_strength < 0 ? p.tensile_strength : p.tensile_strength / factor;
  if (p.softening_end > 0) {  // the residual strength acts only then
    r.residual_friction_angle = angle(p.residual_friction_angle);
    r.residual_cohesion = p.residual_cohesion / factor;
    r.residual_dilation_angle = std::min(angle(p.residual_dilation_angle), r.residual_friction_angle);
  }
  return r;
}

}  // namespace talus
