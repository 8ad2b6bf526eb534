// Reference quantities for the Mohr-Coulomb tests, recomputed with Eigen's 3x3 eigen-solver
// independently of the closed forms in common/materials/mohr_coulomb.cpp, and the parameter sets and
// random inputs the tests share.
#pragma once
#include <Eigen/Dense>
#include <random>
#include <string>
#include <vector>

#include "common/materials/mohr_coulomb.hpp"

namespace talus::testing {

constexpr double pi = 3.14159265358979323846;

// The 3x3 stress tensor of (xx, yy, zz, xy).
Eigen::Matrix3d tensor(const Eigen::Vector4d& v);

// Eigenvalues and eigenvectors sorted largest first.
struct Principal {
  Eigen::Vector3d values;
  Eigen::Matrix3d vectors;
};
Principal principal(const Eigen::Vector4d& v);

// f from the principal stresses.
double yield(const MohrCoulombConstants& p, const Eigen::Vector4d& sigma);

// Plane strain isotropic D acting on (xx, yy, zz, xy) with the tensor shear strain.
Eigen::Matrix4d stiffness(const MohrCoulombConstants& p);

// v rotated in the xy plane by `angle` (radians).
Eigen::Vector4d rotated(const Eigen::Vector4d& v, double angle);

struct Case {
  std::string name;
  MohrCoulombConstants params;
};

// The parameter sets: associated, non-dilatant, partly dilatant, Poisson's ratio 0, Tresca,
// and three with a tension cut-off.
std::vector<Case> cases();

bool has_cut_off(const MohrCoulombConstants& p);

// A random stress inside both criteria, by rejection.
Eigen::Vector4d admissible_stress(const MohrCoulombConstants& p, std::mt19937& random);

// A random strain increment whose size spans elastic steps to ones far past the apex.
Eigen::Vector4d strain_increment(const MohrCoulombConstants& p, std::mt19937& random);

}  // namespace talus::testing
