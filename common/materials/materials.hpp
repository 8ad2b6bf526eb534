// The materials: the one list of the constitutive models, and what the rest of Talus asks of a
// material through it. Each model is one unit, a struct in its own file of this folder
// (linear_elastic.hpp, mohr_coulomb.hpp, mu_i.hpp) that declares its name, its parameter struct with the
// one visitor that lists its keys, its cross-parameter rules, its prepared state, its stress
// update, its history width and its strength (docs/architecture.md, "Materials", gives the
// recipe for a new one). Nothing outside this folder names a model but through this header.
#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <variant>

#include "common/materials/linear_elastic.hpp"
#include "common/materials/mohr_coulomb.hpp"
#include "common/materials/mu_i.hpp"
#include "common/materials/parameter.hpp"

namespace talus {

template <class... Models>
struct ModelList {
  static constexpr std::size_t kCount = sizeof...(Models);
  template <std::size_t I>
  using At = std::tuple_element_t<I, std::tuple<Models...>>;
  using Parameters = std::variant<typename Models::Parameters...>;
  using Prepared = std::variant<typename Models::Prepared...>;
};

// The material models, one line each: a new model is its file in this folder, one line here and
// its tests. The first is the default of a Material.
using MaterialModels = ModelList<
    LinearElastic,
    MohrCoulomb,
    MuI>;

// A material's model with its own parameters (the alternative says which model it is).
using MaterialParameters = MaterialModels::Parameters;
// A model's state prepared for the stress update (the solver's, one per material).
using PreparedMaterial = MaterialModels::Prepared;

// A material as the scene gives it and model.h5 stores it: its name, the parameters every model
// shares (density, youngs_modulus, poisson_ratio, saturated_density, porosity) and its model.
struct Material : SharedParameters {
  std::string name;
  MaterialParameters model;
};

// Calls f(Model{}, alternative) for the model whose alternative `v` (a MaterialParameters or a
// PreparedMaterial, const or not) holds: a test of the index per model and no virtual call; the
// last model is taken by elimination (a variant here never is valueless: nothing that fills one
// throws), so the last two models share one test, as a switch's would.
template <std::size_t I = 0, class Variant, class F>
inline decltype(auto) with_model(Variant& v, F&& f) {
  using Model = typename MaterialModels::template At<I>;
  if constexpr (I + 1 == MaterialModels::kCount) {
    if (v.index() != I) __builtin_unreachable();
    return f(Model{}, *std::get_if<I>(&v));
  } else {
    if (v.index() == I) return f(Model{}, *std::get_if<I>(&v));
    return with_model<I + 1>(v, std::forward<F>(f));
  }
}

// ---- Names ----------------------------------------------------------------------------------

std::string_view model_name(const Material& m);  // "mohr_coulomb"
std::string model_names();                        // "linear_elastic or mohr_coulomb", for messages
// Gives `m` the named model with its parameters' defaults; false for an unknown name.
bool set_model(Material& m, std::string_view name);

template <class Model>
bool is(const Material& m) {
  return std::holds_alternative<typename Model::Parameters>(m.model);
}
// The model's own parameters of `m` (std::bad_variant_access when `m` is of another model).
template <class Model>
typename Model::Parameters& parameters_of(Material& m) {
  return std::get<typename Model::Parameters>(m.model);
}
template <class Model>
const typename Model::Parameters& parameters_of(const Material& m) {
  return std::get<typename Model::Parameters>(m.model);
}

// ---- Parameters -----------------------------------------------------------------------------

// visit(const Parameter&, value) for every parameter of `m` (value a double&, const when `m` is)
// in the order a scene is read and checked: density, youngs_modulus, poisson_ratio, the model's
// own, saturated_density, porosity. The scene reader, model.h5 and the checkpoint's fingerprint
// all go through it.
template <class M, class Visit>
void for_each_parameter(M& m, Visit&& visit) {
  SharedParameters::visit_elastic(m, visit);
  with_model(m.model, [&](auto model, auto& own) { decltype(model)::Parameters::visit(own, visit); });
  SharedParameters::visit_water(m, visit);
}

// The description of the parameter `key` of `m` (its range given m's other values), or none
// when m's model has no such key; and its value.
std::optional<Parameter> find_parameter(const Material& m, std::string_view key);
std::optional<double> parameter_value(const Material& m, std::string_view key);

// Where the parameter lives, resolved once so that a per-particle value is written into copies
// of the parameter structs without looking its name up again: in the shared parameters or the
// model's own, at a byte offset.
struct ParameterSlot {
  bool shared = false;
  std::size_t offset = 0;
};
std::optional<ParameterSlot> parameter_slot(const Material& m, std::string_view key);
template <class Own>
void set_parameter(SharedParameters& shared, Own& own, ParameterSlot slot, double value) {
  char* base = slot.shared ? reinterpret_cast<char*>(&shared) : reinterpret_cast<char*>(&own);
  std::memcpy(base + slot.offset, &value, sizeof value);
}
inline void set_parameter(Material& m, ParameterSlot slot, double value) {
  with_model(m.model, [&](auto, auto& own) { set_parameter(m, own, slot, value); });
}

// ---- Checks ---------------------------------------------------------------------------------

// The first problem of `m`: each parameter against its range in the order above, then the
// model's rules across them (a Mohr-Coulomb material needs friction_angle > 0 or cohesion > 0).
std::optional<MaterialProblem> material_problem(const Material& m);
// Throws talus::Error located at `file` and `item_prefix + key` on the first problem of `m`;
// the scene passes "materials.NAME.", the model "materials/NAME@".
void check_material(const Material& m, const std::string& file, const std::string& item_prefix);

// ---- Strength (strength reduction, limit equilibrium) ---------------------------------------

// Whether the model has a strength to reduce (and yields): the bodies `talus fos` and the slope
// metrics analyse by default.
bool has_strength(const Material& m);
// `m` with its strength divided by `factor` as its model defines it (docs/fos.md).
Material reduced(const Material& m, double factor);
// c and phi for Bishop's method; none for a model without them.
std::optional<CohesionFriction> limit_equilibrium_strength(const Material& m);

// ---- The solver's side ----------------------------------------------------------------------

// State variables per particle the model keeps in Particles::history.
int history_width(const Material& m);
// The model's state for the stress update.
PreparedMaterial prepare(const Material& m, const PrepareContext& context);

// The objective stress update of one particle (sigma already rotated by the caller): adds the
// model's response to the strain increment d_eps over the step dt, its increment of equivalent
// plastic shear strain to eps_p, and advances its history_width state variables at `history`.
inline void update_stress(const PreparedMaterial& s, Eigen::Vector4d& sigma, const Eigen::Vector4d& d_eps, double dt,
                          double& eps_p, double* history) {
  with_model(s, [&](auto model, const auto& prepared) {
    decltype(model)::update(prepared, sigma, d_eps, dt, eps_p, history);
  });
}

}  // namespace talus
