// Linear elastic material, plane strain, isotropic: sigma += D d_eps with D = lambda 1 (x) 1 + 2G I
// (tensor shear: sigma_xy += 2G d_eps_xy). Its parameters are the shared ones (E, nu); it has
// no strength, keeps no state and leaves eps_p alone. The unit's declarations are those listed in
// docs/architecture.md, "Materials".
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string_view>

#include "common/materials/parameter.hpp"

namespace talus {

// Linear elastic trial: sigma += D d_eps. Also the first half of Mohr-Coulomb's update.
inline void elastic_update(double shear_modulus, double bulk_modulus, Eigen::Vector4d& sigma,
                           const Eigen::Vector4d& d_eps) {
  const double two_g = 2.0 * shear_modulus;
  const double lambda_trace = (bulk_modulus - two_g / 3.0) * (d_eps[0] + d_eps[1] + d_eps[2]);
  sigma[0] += lambda_trace + two_g * d_eps[0];
  sigma[1] += lambda_trace + two_g * d_eps[1];
  sigma[2] += lambda_trace + two_g * d_eps[2];
  sigma[3] += two_g * d_eps[3];
}

struct LinearElastic {
  static constexpr std::string_view kName = "linear_elastic";

  struct Parameters {  // none beyond the shared E and nu
    template <class Self, class Visit>
    static void visit(Self&, Visit&&) {}
  };
  static std::optional<MaterialProblem> rules(const Parameters&) { return std::nullopt; }

  struct Prepared {
    double shear_modulus = 0, bulk_modulus = 0;  // G, K (Pa)
  };
  static Prepared prepare(const SharedParameters& shared, const Parameters&, const PrepareContext&) {
    return {shared.shear_modulus(), shared.bulk_modulus()};
  }
  static int history_width(const Parameters&) { return 0; }
  static void update(const Prepared& s, Eigen::Vector4d& sigma, const Eigen::Vector4d& d_eps, double /*dt*/,
                     double& /*eps_p*/, double* /*history*/) {
    elastic_update(s.shear_modulus, s.bulk_modulus, sigma, d_eps);
  }

  // No strength to reduce, none for limit equilibrium.
  static constexpr bool kHasStrength = false;
  static Parameters reduced(const Parameters& p, double /*factor*/) { return p; }
  static std::optional<CohesionFriction> limit_equilibrium(const Parameters&) { return std::nullopt; }
};

}  // namespace talus
