// The materials in model.h5 and results.h5 (/materials), and the per-particle properties
// (/particles/properties in model.h5, /particles/<parameter> in results.h5): written and read
// through each material's one parameter visitor (common/materials/materials.hpp).
#include <algorithm>
#include <limits>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/model/model_io.hpp"

namespace talus {
namespace {

const char* const kPropertiesGroup = "particles/properties";

std::string property_item(const ParticleProperty& property) {
  return std::string(kPropertiesGroup) + "/" + property.material + "." + property.parameter;
}

// The material of each particle (index into model.materials).
std::vector<int32_t> material_of_particles(const Model& model, const std::vector<int32_t>& body) {
  std::vector<int32_t> material(body.size());
  for (std::size_t p = 0; p < body.size(); ++p) material[p] = model.bodies[body[p]].material;
  return material;
}

int material_index(const Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.materials.size(); ++i)
    if (model.materials[i].name == name) return static_cast<int>(i);
  return -1;
}

}  // namespace

void write_materials(const h5::File& file, const std::vector<Material>& materials) {
  std::vector<std::string> names;
  for (const auto& m : materials) names.push_back(m.name);
  h5::write(file, "materials/names", names);
  for (const auto& m : materials) {
    const std::string group = "materials/" + m.name;
    h5::create_group(file, group);
    h5::set_attribute(file, group, "model", std::string(model_name(m)));
    for_each_parameter(m, [&](const Parameter& parameter, double value) {
      h5::set_attribute(file, group, parameter.name, value);
    });
  }
}

std::vector<Material> read_materials(const h5::File& file) {
  std::vector<Material> materials;
  for (const auto& name : h5::read_strings(file, "materials/names")) {
    const std::string group = "materials/" + name;
    Material m;
    m.name = name;
    const std::string kind = h5::get_string(file, group, "model");
    if (!set_model(m, kind))
      throw Error(located(file.path(), group + "@model", "unknown material model '" + kind + "'"));
    // The model's keys only: a file of an earlier Talus also holds the Mohr-Coulomb keys of a
    // linear elastic material, which are ignored.
    for_each_parameter(m, [&](const Parameter& parameter, double& value) {
      if (parameter.optional_in_file && !h5::has_attribute(file, group, parameter.name)) return;
      value = h5::get_double(file, group, parameter.name);
    });
    check_material(m, file.path(), group + "@");
    materials.push_back(m);
  }
  return materials;
}

std::optional<MaterialProblem> properties_problem(const Model& model) {
  const std::size_t n = model.particle_count();
  // Per material, its properties' columns and where each writes.
  struct Column {
    const ParticleProperty* property;
    ParameterSlot slot;
  };
  std::vector<std::vector<Column>> columns(model.materials.size());
  for (const ParticleProperty& property : model.properties) {
    const std::string item = property_item(property);
    auto problem = [&](const std::string& message) { return MaterialProblem{item, message}; };
    const int m = material_index(model, property.material);
    if (m < 0) return problem("no material named '" + property.material + "'");
    const Material& material = model.materials[m];
    if (property.parameter == "density" || property.parameter == "saturated_density")
      return problem(property.parameter + " is not a per-particle property: it acts through each particle's mass "
                                          "and initial stress, set when meshing");
    const std::optional<ParameterSlot> slot = parameter_slot(material, property.parameter);
    if (!slot)
      return problem("material '" + material.name + "' (" + std::string(model_name(material)) +
                     ") has no parameter '" + property.parameter + "'");
    for (const Column& other : columns[m])
      if (other.property->parameter == property.parameter) return problem("given twice");
    if (property.values.size() != n)
      return problem("expected " + std::to_string(n) + " values (one per particle), got " +
                     std::to_string(property.values.size()));
    columns[m].push_back({&property, *slot});
  }
  if (model.properties.empty()) return std::nullopt;
  const std::vector<int32_t> material_of = material_of_particles(model, model.body);
  std::vector<Material> particle_material = model.materials;  // overwritten particle by particle
  for (std::size_t p = 0; p < n; ++p) {
    const int32_t m = material_of[p];
    if (columns[m].empty()) continue;
    Material& material = particle_material[m];
    for (const Column& column : columns[m]) set_parameter(material, column.slot, column.property->values[p]);
    if (const auto problem = material_problem(material)) {
      // Reported at the property that holds the bad value, or at the first when a rule across
      // values fails.
      const ParticleProperty* at = columns[m].front().property;
      for (const Column& column : columns[m])
        if (column.property->parameter == problem->key) at = column.property;
      return MaterialProblem{property_item(*at),
                             "particle " + std::to_string(p) + ": " + problem->key + ": " + problem->message};
    }
  }
  return std::nullopt;
}

void write_properties(const h5::File& file, const Model& model) {
  if (model.properties.empty()) return;
  const std::vector<int32_t> material_of = material_of_particles(model, model.body);
  h5::create_group(file, kPropertiesGroup);
  for (const ParticleProperty& property : model.properties) {
    const int m = material_index(model, property.material);
    std::vector<double> values(material_of.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t p = 0; p < values.size(); ++p)
      if (material_of[p] == m) values[p] = property.values[p];
    h5::write(file, property_item(property), values, {values.size()});
  }
}

void read_properties(const h5::File& file, Model& model) {
  model.properties.clear();
  if (!h5::exists(file, kPropertiesGroup)) return;
  for (const std::string& name : h5::list(file, kPropertiesGroup)) {
    const std::string item = std::string(kPropertiesGroup) + "/" + name;
    const std::size_t dot = name.rfind('.');  // parameter keys have none; a material name might
    if (dot == std::string::npos || dot == 0 || dot + 1 == name.size())
      throw Error(located(file.path(), item, "expected a name MATERIAL.PARAMETER"));
    ParticleProperty property{name.substr(0, dot), name.substr(dot + 1), {}};
    h5::Dims dims;
    property.values = h5::read_doubles(file, item, &dims);
    check_count(file, item, dims, model.particle_count());
    model.properties.push_back(std::move(property));
  }
  if (const auto problem = properties_problem(model)) throw Error(located(file.path(), problem->key, problem->message));
}

void write_property_values(const h5::File& file, const Model& metadata, const std::vector<int32_t>& body) {
  if (metadata.properties.empty()) return;
  const std::vector<int32_t> material_of = material_of_particles(metadata, body);
  std::vector<std::string> written;
  for (const ParticleProperty& first : metadata.properties) {
    const std::string& key = first.parameter;
    if (std::find(written.begin(), written.end(), key) != written.end()) continue;
    written.push_back(key);
    // Each particle's value: its own where its material has the property, else its material's,
    // NaN for a material without the parameter.
    std::vector<double> values(material_of.size(), std::numeric_limits<double>::quiet_NaN());
    std::vector<const ParticleProperty*> column(metadata.materials.size(), nullptr);
    std::vector<double> own(metadata.materials.size(), std::numeric_limits<double>::quiet_NaN());
    for (const ParticleProperty& property : metadata.properties)
      if (property.parameter == key) column[material_index(metadata, property.material)] = &property;
    for (std::size_t m = 0; m < metadata.materials.size(); ++m)
      for_each_parameter(metadata.materials[m], [&](const Parameter& parameter, double value) {
        if (key == parameter.name) own[m] = value;
      });
    for (std::size_t p = 0; p < values.size(); ++p) {
      const int32_t m = material_of[p];
      values[p] = column[m] ? column[m]->values[p] : own[m];
    }
    const std::string path = "particles/" + key;
    h5::write(file, path, values, {values.size()});
    const Material& material = metadata.materials[material_index(metadata, first.material)];
    h5::set_attribute(file, path, "unit", std::string(find_parameter(material, key)->unit));
  }
}

}  // namespace talus
