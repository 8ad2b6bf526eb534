// The readers of the scene's [bodies.NAME] and [boundaries.NAME] tables.
#include "common/model/checks.hpp"
#include "common/scene/reader.hpp"

namespace talus::scene_reader {

void read_bodies(TableReader& top, Scene& scene) {
  const toml::table* bodies = top.table("bodies");
  if (!bodies || bodies->empty()) top.fail("bodies", "missing (at least one [bodies.NAME] table)");
  for (const auto& [key, node] : *bodies) {
    const std::string name(key.str());
    if (!node.as_table()) top.fail("bodies." + name, "expected a table");
    check_name(name, "bodies." + name, top.file());
    TableReader r = top.child(node.as_table(), "bodies." + name);
    Body b;
    b.name = name;
    b.group = r.text("group", name);
    b.material = r.text("material", std::nullopt);
    if (scene.material_index(b.material) < 0)
      r.fail("material", "no material named '" + echoed(b.material) + "' in [materials]");
    b.particles_per_cell = static_cast<int>(r.integer("particles_per_cell", b.particles_per_cell, 1, 10));
    if (b.particles_per_cell != 1 && b.particles_per_cell != 3 && b.particles_per_cell != 4 &&
        b.particles_per_cell != 6 && b.particles_per_cell != 10)
      r.fail("particles_per_cell", "got " + std::to_string(b.particles_per_cell) + ", expected 1, 3, 4, 6 or 10");
    b.fixed = r.boolean("fixed", false);
    b.initial_velocity = r.vector2("initial_velocity", Eigen::Vector2d::Zero());
    if (const toml::table* stress = r.table("initial_stress")) {
      TableReader s = r.child(stress, r.prefix() + ".initial_stress");
      InitialStress initial;
      initial.k0 = s.number("k0", std::nullopt, 0, kMaxK0);
      if (s.has("surface")) initial.surface = s.number("surface", std::nullopt, -kInf, kInf);
      s.finish();
      b.initial_stress = initial;
    }
    r.finish();
    scene.bodies.push_back(b);
  }
}

void read_boundaries(TableReader& top, Scene& scene) {
  const toml::table* boundaries = top.table("boundaries");
  if (!boundaries) return;
  for (const auto& [key, node] : *boundaries) {
    const std::string name(key.str());
    if (!node.as_table()) top.fail("boundaries." + name, "expected a table");
    TableReader r = top.child(node.as_table(), "boundaries." + name);
    Boundary b;
    b.name = name;
    b.group = r.text("group", name);
    const std::string type = r.text("type", std::nullopt);
    if (type == "fixed") b.type = BoundaryType::Fixed;
    else if (type == "roller") b.type = BoundaryType::Roller;
    else if (type == "friction") b.type = BoundaryType::Friction;
    else if (type == "absorbing") b.type = BoundaryType::Absorbing;
    else r.fail("type", "unknown boundary type '" + echoed(type) + "' (expected fixed, roller, friction or absorbing)");
    if (b.type == BoundaryType::Absorbing) read_absorbing(r, scene, b);
    if (b.type == BoundaryType::Friction) b.friction = r.number("friction", std::nullopt, 0, kInf);
    else if (r.has("friction"))
      r.fail("friction", "belongs to type = \"friction\" only (this boundary is " + type + ")");
    if (r.has("normal")) {
      Eigen::Vector2d n = r.vector2("normal", std::nullopt);
      if (n.norm() == 0) r.fail("normal", "expected a non-zero vector");
      b.normal = n.normalized();
    }
    r.finish();
    scene.boundaries.push_back(b);
  }
}

}  // namespace talus::scene_reader
