// The reader of the scene's [loads.NAME] tables: surface loads on a body's outline.
#include "common/scene/reader.hpp"

namespace talus::scene_reader {

void read_loads(TableReader& top, Scene& scene) {
  const toml::table* loads = top.table("loads");
  if (!loads) return;
  for (const auto& [key, node] : *loads) {
    const std::string name(key.str());
    if (!node.as_table()) top.fail("loads." + name, "expected a table");
    check_name(name, "loads." + name, top.file());
    TableReader r = top.child(node.as_table(), "loads." + name);
    SurfaceLoad load;
    load.name = name;
    load.group = r.text("group", name);
    const bool pressure = r.has("pressure"), traction = r.has("traction");
    if (pressure && traction)
      r.fail("traction", "a load takes either pressure (Pa, normal to the curve) or traction = [tx, ty] (Pa), not both");
    if (!pressure && !traction)
      r.fail("pressure", "missing: a load needs pressure (Pa, normal to the curve) or traction = [tx, ty] (Pa)");
    if (pressure) load.pressure = r.number("pressure", std::nullopt, -kInf, kInf);
    if (traction) load.traction = r.vector2("traction", std::nullopt);
    load.ramp = r.number("ramp", 0.0, 0, kInf, true, false);
    r.finish();
    scene.loads.push_back(load);
  }
}

}  // namespace talus::scene_reader
