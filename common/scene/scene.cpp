// load_scene: parses the file, applies the --set overrides and reads the tables in the order of
// the format (the readers are common/scene/*.cpp, their shared reader common/scene/reader.cpp).
#include "common/scene/scene.hpp"

#include <filesystem>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "common/error.hpp"
#include "common/scene/reader.hpp"

namespace talus {

int Scene::material_index(const std::string& name) const {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == name) return static_cast<int>(i);
  return -1;
}

int Scene::body_index(const std::string& name) const {
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (bodies[i].name == name) return static_cast<int>(i);
  return -1;
}

const char* transfer_name(Transfer transfer) {
  switch (transfer) {
    case Transfer::Flip: return "flip";
    case Transfer::PicBlend: return "pic_blend";
    case Transfer::Xpic: return "xpic";
    case Transfer::Apic: return "apic";
  }
  return "";
}

std::optional<Transfer> transfer_from_name(const std::string& name) {
  for (Transfer t : {Transfer::Flip, Transfer::PicBlend, Transfer::Xpic, Transfer::Apic})
    if (name == transfer_name(t)) return t;
  return std::nullopt;
}

std::vector<std::string> transfer_overrides(const std::string& name) {
  if (name == "flip" || name == "apic" || name == "pic_blend") return {"run.transfer=" + name};
  if (name == "xpic") return {"run.transfer=xpic", "run.xpic_order=5"};
  if (name.rfind("xpic", 0) == 0 && name.size() > 4 && name.size() <= 7 &&
      name.find_first_not_of("0123456789", 4) == std::string::npos) {
    const int order = std::stoi(name.substr(4));
    if (order >= 1 && order <= 100) return {"run.transfer=xpic", "run.xpic_order=" + std::to_string(order)};
  }
  throw Error("unknown transfer '" + name + "' (expected flip, apic, pic_blend, xpic (order 5) or xpicM with M from 1 to 100)");
}

const char* shape_functions_name(ShapeFunctions family) {
  switch (family) {
    case ShapeFunctions::QuadraticBspline: return "bspline";
    case ShapeFunctions::Cpdi: return "cpdi";
    default: return "linear";
  }
}

std::optional<ShapeFunctions> shape_functions_from_name(const std::string& name) {
  for (ShapeFunctions f : {ShapeFunctions::Linear, ShapeFunctions::QuadraticBspline, ShapeFunctions::Cpdi})
    if (name == shape_functions_name(f)) return f;
  return std::nullopt;
}

double pair_friction(const ContactSettings& contact, const std::string& a, const std::string& b) {
  for (const auto& pair : contact.pairs)
    if ((pair.body_a == a && pair.body_b == b) || (pair.body_a == b && pair.body_b == a)) return pair.friction;
  return contact.friction;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  using namespace scene_reader;
  // Checked before it is opened: opening a FIFO blocks until something writes into it.
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) throw Error(located(path, "", "no such scene file"));
  if (std::filesystem::is_directory(status)) throw Error(located(path, "", "is a folder, not a scene file"));
  if (!std::filesystem::is_regular_file(status))
    throw Error(located(path, "", "is not a regular file (a FIFO, a device or a socket): expected a scene file"));
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    std::ostringstream where;
    where << "line " << e.source().begin.line << ", column " << e.source().begin.column;
    throw Error(located(path, where.str(), std::string("not valid TOML: ") + std::string(e.description())));
  }
  std::set<std::string> overridden;
  for (const auto& assignment : overrides) apply_override(root, assignment, path, overridden);

  Scene scene;
  scene.path = path;
  TableReader top(&root, "", path, overridden);
  read_scene_table(top, scene);
  read_mesh(top, scene);
  read_run(top, scene);
  read_materials(top, scene);
  read_bodies(top, scene);
  read_boundaries(top, scene);
  read_loads(top, scene);
  read_contact(top, scene);
  read_post(top, scene);
  read_water(top, scene);
  read_random(top, scene);
  read_seismic(top, scene);
  read_base_motion(top, scene);
  top.finish();

  std::ostringstream canonical;
  canonical << root;
  scene.canonical_text = canonical.str();
  return scene;
}

}  // namespace talus
