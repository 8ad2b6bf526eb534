#include "common/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "common/error.hpp"
#include "common/material.hpp"
#include "common/range.hpp"

namespace talus {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string nearest(const std::string& key, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const auto& candidate : candidates) {
    const std::size_t d = edit_distance(key, candidate);
    if (d < best_distance) best_distance = d, best = candidate;
  }
  return best_distance <= std::max<std::size_t>(2, key.size() / 3) ? best : "";
}

// Reads one TOML table, remembering which keys were read, so that whatever is left over is
// reported as unknown with the nearest valid key.
class TableReader {
 public:
  TableReader(const toml::table* table, std::string prefix, const std::string& file,
              const std::set<std::string>& overridden)
      : table_(table), prefix_(std::move(prefix)), file_(file), overridden_(overridden) {}

  bool has(const std::string& key) {
    known_.push_back(key);
    return table_ && table_->contains(key);
  }

  double number(const std::string& key, std::optional<double> fallback, double min, double max,
                bool min_inclusive = true, bool max_inclusive = true) {
    if (!has(key)) {
      if (!fallback) fail(key, "missing (a number is required)");
      return *fallback;
    }
    const auto value = (*table_)[key].value<double>();
    if (!value) fail(key, "expected a number");
    const std::string problem = NumberRange{min, max, min_inclusive, max_inclusive}.problem(*value);
    if (!problem.empty()) fail(key, problem);
    return *value;
  }

  // A number of any value, infinite or NaN too, for a caller that checks it (materials).
  double any_number(const std::string& key, std::optional<double> fallback) {
    if (!has(key)) {
      if (!fallback) fail(key, "missing (a number is required)");
      return *fallback;
    }
    const auto value = (*table_)[key].value<double>();
    if (!value) fail(key, "expected a number");
    return *value;
  }

  long integer(const std::string& key, long fallback, long min, long max) {
    if (!has(key)) return fallback;
    const auto value = (*table_)[key].value<int64_t>();
    if (!value || !(*table_)[key].is_integer()) fail(key, "expected an integer");
    if (*value < min || *value > max)
      fail(key, "got " + std::to_string(*value) + ", expected an integer in [" + std::to_string(min) + ", " +
                    std::to_string(max) + "]");
    return static_cast<long>(*value);
  }

  std::string text(const std::string& key, std::optional<std::string> fallback) {
    if (!has(key)) {
      if (!fallback) fail(key, "missing (a string is required)");
      return *fallback;
    }
    const auto value = (*table_)[key].value<std::string>();
    if (!value) fail(key, "expected a string");
    return *value;
  }

  bool boolean(const std::string& key, bool fallback) {
    if (!has(key)) return fallback;
    // value<bool>() would take an integer too: 1 is not true here.
    const auto value = (*table_)[key].value<bool>();
    if (!value || !(*table_)[key].is_boolean()) fail(key, "expected true or false");
    return *value;
  }

  Eigen::Vector2d vector2(const std::string& key, std::optional<Eigen::Vector2d> fallback) {
    if (!has(key)) {
      if (!fallback) fail(key, "missing (expected [x, y])");
      return *fallback;
    }
    const toml::array* array = (*table_)[key].as_array();
    if (!array || array->size() != 2) fail(key, "expected two numbers [x, y]");
    Eigen::Vector2d v;
    for (int i = 0; i < 2; ++i) {
      const auto x = (*array)[i].value<double>();
      if (!x || !std::isfinite(*x)) fail(key, "expected two finite numbers [x, y]");
      v[i] = *x;
    }
    return v;
  }

  std::vector<std::string> strings(const std::string& key) {
    std::vector<std::string> out;
    if (!has(key)) return out;
    const toml::array* array = (*table_)[key].as_array();
    if (!array) fail(key, "expected a list of strings");
    for (const auto& item : *array) {
      const auto s = item.value<std::string>();
      if (!s) fail(key, "expected a list of strings");
      out.push_back(*s);
    }
    return out;
  }

  const toml::table* table(const std::string& key) {
    if (!has(key)) return nullptr;
    const toml::table* sub = (*table_)[key].as_table();
    if (!sub) fail(key, "expected a table");
    return sub;
  }

  // Every key of this table that was not read is a mistake.
  void finish() const {
    if (!table_) return;
    for (const auto& [key, node] : *table_) {
      const std::string name(key.str());
      if (std::find(known_.begin(), known_.end(), name) != known_.end()) continue;
      const std::string path = prefix_.empty() ? name : prefix_ + "." + name;
      const std::string suggestion = nearest(name, known_);
      std::string message = "unknown key";
      if (!suggestion.empty()) message += " (did you mean '" + (prefix_.empty() ? "" : prefix_ + ".") + suggestion + "'?)";
      else if (!known_.empty()) message += " (valid keys here: " + join(known_) + ")";
      if (overridden_.count(path)) throw Error(located(file_, "--set " + path, "no such scene key: " + message));
      throw Error(located(file_, path, message));
    }
  }

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw Error(located(file_, prefix_.empty() ? key : prefix_ + "." + key, message));
  }

  const std::string& prefix() const { return prefix_; }

 private:
  static std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
  }

  const toml::table* table_;
  std::string prefix_;
  const std::string& file_;
  const std::set<std::string>& overridden_;
  std::vector<std::string> known_;
};

constexpr double kInf = std::numeric_limits<double>::infinity();

void apply_override(toml::table& root, const std::string& assignment, const std::string& file,
                    std::set<std::string>& overridden) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0 || assignment[equals - 1] == '.')
    throw Error(located(file, "--set " + assignment, "expected KEY=VALUE, e.g. --set run.end_time=2.0"));
  const std::string key = assignment.substr(0, equals);
  const std::string value_text = assignment.substr(equals + 1);

  // The value in TOML syntax; a bare word that TOML does not accept is taken as a string.
  toml::table parsed;
  try {
    parsed = toml::parse("value = " + value_text);
  } catch (const toml::parse_error&) {
    parsed = toml::table{{"value", value_text}};
  }

  std::vector<std::string> parts;
  std::stringstream stream(key);
  for (std::string part; std::getline(stream, part, '.');) {
    if (part.empty()) throw Error(located(file, "--set " + assignment, "empty part in the dotted key"));
    parts.push_back(part);
  }
  toml::table* table = &root;
  std::string path;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    path += (path.empty() ? "" : ".") + parts[i];
    toml::node* node = table->get(parts[i]);
    if (!node) node = &table->insert_or_assign(parts[i], toml::table{}).first->second;
    table = node->as_table();
    if (!table) throw Error(located(file, "--set " + assignment, "'" + path + "' is not a table"));
  }
  const toml::node* value = parsed.get("value");
  if (!value) throw Error(located(file, "--set " + assignment, "expected KEY=VALUE, e.g. --set run.end_time=2.0"));
  table->insert_or_assign(parts.back(), *value);
  overridden.insert(key);
}

// Body and material names become HDF5 group names (bodies/NAME, materials/NAME) beside the
// list of names itself: keep them to plain words.
void check_name(const std::string& name, const std::string& item, const std::string& file) {
  const bool plain = !name.empty() && name.size() <= 64 && name != "names" &&
                     std::all_of(name.begin(), name.end(), [](unsigned char c) {
                       return std::isalnum(c) || c == '_' || c == '-';
                     });
  if (!plain)
    throw Error(located(file, item,
                        "expected a name of letters, digits, '_' or '-' (at most 64, and not 'names'), got '" +
                            name + "'"));
}

Material read_material(const std::string& name, const toml::table* table, const std::string& file,
                       const std::set<std::string>& overridden) {
  check_name(name, "materials." + name, file);
  TableReader r(table, "materials." + name, file, overridden);
  Material m;
  m.name = name;
  const std::string model = r.text("model", std::nullopt);
  if (model == "linear_elastic") m.model = MaterialModel::LinearElastic;
  else if (model == "mohr_coulomb") m.model = MaterialModel::MohrCoulomb;
  else r.fail("model", "unknown material model '" + model + "' (expected linear_elastic or mohr_coulomb)");
  // Each parameter checked as it is read (common/material.hpp), so the first bad one is reported.
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
  }
  if (const auto problem = material_problem(m)) r.fail(problem->key, problem->message);
  r.finish();
  return m;
}

}  // namespace

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

double pair_friction(const ContactSettings& contact, const std::string& a, const std::string& b) {
  for (const auto& pair : contact.pairs)
    if ((pair.body_a == a && pair.body_b == b) || (pair.body_a == b && pair.body_b == a)) return pair.friction;
  return contact.friction;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  namespace fs = std::filesystem;
  if (!fs::exists(path)) throw Error(located(path, "", "no such scene file"));
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

  TableReader scene_table(top.table("scene"), "scene", path, overridden);
  scene.name = scene_table.text("name", fs::path(path).stem().string());
  const std::string geometry = scene_table.text("geometry", fs::path(path).stem().string() + ".geo");
  scene_table.finish();
  scene.geometry = (fs::path(path).parent_path() / geometry).lexically_normal().string();
  if (scene.name.empty() || scene.name.find('/') != std::string::npos)
    scene_table.fail("name", "expected a non-empty name without '/'");

  TableReader mesh(top.table("mesh"), "mesh", path, overridden);
  if (mesh.has("size")) scene.mesh.size = mesh.number("size", std::nullopt, 0, kInf, false);
  scene.mesh.domain = mesh.text("domain", scene.mesh.domain);
  mesh.finish();

  TableReader run(top.table("run"), "run", path, overridden);
  RunSettings& rs = scene.run;
  rs.end_time = run.number("end_time", std::nullopt, 0, kInf, false);
  rs.cfl = run.number("cfl", rs.cfl, 0, 1, false, true);
  rs.output_interval = run.number("output_interval", rs.output_interval, 0, kInf, false);
  rs.gravity = run.vector2("gravity", rs.gravity);
  rs.gravity_ramp = run.number("gravity_ramp", rs.gravity_ramp, 0, kInf);
  rs.damping = run.number("damping", rs.damping, 0, 1, true, false);
  rs.evs = run.boolean("evs", rs.evs);
  rs.pic_fraction = run.number("pic_fraction", rs.pic_fraction, 0, 1);
  rs.history_interval = static_cast<int>(run.integer("history_interval", rs.history_interval, 1, 1000000));
  rs.rest_ratio = run.number("rest_ratio", rs.rest_ratio, 0, 1, true, false);
  rs.rest_window = run.number("rest_window", rs.rest_window, 0, kInf, false);
  rs.max_steps = run.integer("max_steps", rs.max_steps, 0, std::numeric_limits<long>::max());
  run.finish();

  const toml::table* materials = top.table("materials");
  if (!materials || materials->empty()) top.fail("materials", "missing (at least one [materials.NAME] table)");
  for (const auto& [key, node] : *materials) {
    const toml::table* table = node.as_table();
    if (!table) top.fail("materials." + std::string(key.str()), "expected a table");
    scene.materials.push_back(read_material(std::string(key.str()), table, path, overridden));
  }

  const toml::table* bodies = top.table("bodies");
  if (!bodies || bodies->empty()) top.fail("bodies", "missing (at least one [bodies.NAME] table)");
  for (const auto& [key, node] : *bodies) {
    const std::string name(key.str());
    if (!node.as_table()) top.fail("bodies." + name, "expected a table");
    check_name(name, "bodies." + name, path);
    TableReader r(node.as_table(), "bodies." + name, path, overridden);
    Body b;
    b.name = name;
    b.group = r.text("group", name);
    b.material = r.text("material", std::nullopt);
    if (scene.material_index(b.material) < 0)
      r.fail("material", "no material named '" + b.material + "' in [materials]");
    b.particles_per_cell = static_cast<int>(r.integer("particles_per_cell", b.particles_per_cell, 1, 10));
    if (b.particles_per_cell != 1 && b.particles_per_cell != 3 && b.particles_per_cell != 4 &&
        b.particles_per_cell != 6 && b.particles_per_cell != 10)
      r.fail("particles_per_cell", "got " + std::to_string(b.particles_per_cell) + ", expected 1, 3, 4, 6 or 10");
    b.fixed = r.boolean("fixed", false);
    b.initial_velocity = r.vector2("initial_velocity", Eigen::Vector2d::Zero());
    if (const toml::table* stress = r.table("initial_stress")) {
      TableReader s(stress, r.prefix() + ".initial_stress", path, overridden);
      InitialStress initial;
      initial.k0 = s.number("k0", std::nullopt, 0, kInf);
      if (s.has("surface")) initial.surface = s.number("surface", std::nullopt, -kInf, kInf);
      s.finish();
      b.initial_stress = initial;
    }
    r.finish();
    scene.bodies.push_back(b);
  }

  if (const toml::table* boundaries = top.table("boundaries")) {
    for (const auto& [key, node] : *boundaries) {
      const std::string name(key.str());
      if (!node.as_table()) top.fail("boundaries." + name, "expected a table");
      TableReader r(node.as_table(), "boundaries." + name, path, overridden);
      Boundary b;
      b.name = name;
      b.group = r.text("group", name);
      const std::string type = r.text("type", std::nullopt);
      if (type == "fixed") b.type = BoundaryType::Fixed;
      else if (type == "roller") b.type = BoundaryType::Roller;
      else r.fail("type", "unknown boundary type '" + type + "' (expected fixed or roller)");
      if (r.has("normal")) {
        Eigen::Vector2d n = r.vector2("normal", std::nullopt);
        if (n.norm() == 0) r.fail("normal", "expected a non-zero vector");
        b.normal = n.normalized();
      }
      r.finish();
      scene.boundaries.push_back(b);
    }
  }

  TableReader contact(top.table("contact"), "contact", path, overridden);
  scene.contact.enabled = contact.boolean("enabled", true);
  scene.contact.friction = contact.number("friction", 0.0, 0, kInf);
  if (contact.has("pairs")) {
    const toml::array* pairs = root["contact"]["pairs"].as_array();
    if (!pairs) contact.fail("pairs", "expected an array of tables [[contact.pairs]]");
    for (std::size_t i = 0; i < pairs->size(); ++i) {
      const toml::table* table = (*pairs)[i].as_table();
      if (!table) contact.fail("pairs", "expected an array of tables [[contact.pairs]]");
      TableReader r(table, "contact.pairs[" + std::to_string(i) + "]", path, overridden);
      ContactPair pair;
      const std::vector<std::string> names = r.strings("bodies");
      if (names.size() != 2 || names[0] == names[1]) r.fail("bodies", "expected two different body names");
      for (const auto& n : names)
        if (scene.body_index(n) < 0) r.fail("bodies", "no body named '" + n + "' in [bodies]");
      pair.body_a = names[0];
      pair.body_b = names[1];
      pair.friction = r.number("friction", std::nullopt, 0, kInf);
      r.finish();
      scene.contact.pairs.push_back(pair);
    }
  }
  contact.finish();

  TableReader post(top.table("post"), "post", path, overridden);
  PostSettings& ps = scene.post;
  ps.metrics = post.strings("metrics");
  static const std::vector<std::string> kMetrics{"runout", "failure_surface", "bishop", "spring_mass", "box_incline"};
  for (const auto& m : ps.metrics)
    if (std::find(kMetrics.begin(), kMetrics.end(), m) == kMetrics.end()) {
      const std::string suggestion = nearest(m, kMetrics);
      post.fail("metrics", "unknown metric '" + m + "'" +
                               (suggestion.empty() ? " (expected runout, failure_surface, bishop, spring_mass or box_incline)"
                                                   : " (did you mean '" + suggestion + "'?)"));
    }
  ps.body = post.text("body", scene.bodies.front().name);
  if (scene.body_index(ps.body) < 0) post.fail("body", "no body named '" + ps.body + "' in [bodies]");
  ps.sliding_threshold = post.number("sliding_threshold", ps.sliding_threshold, 0, 1, false, true);
  ps.spring_amplitude = post.number("spring_amplitude", ps.spring_amplitude, 0, kInf, false);
  ps.spring_omega = post.number("spring_omega", ps.spring_omega, 0, kInf, false);
  ps.incline_angle = post.number("incline_angle", ps.incline_angle, 0, 90, false, false);
  post.finish();

  top.finish();

  std::ostringstream canonical;
  canonical << root;
  scene.canonical_text = canonical.str();
  return scene;
}

}  // namespace talus
