#include "support/mohr_coulomb_reference.hpp"

#include <cmath>

namespace talus::testing {

Eigen::Matrix3d tensor(const Eigen::Vector4d& v) {
  Eigen::Matrix3d m;
  m << v[0], v[3], 0.0, v[3], v[1], 0.0, 0.0, 0.0, v[2];
  return m;
}

Principal principal(const Eigen::Vector4d& v) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(tensor(v));
  Principal result;
  for (int i = 0; i < 3; ++i) {  // Eigen sorts ascending
    result.values[i] = solver.eigenvalues()[2 - i];
    result.vectors.col(i) = solver.eigenvectors().col(2 - i);
  }
  return result;
}

double yield(const MohrCoulombConstants& p, const Eigen::Vector4d& sigma) {
  const Eigen::Vector3d s = principal(sigma).values;
  return (s[0] - s[2]) + (s[0] + s[2]) * p.sin_phi - 2.0 * p.cohesion * p.cos_phi;
}

Eigen::Matrix4d stiffness(const MohrCoulombConstants& p) {
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

std::vector<Case> cases() {
  const double e = 20e6, c = 10e3;
  return {
      {"associated", MohrCoulombConstants::from(e, 0.3, 30, c, 30, -1)},
      {"non_dilatant", MohrCoulombConstants::from(e, 0.3, 30, c, 0, -1)},
      {"partly_dilatant", MohrCoulombConstants::from(e, 0.25, 35, c, 10, -1)},
      {"poisson_zero", MohrCoulombConstants::from(e, 0.0, 20, c, 20, -1)},
      {"tresca", MohrCoulombConstants::from(e, 0.3, 0, 2 * c, 0, -1)},
      {"associated_cut_off", MohrCoulombConstants::from(e, 0.3, 30, c, 30, 5e3)},
      {"non_dilatant_zero_tension", MohrCoulombConstants::from(e, 0.3, 30, c, 0, 0)},
      {"tresca_cut_off", MohrCoulombConstants::from(e, 0.3, 0, 2 * c, 0, 10e3)},
  };
}

bool has_cut_off(const MohrCoulombConstants& p) { return p.tensile_strength >= 0; }

Eigen::Vector4d admissible_stress(const MohrCoulombConstants& p, std::mt19937& random) {
  const double c = p.cohesion;
  std::uniform_real_distribution<double> normal(-12 * c, 3 * c), shear(-3 * c, 3 * c);
  for (;;) {
    const Eigen::Vector4d sigma(normal(random), normal(random), normal(random), shear(random));
    if (yield(p, sigma) > 0) continue;
    if (has_cut_off(p) && principal(sigma).values[0] > p.tensile_strength) continue;
    return sigma;
  }
}

Eigen::Vector4d strain_increment(const MohrCoulombConstants& p, std::mt19937& random) {
  std::uniform_real_distribution<double> unit(-1, 1), exponent(-3, 1.5);
  const double size = p.cohesion / p.shear_modulus * std::pow(10.0, exponent(random));
  Eigen::Vector4d d_eps(unit(random), unit(random), unit(random), unit(random));
  d_eps *= size;
  if (unit(random) < 0) d_eps[2] = 0;  // mostly plane strain, but the zz slot is general
  if (unit(random) > 0.5) d_eps.head<3>().array() += size * (1 + unit(random));  // towards the apex
  return d_eps;
}

}  // namespace talus::testing
