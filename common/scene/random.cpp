// The reader of the scene's [random.NAME] tables (common/scene/scene.hpp, RandomField; docs/scenes.md):
// a material parameter as a spatially correlated random field (issue 41). The fields
// themselves are drawn by preproc/random_field/random_field.hpp.
#include <algorithm>
#include <cmath>

#include "common/materials/materials.hpp"
#include "common/scene/reader.hpp"

namespace talus::scene_reader {
namespace {

// The parameters a [random] table may vary: those a particle may carry as its own
// (common/model/model.hpp, ParticleProperty), every key of the material's model but density and
// saturated_density.
bool may_be_random(const std::string& key) { return key != "density" && key != "saturated_density"; }

// The problem of `value` as the parameter `key` of `material` (its range may depend on the
// material's other values: dilation_angle on friction_angle), or "".
std::string problem_of(Material material, const std::string& key, double value) {
  set_parameter(material, *parameter_slot(material, key), value);
  return find_parameter(material, key)->problem(value);
}

std::string list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// The parameter's name, checked against the keys of the material's model.
std::string read_parameter(TableReader& r, const Material& material) {
  const std::string parameter = r.text("parameter", std::nullopt);
  const std::optional<Parameter> found = find_parameter(material, parameter);
  if (!found || !may_be_random(parameter)) {
    std::vector<std::string> keys;
    for_each_parameter(material, [&](const Parameter& p, double) {
      if (may_be_random(p.name)) keys.push_back(p.name);
    });
    r.fail("parameter", "'" + echoed(parameter) + "' cannot be random for materials." + material.name + ", a " +
                            std::string(model_name(material)) + " material (expected one of " + list(keys) + ")");
  }
  // A key that acts only with another one on (the residual strength with softening_end).
  if (found->needs) {
    const std::optional<Parameter> needed = find_parameter(material, found->needs);
    if (needed && needed->off && *parameter_value(material, found->needs) == *needed->off)
      r.fail("parameter", "materials." + material.name + " has no " + found->needs + " (" + found->needs_why +
                              "), so no " + parameter);
  }
  return parameter;
}

// mean > 0 in the parameter's range; cov > 0, and for a uniform distribution its whole range
// [mean (1 - sqrt(3) cov), mean (1 + sqrt(3) cov)] in the parameter's range too.
void read_moments(TableReader& r, const Material& material, RandomField& field) {
  field.mean = r.number("mean", std::nullopt, 0, kInf, false);
  if (const std::string problem = problem_of(material, field.parameter, field.mean); !problem.empty())
    r.fail("mean", problem + " (the range of " + field.parameter + ")");
  field.cov = r.number("cov", std::nullopt, 0, kInf, false);
  if (field.distribution != RandomDistribution::Uniform) return;
  const double half_width = std::sqrt(3.0) * field.cov * field.mean;
  for (const double end : {field.mean - half_width, field.mean + half_width})
    if (const std::string problem = problem_of(material, field.parameter, end); !problem.empty())
      r.fail("cov", "the uniform distribution's range, mean (1 - sqrt(3) cov) to mean (1 + sqrt(3) cov), leaves "
                    "the range of " + field.parameter + ": at its end " + problem);
}

// correlation_length = [horizontal, vertical]: two lengths > 0 m, inf for a field fully
// correlated along that axis ([inf, inf]: one value per realisation).
Eigen::Vector2d read_lengths(TableReader& r) {
  const std::string expected = "expected [horizontal, vertical]: two lengths > 0 m, inf for a fully correlated axis";
  const toml::array* list = r.array("correlation_length", expected);
  if (!list) r.fail("correlation_length", "missing (" + expected + ")");
  if (list->size() != 2) r.fail("correlation_length", expected);
  Eigen::Vector2d lengths;
  for (int a = 0; a < 2; ++a) {
    const auto x = (*list)[a].value<double>();
    if (!x || !(*x > 0)) r.fail("correlation_length", expected);
    lengths[a] = *x;
  }
  return lengths;
}

RandomField read_field(TableReader& top, const std::string& name, const toml::table* table, const Scene& scene) {
  check_name(name, "random." + name, top.file());
  TableReader r = top.child(table, "random." + name);
  RandomField field;
  field.name = name;
  field.material = r.text("material", std::nullopt);
  const int m = scene.material_index(field.material);
  if (m < 0) r.fail("material", "no material '" + echoed(field.material) + "' in [materials]");
  const Material& material = scene.materials[m];
  field.parameter = read_parameter(r, material);
  for (const RandomField& other : scene.random)
    if (other.material == field.material && other.parameter == field.parameter)
      r.fail("parameter", "random." + other.name + " already makes materials." + field.material + "." +
                              field.parameter + " random");

  const std::string distribution = r.text("distribution", std::nullopt);
  if (distribution == "lognormal") field.distribution = RandomDistribution::Lognormal;
  else if (distribution == "normal") field.distribution = RandomDistribution::Normal;
  else if (distribution == "uniform") field.distribution = RandomDistribution::Uniform;
  else r.fail("distribution", "unknown distribution '" + echoed(distribution) + "' (expected lognormal, normal or uniform)");
  read_moments(r, material, field);

  field.correlation_length = read_lengths(r);
  const std::string correlation = r.text("correlation", "markov");
  if (correlation == "markov") field.correlation = Correlation::Markov;
  else if (correlation == "gaussian") field.correlation = Correlation::Gaussian;
  else r.fail("correlation", "unknown correlation '" + echoed(correlation) + "' (expected markov or gaussian)");

  if (const toml::table* cross = r.table("cross_correlation")) {
    TableReader c = r.child(cross, r.prefix() + ".cross_correlation");
    field.cross_with = c.text("with", std::nullopt);
    field.cross_rho = c.number("rho", std::nullopt, -1, 1, false, false);
    c.finish();
  }
  r.finish();
  return field;
}

// A cross-correlated field names another [random] table that has no cross_correlation of its
// own (so pairs never chain or loop) and shares its correlation: the 2 x 2 Cholesky factor
// mixes two fields of one correlation structure, which keeps that structure.
void check_cross_correlations(TableReader& top, const Scene& scene) {
  for (const RandomField& field : scene.random) {
    if (field.cross_with.empty()) continue;
    const std::string key = "random." + field.name + ".cross_correlation.with";
    if (field.cross_with == field.name) top.fail(key, "a field cannot be cross-correlated with itself");
    const auto partner = std::find_if(scene.random.begin(), scene.random.end(),
                                      [&](const RandomField& f) { return f.name == field.cross_with; });
    if (partner == scene.random.end())
      top.fail(key, "no [random." + echoed(field.cross_with) + "] table to correlate with");
    if (!partner->cross_with.empty())
      top.fail(key, "random." + partner->name + " has a cross_correlation of its own (with " + partner->cross_with +
                        "): name a field without one, so that each pair is given once");
    if (partner->correlation != field.correlation || partner->correlation_length != field.correlation_length)
      top.fail(key, "random." + partner->name +
                        " has another correlation or correlation_length: cross-correlated fields share both");
  }
}

}  // namespace

void read_random(TableReader& top, Scene& scene) {
  const toml::table* random = top.table("random");
  if (!random) return;
  for (const auto& [key, node] : *random) {
    const std::string name(key.str());
    if (!node.as_table()) top.fail("random." + name, "expected a table");
    scene.random.push_back(read_field(top, name, node.as_table(), scene));
  }
  check_cross_correlations(top, scene);
}

}  // namespace talus::scene_reader
