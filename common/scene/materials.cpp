// The reader of the scene's [materials.NAME] tables: the model's name, then every parameter its
// visitor lists (common/materials/materials.hpp, for_each_parameter) with its fallback and range.
#include "common/materials/materials.hpp"
#include "common/scene/reader.hpp"

namespace talus::scene_reader {
namespace {

Material read_material(TableReader& top, const std::string& name, const toml::table* table) {
  check_name(name, "materials." + name, top.file());
  TableReader r = top.child(table, "materials." + name);
  Material m;
  m.name = name;
  const std::string model = r.text("model", std::nullopt);
  if (!set_model(m, model))
    r.fail("model", "unknown material model '" + echoed(model) + "' (expected " + model_names() + ")");
  // Each parameter checked as it is read, so the first bad one is reported; a fallback may
  // depend on the parameters before it (residual_cohesion: cohesion).
  for_each_parameter(m, [&](const Parameter& parameter, double& value) {
    const std::string key = parameter.name;
    if (!r.has(key)) {
      if (!parameter.fallback) r.fail(key, "missing (a number is required)");
      value = *parameter.fallback;
      return;
    }
    if (parameter.needs && !r.has(parameter.needs))
      r.fail(key, "needs " + std::string(parameter.needs) + " (" + parameter.needs_why + ")");
    value = r.any_number(key, std::nullopt);
    if (const std::string problem = parameter.problem_given(value); !problem.empty()) r.fail(key, problem);
  });
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
