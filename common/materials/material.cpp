#include "common/materials/material.hpp"

#include <limits>

#include "common/error.hpp"
#include "common/model/parameters.hpp"
#include "common/range.hpp"

namespace talus {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
const char* const kParameters[] = {"density",           "youngs_modulus",          "poisson_ratio",
                                   "friction_angle",    "cohesion",                "dilation_angle",
                                   "tensile_strength",  "saturated_density",       "porosity",
                                   "residual_cohesion", "residual_friction_angle", "residual_dilation_angle",
                                   "softening_start",   "softening_end",           "softening_reference_size"};

}  // namespace

NumberRange parameter_range(const Material& m, const std::string& key) {
  if (key == "density") return {0, kInf, false};
  if (key == "youngs_modulus") return {0, kInf, false};
  if (key == "poisson_ratio") return {0, 0.5, true, false};
  if (key == "friction_angle") return {0, 90, true, false};
  if (key == "cohesion") return {0, kInf};
  if (key == "dilation_angle") return {0, m.friction_angle};
  if (key == "tensile_strength") return {-kInf, kInf};  // < 0: no cut-off
  if (key == "saturated_density") return {0, kInf};     // 0: density
  if (key == "porosity") return {0, 1, true, false};
  if (key == "residual_cohesion") return {0, kInf};
  if (key == "residual_friction_angle") return {0, 90, true, false};
  if (key == "residual_dilation_angle") return {0, m.residual_friction_angle};
  if (key == "softening_start") return {0, kInf};
  if (key == "softening_end") return {m.softening_start, kInf, false};  // or 0: no softening
  if (key == "softening_reference_size") return {0, kInf};
  throw Error("internal error: no material parameter '" + key + "'");
}

std::optional<MaterialProblem> parameter_problem(const Material& m, const std::string& key) {
  const NumberRange range = parameter_range(m, key);
  double x = 0;
  for_each_material_parameter(m, [&](const char* name, double value) {
    if (name == key) x = value;
  });
  if (key == "softening_end" && x == 0) return std::nullopt;  // no softening
  if (range.contains(x)) return std::nullopt;
  return MaterialProblem{key, range.problem(x)};
}

std::optional<MaterialProblem> material_problem(const Material& m) {
  for (const char* key : kParameters)
    if (auto problem = parameter_problem(m, key)) return problem;
  if (m.model == MaterialModel::MohrCoulomb && m.friction_angle == 0 && m.cohesion == 0)
    return MaterialProblem{"cohesion", "a Mohr-Coulomb material needs friction_angle > 0 or cohesion > 0"};
  if (m.model == MaterialModel::MohrCoulomb && m.softening_end > 0 && m.residual_friction_angle == 0 &&
      m.residual_cohesion == 0)
    return MaterialProblem{"residual_cohesion",
                           "a softening material needs residual_friction_angle > 0 or residual_cohesion > 0"};
  return std::nullopt;
}

void check_material(const Material& m, const std::string& file, const std::string& item_prefix) {
  if (const auto problem = material_problem(m)) throw Error(located(file, item_prefix + problem->key, problem->message));
}

}  // namespace talus
