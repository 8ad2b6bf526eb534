// The one check of a material's parameters, used wherever a Material comes in: the scene
// reader (common/scene/*.cpp), the model and results reader (common/model/model.cpp) and, as a guard,
// the Mohr-Coulomb constants (common/materials/mohr_coulomb.cpp).
#pragma once
#include <optional>
#include <string>

#include "common/range.hpp"
#include "common/scene/scene.hpp"

namespace talus {

struct MaterialProblem {
  std::string key;      // the parameter, named as in the scene and the model: "poisson_ratio"
  std::string message;  // what is wrong: "got 0.5, expected a finite number in [0, 0.5)"
};

// The problem with the parameter `key` of `m`, if any. Every parameter is a finite number:
// density and youngs_modulus > 0, poisson_ratio in [0, 0.5), friction_angle in [0, 90),
// cohesion >= 0, dilation_angle in [0, friction_angle], tensile_strength any (< 0: no tension
// cut-off), saturated_density >= 0 (0: density), porosity in [0, 1), the residual_* like their
// peak counterparts, softening_start >= 0, softening_end 0 (no softening) or > softening_start,
// softening_reference_size >= 0. Every parameter is checked whatever the model (a linear elastic material keeps the
// Mohr-Coulomb defaults, which are valid).
std::optional<MaterialProblem> parameter_problem(const Material& m, const std::string& key);

// The valid range of the parameter `key` of `m` (the range parameter_problem checks; it may
// depend on another parameter of `m`: dilation_angle's upper end is friction_angle). For
// softening_end the range excludes 0, which parameter_problem accepts as "no softening".
NumberRange parameter_range(const Material& m, const std::string& key);

// The first problem of `m`: the parameters in the order above, then the one rule across them,
// a Mohr-Coulomb material needs friction_angle > 0 or cohesion > 0 (reported at "cohesion"), and
// with softening residual_friction_angle > 0 or residual_cohesion > 0.
std::optional<MaterialProblem> material_problem(const Material& m);

// Throws talus::Error located at `file` and `item_prefix + key` on the first problem of `m`;
// the scene passes "materials.NAME.", the model "materials/NAME@".
void check_material(const Material& m, const std::string& file, const std::string& item_prefix);

}  // namespace talus
