// The metadata of model.h5 and results.h5 (model_io.hpp): the format tag, bodies, materials,
// loads and settings; and the start of results.h5.
#include <cmath>
#include <type_traits>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/model/checks.hpp"
#include "common/model/model_io.hpp"
#include "common/model/parameters.hpp"
#include "common/model/seismic_io.hpp"

namespace talus {
namespace {

// One setting as an attribute of `group`: numbers as doubles, flags and counts as integers,
// vectors as lists of doubles.
void write_setting(const h5::File& file, const std::string& group, const char* name, double value) {
  h5::set_attribute(file, group, name, value);
}
void write_setting(const h5::File& file, const std::string& group, const char* name, const Eigen::Vector2d& value) {
  h5::set_attribute(file, group, name, std::vector<double>{value.x(), value.y()});
}
void write_setting(const h5::File& file, const std::string& group, const char* name, Transfer value) {
  h5::set_attribute(file, group, name, std::string(transfer_name(value)));
}
void write_setting(const h5::File& file, const std::string& group, const char* name, ShapeFunctions value) {
  h5::set_attribute(file, group, name, std::string(shape_functions_name(value)));
}
template <class Integer, class = std::enable_if_t<std::is_integral_v<Integer>>>
void write_setting(const h5::File& file, const std::string& group, const char* name, Integer value) {
  h5::set_attribute(file, group, name, static_cast<int64_t>(value));
}

void read_setting(const h5::File& file, const std::string& group, const char* name, double& value) {
  value = h5::get_double(file, group, name);
}
void read_setting(const h5::File& file, const std::string& group, const char* name, Eigen::Vector2d& value) {
  const auto values = h5::get_doubles(file, group, name);
  if (values.size() != 2) throw Error(located(file.path(), group + "@" + name, "expected two numbers"));
  value = {values[0], values[1]};
}
void read_setting(const h5::File& file, const std::string& group, const char* name, bool& value) {
  value = h5::get_int(file, group, name) != 0;
}
// A setting stored by its name (the transfer, the shape functions): `from_name` maps it back.
template <class Named, class FromName>
void read_named(const h5::File& file, const std::string& group, const char* name, Named& value, FromName from_name,
                const char* what, const char* expected) {
  const std::string text = h5::get_string(file, group, name);
  const auto named = from_name(text);
  if (!named)
    throw Error(located(file.path(), group + "@" + name,
                        std::string("unknown ") + what + " '" + text + "' (expected " + expected + ")"));
  value = *named;
}
void read_setting(const h5::File& file, const std::string& group, const char* name, Transfer& value) {
  read_named(file, group, name, value, transfer_from_name, "transfer", "flip, pic_blend, xpic or apic");
}
void read_setting(const h5::File& file, const std::string& group, const char* name, ShapeFunctions& value) {
  read_named(file, group, name, value, shape_functions_from_name, "shape functions", "linear, bspline or cpdi");
}
template <class Integer, class = std::enable_if_t<std::is_integral_v<Integer>>>
void read_setting(const h5::File& file, const std::string& group, const char* name, Integer& value) {
  value = static_cast<Integer>(h5::get_int(file, group, name));
}

// settings/water, only when there is a table: attributes unit_weight, mode, bulk_modulus and
// the datasets table [n, 2] and rise [m, 2].
void write_water(const h5::File& file, const WaterSettings& water) {
  if (!water.enabled()) return;
  h5::create_group(file, "settings/water");
  h5::set_attribute(file, "settings/water", "unit_weight", water.unit_weight);
  h5::set_attribute(file, "settings/water", "mode", std::string(water_mode_name(water.mode)));
  h5::set_attribute(file, "settings/water", "bulk_modulus", water.bulk_modulus);
  h5::write(file, "settings/water/table", talus::flatten(water.table), {water.table.size(), 2});
  h5::write(file, "settings/water/rise", talus::flatten(water.rise), {water.rise.size(), 2});
}

WaterSettings read_water(const h5::File& file) {
  WaterSettings water;
  if (!h5::exists(file, "settings/water")) return water;
  water.unit_weight = h5::get_double(file, "settings/water", "unit_weight");
  water.bulk_modulus = h5::get_double(file, "settings/water", "bulk_modulus");
  const std::string mode = h5::get_string(file, "settings/water", "mode");
  if (mode == "drained") water.mode = WaterMode::Drained;
  else if (mode == "undrained") water.mode = WaterMode::Undrained;
  else throw Error(located(file.path(), "settings/water@mode", "unknown mode '" + mode + "' (expected drained or undrained)"));
  for (const char* name : {"table", "rise"}) {
    const std::string path = std::string("settings/water/") + name;
    h5::Dims dims;
    const auto flat = h5::read_doubles(file, path, &dims);
    check_finite(file, path, flat);
    (std::string(name) == "table" ? water.table : water.rise) =
        unflatten<Eigen::Vector2d>(flat, dims, file, path, dims.empty() ? 0 : dims[0]);
  }
  if (const std::string problem = water_problem(water); !problem.empty())
    throw Error(located(file.path(), "settings/water", problem));
  return water;
}

}  // namespace

void check_count(const h5::File& file, const std::string& path, const h5::Dims& dims, std::size_t rows) {
  if (dims.size() != 1 || dims[0] != rows)
    throw Error(located(file.path(), path, "expected shape [" + std::to_string(rows) + "]"));
}

void check_finite(const h5::File& file, const std::string& path, const std::vector<double>& values) {
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i]))
      throw Error(located(file.path(), path, "non-finite value at flat index " + std::to_string(i)));
}

void write_format_tag(const h5::File& file, const std::string& kind, int version) {
  h5::set_attribute(file, "/", "format", std::string(kind));
  h5::set_attribute(file, "/", "format_version", static_cast<int64_t>(version));
  h5::set_attribute(file, "/", "talus_version", std::string(TALUS_VERSION));
}

void check_format_tag(const h5::File& file, const std::string& kind, int version) {
  if (!h5::has_attribute(file, "/", "format") || h5::get_string(file, "/", "format") != kind)
    throw Error(located(file.path(), "", "not a Talus " + kind + " file (no format=" + kind + " attribute)"));
  const int64_t found = h5::get_int(file, "/", "format_version");
  if (found != version)
    throw Error(located(file.path(), "format_version",
                        "file has version " + std::to_string(found) + ", this talus reads version " +
                            std::to_string(version) + " (re-run the stage that made it)"));
}

void write_metadata(const h5::File& file, const Model& model) {
  h5::set_attribute(file, "/", "scene", model.scene_name);

  std::vector<std::string> body_names;
  for (const auto& body : model.bodies) body_names.push_back(body.name);
  h5::write(file, "bodies/names", body_names);
  for (const auto& body : model.bodies) {
    const std::string group = "bodies/" + body.name;
    h5::create_group(file, group);
    h5::set_attribute(file, group, "material", static_cast<int64_t>(body.material));
    h5::set_attribute(file, group, "fixed", static_cast<int64_t>(body.fixed));
    h5::set_attribute(file, group, "loops", static_cast<int64_t>(body.loops.size()));
    for (std::size_t k = 0; k < body.loops.size(); ++k)
      h5::write(file, group + "/loop_" + std::to_string(k), flatten(body.loops[k]), {body.loops[k].size(), 2});
  }

  write_materials(file, model.materials);

  if (!model.loads.empty()) {
    std::vector<std::string> load_names;
    for (const auto& load : model.loads) load_names.push_back(load.name);
    h5::write(file, "loads/names", load_names);
    for (const auto& load : model.loads) {
      const std::string group = "loads/" + load.name;
      h5::create_group(file, group);
      h5::set_attribute(file, group, "group", load.group);
      if (load.pressure) h5::set_attribute(file, group, "pressure", *load.pressure);
      if (load.traction) write_setting(file, group, "traction", *load.traction);
      h5::set_attribute(file, group, "ramp", load.ramp);
    }
  }

  h5::create_group(file, "settings/run");
  for_each_run_setting(model.run,
                       [&](const char* name, const auto& value) { write_setting(file, "settings/run", name, value); });

  h5::create_group(file, "settings/contact");
  h5::set_attribute(file, "settings/contact", "enabled", static_cast<int64_t>(model.contact.enabled));
  h5::set_attribute(file, "settings/contact", "friction", model.contact.friction);
  std::vector<std::string> pair_names;
  std::vector<double> pair_friction;
  std::vector<int32_t> pair_bonded;
  for (const auto& pair : model.contact.pairs) {
    pair_names.push_back(pair.body_a);
    pair_names.push_back(pair.body_b);
    pair_friction.push_back(pair.friction);
    pair_bonded.push_back(pair.bonded);
  }
  h5::write(file, "settings/contact/pair_bodies", pair_names);
  h5::write(file, "settings/contact/pair_friction", pair_friction, {pair_friction.size()});
  h5::write(file, "settings/contact/pair_bonded", pair_bonded, {pair_bonded.size()});

  write_water(file, model.water);
  write_seismic(file, model.seismic, model.base_motion);

  const PostSettings& post = model.post;
  h5::create_group(file, "settings/post");
  h5::write(file, "settings/post/metrics", post.metrics);
  h5::set_attribute(file, "settings/post", "body", post.body);
  if (!post.bodies.empty()) h5::write(file, "settings/post/bodies", post.bodies);
  h5::set_attribute(file, "settings/post", "sliding_threshold", post.sliding_threshold);
  h5::set_attribute(file, "settings/post", "spring_amplitude", post.spring_amplitude);
  h5::set_attribute(file, "settings/post", "spring_omega", post.spring_omega);
  h5::set_attribute(file, "settings/post", "incline_angle", post.incline_angle);
  h5::set_attribute(file, "settings/post", "animate", static_cast<int64_t>(post.animate));
}

void read_metadata(const h5::File& file, Model& model) {
  model.scene_name = h5::get_string(file, "/", "scene");
  model.bodies.clear();
  for (const auto& name : h5::read_strings(file, "bodies/names")) {
    const std::string group = "bodies/" + name;
    BodyInfo body;
    body.name = name;
    body.material = static_cast<int>(h5::get_int(file, group, "material"));
    body.fixed = h5::get_int(file, group, "fixed") != 0;
    const int64_t loops = h5::get_int(file, group, "loops");
    for (int64_t k = 0; k < loops; ++k) {
      const std::string path = group + "/loop_" + std::to_string(k);
      h5::Dims dims;
      const auto flat = h5::read_doubles(file, path, &dims);
      check_finite(file, path, flat);
      body.loops.push_back(unflatten<Eigen::Vector2d>(flat, dims, file, path, dims.empty() ? 0 : dims[0]));
    }
    model.bodies.push_back(body);
  }

  model.materials = read_materials(file);
  for (const auto& body : model.bodies)
    if (body.material < 0 || body.material >= static_cast<int>(model.materials.size()))
      throw Error(located(file.path(), "bodies/" + body.name + "@material", "material index out of range"));

  model.loads.clear();
  if (h5::exists(file, "loads/names"))
    for (const auto& name : h5::read_strings(file, "loads/names")) {
      const std::string group = "loads/" + name;
      SurfaceLoad load;
      load.name = name;
      load.group = h5::get_string(file, group, "group");
      if (h5::has_attribute(file, group, "pressure")) load.pressure = h5::get_double(file, group, "pressure");
      if (h5::has_attribute(file, group, "traction")) {
        Eigen::Vector2d traction;
        read_setting(file, group, "traction", traction);
        load.traction = traction;
      }
      load.ramp = h5::get_double(file, group, "ramp");
      if (const std::string problem = load_problem(load); !problem.empty())
        throw Error(located(file.path(), group, problem));
      model.loads.push_back(load);
    }

  RunSettings& run = model.run;
  // Files written before the transfer was a setting meant FLIP, blended when pic_fraction > 0,
  // and had no xpic_order (2); files from before mixed integration integrate over the particles;
  // files from before the shape families are linear.
  const bool has_transfer = h5::has_attribute(file, "settings/run", "transfer");
  for_each_run_setting(run, [&](const char* name, auto& value) {
    const std::string key = name;
    if ((key == "transfer" || key == "xpic_order" || key == "full_cell_fill" || key == "shape_functions") &&
        !h5::has_attribute(file, "settings/run", name))
      return;
    read_setting(file, "settings/run", name, value);
  });
  if (!has_transfer) run.transfer = run.pic_fraction > 0 ? Transfer::PicBlend : Transfer::Flip;
  if (!h5::has_attribute(file, "settings/run", "xpic_order")) run.xpic_order = 2;  // the default then
  if (const std::string problem = run_settings_problem(run); !problem.empty())
    throw Error(located(file.path(), "", problem));
  if (const std::string problem = output_interval_problem(run); !problem.empty())
    throw Error(located(file.path(), "settings/run@output_interval", problem));

  model.contact.enabled = h5::get_int(file, "settings/contact", "enabled") != 0;
  model.contact.friction = h5::get_double(file, "settings/contact", "friction");
  if (!(model.contact.friction >= 0) || !std::isfinite(model.contact.friction))
    throw Error(located(file.path(), "settings/contact@friction", "expected a finite number >= 0"));
  const auto pair_names = h5::read_strings(file, "settings/contact/pair_bodies");
  const auto pair_friction = h5::read_doubles(file, "settings/contact/pair_friction");
  if (pair_names.size() != 2 * pair_friction.size())
    throw Error(located(file.path(), "settings/contact", "pair_bodies and pair_friction disagree"));
  // Files written before bonded pairs had no pair_bonded: no pair was bonded.
  std::vector<int32_t> pair_bonded(pair_friction.size(), 0);
  if (h5::exists(file, "settings/contact/pair_bonded")) pair_bonded = h5::read_ints(file, "settings/contact/pair_bonded");
  if (pair_bonded.size() != pair_friction.size())
    throw Error(located(file.path(), "settings/contact", "pair_bonded and pair_friction disagree"));
  model.contact.pairs.clear();
  for (std::size_t i = 0; i < pair_friction.size(); ++i) {
    if (!(pair_friction[i] >= 0) || !std::isfinite(pair_friction[i]))
      throw Error(located(file.path(), "settings/contact/pair_friction", "expected finite numbers >= 0"));
    if (pair_bonded[i] != 0 && pair_bonded[i] != 1)
      throw Error(located(file.path(), "settings/contact/pair_bonded", "expected 0 or 1"));
    model.contact.pairs.push_back({pair_names[2 * i], pair_names[2 * i + 1], pair_friction[i], pair_bonded[i] == 1});
  }
  {
    std::vector<std::string> names;
    std::vector<uint8_t> fixed;
    for (const auto& body : model.bodies) names.push_back(body.name), fixed.push_back(body.fixed);
    if (const std::string problem = contact_groups(model.contact, names, fixed).problem; !problem.empty())
      throw Error(located(file.path(), "settings/contact", problem));
  }

  model.water = read_water(file);
  read_seismic(file, model.seismic, model.base_motion);

  PostSettings& post = model.post;
  post.metrics = h5::read_strings(file, "settings/post/metrics");
  post.body = h5::get_string(file, "settings/post", "body");
  post.bodies = h5::exists(file, "settings/post/bodies") ? h5::read_strings(file, "settings/post/bodies")
                                                         : std::vector<std::string>{};
  post.sliding_threshold = h5::get_double(file, "settings/post", "sliding_threshold");
  post.spring_amplitude = h5::get_double(file, "settings/post", "spring_amplitude");
  post.spring_omega = h5::get_double(file, "settings/post", "spring_omega");
  post.incline_angle = h5::get_double(file, "settings/post", "incline_angle");
  // Absent from files written before it existed: animate, as the scene's default.
  post.animate = !h5::has_attribute(file, "settings/post", "animate") ||
                 h5::get_int(file, "settings/post", "animate") != 0;
}

void write_results_start(const h5::File& file, const Model& metadata,
                         const std::vector<Eigen::Vector2d>& initial_position, const std::vector<int32_t>& body,
                         const std::vector<double>& mass, const std::vector<double>& volume) {
  write_format_tag(file, "talus-results", kResultsFormatVersion);
  write_metadata(file, metadata);
  const hsize_t n = initial_position.size();
  h5::write(file, "particles/initial_position", flatten(initial_position), {n, 2});
  h5::write(file, "particles/body", body, {n});
  h5::write(file, "particles/mass", mass, {n});
  h5::write(file, "particles/volume", volume, {n});
  write_property_values(file, metadata, body);
  h5::set_attribute(file, "/", "particles", static_cast<int64_t>(n));
}

}  // namespace talus
