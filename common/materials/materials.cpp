#include "common/materials/materials.hpp"

#include "common/error.hpp"

namespace talus {
namespace {

// Calls f(Model{}, index) for every model in list order until f returns true.
template <std::size_t I = 0, class F>
bool any_model(F&& f) {
  if constexpr (I == MaterialModels::kCount) {
    return false;
  } else {
    if (f(typename MaterialModels::template At<I>{}, std::integral_constant<std::size_t, I>{})) return true;
    return any_model<I + 1>(std::forward<F>(f));
  }
}

}  // namespace

std::string_view model_name(const Material& m) {
  return with_model(m.model, [](auto model, const auto&) { return decltype(model)::kName; });
}

std::string model_names() {
  std::string names;
  any_model([&](auto model, auto index) {
    if (index > 0) names += index + 1 == MaterialModels::kCount ? " or " : ", ";
    names += decltype(model)::kName;
    return false;
  });
  return names;
}

bool set_model(Material& m, std::string_view name) {
  return any_model([&](auto model, auto) {
    using Model = decltype(model);
    if (Model::kName != name) return false;
    m.model = typename Model::Parameters{};
    return true;
  });
}

std::optional<Parameter> find_parameter(const Material& m, std::string_view key) {
  std::optional<Parameter> found;
  for_each_parameter(m, [&](const Parameter& parameter, const double&) {
    if (!found && key == parameter.name) found = parameter;
  });
  return found;
}

std::optional<double> parameter_value(const Material& m, std::string_view key) {
  std::optional<double> found;
  for_each_parameter(m, [&](const Parameter& parameter, double value) {
    if (!found && key == parameter.name) found = value;
  });
  return found;
}

std::optional<ParameterSlot> parameter_slot(const Material& m, std::string_view key) {
  std::optional<ParameterSlot> slot;
  auto offset = [](const void* base, const double& value) {
    return static_cast<std::size_t>(reinterpret_cast<const char*>(&value) - static_cast<const char*>(base));
  };
  const SharedParameters& shared = m;
  auto in_shared = [&](const Parameter& parameter, const double& value) {
    if (key == parameter.name) slot = ParameterSlot{true, offset(&shared, value)};
  };
  SharedParameters::visit_elastic(shared, in_shared);
  SharedParameters::visit_water(shared, in_shared);
  with_model(m.model, [&](auto model, const auto& own) {
    decltype(model)::Parameters::visit(own, [&](const Parameter& parameter, const double& value) {
      if (key == parameter.name) slot = ParameterSlot{false, offset(&own, value)};
    });
  });
  return slot;
}

std::optional<MaterialProblem> material_problem(const Material& m) {
  std::optional<MaterialProblem> problem;
  for_each_parameter(m, [&](const Parameter& parameter, const double& value) {
    if (!problem && !parameter.accepts(value)) problem = MaterialProblem{parameter.name, parameter.problem(value)};
  });
  if (problem) return problem;
  return with_model(m.model, [](auto model, const auto& own) { return decltype(model)::rules(own); });
}

void check_material(const Material& m, const std::string& file, const std::string& item_prefix) {
  if (const auto problem = material_problem(m)) throw Error(located(file, item_prefix + problem->key, problem->message));
}

bool has_strength(const Material& m) {
  return with_model(m.model, [](auto model, const auto&) { return decltype(model)::kHasStrength; });
}

Material reduced(const Material& m, double factor) {
  Material out = m;
  with_model(out.model, [&](auto model, auto& own) { own = decltype(model)::reduced(own, factor); });
  return out;
}

std::optional<CohesionFriction> limit_equilibrium_strength(const Material& m) {
  return with_model(m.model, [](auto model, const auto& own) { return decltype(model)::limit_equilibrium(own); });
}

int history_width(const Material& m) {
  return with_model(m.model, [](auto model, const auto& own) { return decltype(model)::history_width(own); });
}

PreparedMaterial prepare(const Material& m, const PrepareContext& context) {
  return with_model(m.model, [&](auto model, const auto& own) {
    using Model = decltype(model);
    return PreparedMaterial(std::in_place_type<typename Model::Prepared>, Model::prepare(m, own, context));
  });
}

}  // namespace talus
