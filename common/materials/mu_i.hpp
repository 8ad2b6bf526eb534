// A granular material whose friction grows with the rate of shear: the mu(I) rheology (GDR MiDi
// 2004; Jop, Forterre and Pouliquen 2006, Nature 441, 727-730) as a cohesionless, non-dilatant
// Mohr-Coulomb material whose friction is set, at each yielding step, by the inertial number
//
//   I = gamma_dot d / sqrt(p / rho_s),   mu(I) = mu_s + (mu_2 - mu_s) I / (I0 + I),
//
// d the grain diameter, rho_s the grains' density, gamma_dot the step's shear rate (the largest
// minus the smallest principal strain rate, d_eps / dt: gamma_dot itself in simple shear) and p
// the centre of the Mohr circle of the extreme principal stresses, compression positive (the
// normal stress on the plane of steady simple shear). mu_s, mu_2 and I0 are as the experiments
// give them: ratios of shear to normal stress on the sliding plane (Jop et al.'s glass beads:
// mu_s = tan 20.9 deg, mu_2 = tan 32.76 deg, I0 = 0.279, d = 0.5 mm, rho_s = 2450 kg/m^3).
//
// With psi = 0 the plane-strain Mohr-Coulomb surface mobilises tau / p = sin(phi) in steady
// simple shear (Davis; docs/column.md, "Which friction angle"), so the update returns to the
// surface of sin(phi) = mu(I): the flowing material's tau / p is mu(I) itself. Below the static
// surface (sin(phi) = mu_s) the step is elastic, and mu(I) >= mu_s, so a particle at rest costs
// what a Mohr-Coulomb particle does; only a yielding one computes I. At p <= 0 (a grain at a
// free surface) I is infinite and mu = mu_2; with no cohesion the surface's apex is the origin.
// The friction is explicit in the rate: the step's own strain increment sets it.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string_view>

#include "common/materials/linear_elastic.hpp"
#include "common/materials/mohr_coulomb.hpp"
#include "common/materials/parameter.hpp"

namespace talus {

struct MuI {
  static constexpr std::string_view kName = "mu_i";

  struct Parameters {
    double mu_static = 0;              // -, tau / p at rest and in slow flow (tan of the static angle)
    double mu_limit = 0;               // -, tau / p as I grows without bound
    double inertial_number_scale = 0;  // -, I0: mu is halfway between the two at I = I0
    double grain_diameter = 0;         // m
    double grain_density = 0;          // kg/m^3; 0: the material's density

    template <class Self, class Visit>
    static void visit(Self& p, Visit&& visit) {
      visit(Parameter{.name = "mu_static", .unit = "-", .range = {0, 1, false, false}}, p.mu_static);
      visit(Parameter{.name = "mu_limit", .unit = "-", .range = {p.mu_static, 1, true, false}}, p.mu_limit);
      visit(Parameter{.name = "inertial_number_scale", .unit = "-", .range = {0, kUnbounded, false}},
            p.inertial_number_scale);
      visit(Parameter{.name = "grain_diameter", .unit = "m", .range = {0, kUnbounded, false}}, p.grain_diameter);
      visit(Parameter{.name = "grain_density", .unit = "kg/m^3", .range = {0, kUnbounded}, .fallback = 0.0},
            p.grain_density);
    }
  };
  static std::optional<MaterialProblem> rules(const Parameters&) { return std::nullopt; }

  struct Prepared {
    MohrCoulombConstants still;  // the static surface, sin(phi) = mu_s
    double mu_static = 0, mu_rise = 0, inertial_number_scale = 0;
    double diameter_root_density = 0;  // d sqrt(rho_s): I = gamma_dot d sqrt(rho_s / p)
    double youngs_modulus = 0, poisson_ratio = 0;

    // mu at the shear rate `rate` (1/s) under `pressure` (Pa, compression positive).
    double friction(double rate, double pressure) const {
      if (!(pressure > 0.0)) return mu_static + mu_rise;
      const double i = rate * diameter_root_density / std::sqrt(pressure);
      return mu_static + mu_rise * i / (inertial_number_scale + i);
    }
  };
  static Prepared prepare(const SharedParameters& shared, const Parameters& p, const PrepareContext&) {
    Prepared s;
    s.youngs_modulus = shared.youngs_modulus;
    s.poisson_ratio = shared.poisson_ratio;
    s.still = MohrCoulombConstants::unchecked(s.youngs_modulus, s.poisson_ratio, degrees_of_sine(p.mu_static), 0, 0, -1);
    s.mu_static = p.mu_static;
    s.mu_rise = p.mu_limit - p.mu_static;
    s.inertial_number_scale = p.inertial_number_scale;
    s.diameter_root_density = p.grain_diameter * std::sqrt(p.grain_density > 0 ? p.grain_density : shared.density);
    return s;
  }
  static int history_width(const Parameters&) { return 0; }

  // The largest minus the smallest principal value of d_eps (tensor shear), over dt.
  static double shear_rate(const Eigen::Vector4d& d_eps, double dt) {
    if (!(dt > 0.0)) return 0.0;
    const PrincipalExtremes e = principal_extremes(d_eps);
    return (e.largest - e.smallest) / dt;
  }
  // The centre of the Mohr circle of the extreme principal stresses, compression positive.
  static double pressure(const Eigen::Vector4d& sigma) {
    const PrincipalExtremes s = principal_extremes(sigma);
    return -0.5 * (s.largest + s.smallest);
  }

  static void update(const Prepared& s, Eigen::Vector4d& sigma, const Eigen::Vector4d& d_eps, double dt,
                     double& eps_p, double* /*history*/) {
    elastic_update(s.still.shear_modulus, s.still.bulk_modulus, sigma, d_eps);
    if (mohr_coulomb_surely_inside(s.still, sigma)) return;
    // The return is isochoric (psi = 0) and keeps the circle's centre: the trial's p is the final one.
    const double mu = s.friction(shear_rate(d_eps, dt), pressure(sigma));
    const MohrCoulombConstants flowing =
        MohrCoulombConstants::unchecked(s.youngs_modulus, s.poisson_ratio, degrees_of_sine(mu), 0, 0, -1);
    eps_p += mohr_coulomb_return(flowing, sigma);
  }

  // Strength reduction by F as Mohr-Coulomb's (docs/fos.md), on the angle each coefficient
  // stands for: sin(phi) = mu, tan(phi_F) = tan(phi) / F, mu_F = sin(phi_F). A coefficient
  // divided by F itself would pass 1, where no angle has that sine, as soon as F < mu (a
  // strength raised to find a bracket).
  static constexpr bool kHasStrength = true;
  static Parameters reduced(const Parameters& p, double factor) {
    const auto reduce = [factor](double mu) { return std::sin(std::atan(std::tan(std::asin(mu)) / factor)); };
    Parameters out = p;
    out.mu_static = reduce(p.mu_static);
    out.mu_limit = reduce(p.mu_limit);
    return out;
  }
  // Bishop's method: no cohesion, tan(phi) = mu_s on the slip surface.
  static std::optional<CohesionFriction> limit_equilibrium(const Parameters& p) {
    return CohesionFriction{0.0, std::atan(p.mu_static) * 180.0 / std::numbers::pi};
  }

 private:
  static double degrees_of_sine(double mu) { return std::asin(mu) * 180.0 / std::numbers::pi; }
};

}  // namespace talus
