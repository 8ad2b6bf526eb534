// What every material model's unit is built from (common/materials/materials.hpp lists the
// units): the description of one scalar parameter, which the unit's one visitor gives for each
// of its keys, and the parameters every model shares.
#pragma once
#include <limits>
#include <optional>
#include <string>

#include "common/range.hpp"

namespace talus {

// One scalar parameter as a unit's visitor lists it. The scene reader, the model.h5 writer and
// reader, the checkpoint's fingerprint and the per-particle properties all read this and
// nothing else, so a key is described once. `range` may depend on the parameters listed
// before it (dilation_angle in [0, friction_angle]): the visitor builds it from their values.
struct Parameter {
  const char* name;     // the scene key and the model.h5 attribute: "cohesion"
  const char* unit;     // "Pa", "deg", "kg/m^3", "m", "-"
  NumberRange range;    // the valid values of a material (scene, model.h5, per-particle values)
  // What a scene that leaves the key out gets; none: the key is required.
  std::optional<double> fallback = std::nullopt;
  // A value outside `range` that means "off" (softening_end = 0: no softening): valid in a
  // material, but a scene turns it off by leaving the key out, and is told `off_message` if it
  // gives it.
  std::optional<double> off = std::nullopt;
  const char* off_message = nullptr;
  // A narrower range for a value the scene gives (tensile_strength: a cut-off given is >= 0,
  // while the material's -1, the scene's fallback, is "no cut-off").
  std::optional<NumberRange> given = std::nullopt;
  // A scene may give this key only together with `needs` (the softening keys need
  // softening_end); `needs_why` says what that key is.
  const char* needs = nullptr;
  const char* needs_why = nullptr;
  // Added after the first model format: a model.h5 without it keeps the struct's default.
  bool optional_in_file = false;

  bool accepts(double value) const { return (off && value == *off) || range.contains(value); }
  // The problem of a material's value ("got 0.5, expected a finite number in [0, 0.5)"), or "".
  std::string problem(double value) const { return accepts(value) ? "" : range.problem(value); }
  // The problem of a value a scene gives, or "".
  std::string problem_given(double value) const {
    if (off && value == *off) return off_message ? off_message : range.problem(value);
    return given ? given->problem(value) : range.problem(value);
  }
};

inline constexpr double kUnbounded = std::numeric_limits<double>::infinity();

// A problem with a material: the parameter it is reported at, and what is wrong.
struct MaterialProblem {
  std::string key;      // named as in the scene and the model: "poisson_ratio"
  std::string message;  // "got 0.5, expected a finite number in [0, 0.5)"
};

// The parameters every model has. The elastic constants come first in a material's list and
// the water's last, around the model's own (the order a scene is read and checked in).
struct SharedParameters {
  double density = 0;            // kg/m^3
  double youngs_modulus = 0;     // Pa
  double poisson_ratio = 0;      // -
  // With a water table ([water]): the density below it (0: `density` everywhere), and the
  // porosity n of the undrained mode's pore-water stiffness K_w / n (0: no excess pore pressure).
  double saturated_density = 0;  // kg/m^3
  double porosity = 0;           // -

  // Plane strain uses the 3D moduli: G = E / (2 (1 + nu)), K = E / (3 (1 - 2 nu)).
  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  double bulk_modulus() const { return youngs_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio)); }

  // visit(Parameter, value) for density, youngs_modulus and poisson_ratio.
  template <class Self, class Visit>
  static void visit_elastic(Self& s, Visit&& visit) {
    visit(Parameter{.name = "density", .unit = "kg/m^3", .range = {0, kUnbounded, false}}, s.density);
    visit(Parameter{.name = "youngs_modulus", .unit = "Pa", .range = {0, kUnbounded, false}}, s.youngs_modulus);
    visit(Parameter{.name = "poisson_ratio", .unit = "-", .range = {0, 0.5, true, false}}, s.poisson_ratio);
  }
  // visit(Parameter, value) for saturated_density and porosity.
  template <class Self, class Visit>
  static void visit_water(Self& s, Visit&& visit) {
    visit(Parameter{.name = "saturated_density", .unit = "kg/m^3", .range = {0, kUnbounded}, .fallback = 0.0,
                    .optional_in_file = true},
          s.saturated_density);
    visit(Parameter{.name = "porosity", .unit = "-", .range = {0, 1, true, false}, .fallback = 0.0,
                    .optional_in_file = true},
          s.porosity);
  }
};

// What a model's stress update may need beside its parameters, known once the mesh is: the
// mean element size (the softening strains' regularisation).
struct PrepareContext {
  double element_size = 0;  // m; 0: unknown (no regularisation)
};

// The strength a limit-equilibrium method (Bishop's) takes from a material: c and phi.
struct CohesionFriction {
  double cohesion = 0;        // Pa
  double friction_angle = 0;  // deg
};

}  // namespace talus
