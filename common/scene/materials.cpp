// The reader of the scene's [materials.NAME] tables; the ranges are common/materials/material.hpp's.
#include <algorithm>

#include "common/materials/material.hpp"
#include "common/scene/reader.hpp"

namespace talus::scene_reader {
namespace {

Material read_material(TableReader& top, const std::string& name, const toml::table* table) {
  check_name(name, "materials." + name, top.file());
  TableReader r = top.child(table, "materials." + name);
  Material m;
  m.name = name;
  const std::string model = r.text("model", std::nullopt);
  if (model == "linear_elastic") m.model = MaterialModel::LinearElastic;
  else if (model == "mohr_coulomb") m.model = MaterialModel::MohrCoulomb;
  else r.fail("model", "unknown material model '" + echoed(model) + "' (expected linear_elastic or mohr_coulomb)");
  // Each parameter checked as it is read (common/materials/material.hpp), so the first bad one is reported.
  auto parameter = [&](double Material::*field, const std::string& key, std::optional<double> fallback) {
    m.*field = r.any_number(key, fallback);
    if (const auto problem = parameter_problem(m, key)) r.fail(key, problem->message);
  };
  parameter(&Material::density, "density", std::nullopt);
  parameter(&Material::youngs_modulus, "youngs_modulus", std::nullopt);
  parameter(&Material::poisson_ratio, "poisson_ratio", std::nullopt);
  if (m.model == MaterialModel::MohrCoulomb) {
    parameter(&Material::friction_angle, "friction_angle", std::nullopt);
    parameter(&Material::cohesion, "cohesion", std::nullopt);
    parameter(&Material::dilation_angle, "dilation_angle", 0.0);
    // In a scene, no tensile_strength is no cut-off; a strength given is a number >= 0.
    m.tensile_strength = r.has("tensile_strength") ? r.number("tensile_strength", std::nullopt, 0, kInf) : -1;
    // Softening: the residual values default to the peak ones, and need softening_end.
    const bool softening = r.has("softening_end");
    for (const char* key : {"residual_cohesion", "residual_friction_angle", "residual_dilation_angle",
                            "softening_start", "softening_reference_size"})
      if (!softening && r.has(key)) r.fail(key, "needs softening_end (the plastic strain at which the strength is residual)");
    parameter(&Material::softening_start, "softening_start", 0.0);
    parameter(&Material::softening_end, "softening_end", 0.0);
    if (softening && m.softening_end == 0) r.fail("softening_end", "got 0, expected a number > softening_start");
    parameter(&Material::residual_cohesion, "residual_cohesion", m.cohesion);
    parameter(&Material::residual_friction_angle, "residual_friction_angle", m.friction_angle);
    parameter(&Material::residual_dilation_angle, "residual_dilation_angle",
              std::min(m.dilation_angle, m.residual_friction_angle));
    parameter(&Material::softening_reference_size, "softening_reference_size", 0.0);
  }
  parameter(&Material::saturated_density, "saturated_density", 0.0);
  parameter(&Material::porosity, "porosity", 0.0);
  if (const auto problem = material_problem(m)) r.fail(problem->key, problem->message);
  r.finish();
  return m;
}

}  // namespace

void read_materials(TableReader& top, Scene& scene) {
  const toml::table* materials = top.table("materials");
  if (!materials || materials->empty()) top.fail("materials", "missing (at least one [materials.NAME] table)");
  for (const auto& [key, node] : *materials) {
    const toml::table* table = node.as_table();
    if (!table) top.fail("materials." + std::string(key.str()), "expected a table");
    scene.materials.push_back(read_material(top, std::string(key.str()), table));
  }
}

}  // namespace talus::scene_reader
