#include "solver/io/checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "common/error.hpp"
#include "common/fingerprint.hpp"
#include "common/h5.hpp"
#include "common/model/model_io.hpp"
#include "common/model/parameters.hpp"
#include "solver/io/particle_io.hpp"

namespace talus::solver {
namespace {

// A section's fingerprint as an HDF5 attribute value (the same 64 bits, signed).
int64_t stored(const Fingerprint& f) {
  const uint64_t value = f.value();
  int64_t out = 0;
  std::memcpy(&out, &value, sizeof out);
  return out;
}

// A setting's value: numbers and flags as they are, vectors component by component.
void add_setting(Fingerprint& f, const Eigen::Vector2d& value) { f.add(value.x()).add(value.y()); }
void add_setting(Fingerprint& f, Transfer value) { f.add(static_cast<int>(value)); }
// Linear adds nothing, so checkpoints from before the shape families still match.
void add_setting(Fingerprint& f, ShapeFunctions value) {
  if (value != ShapeFunctions::Linear) f.add(static_cast<int>(value));
}
template <class T>
void add_setting(Fingerprint& f, const T& value) {
  f.add(value);
}

// A name with its length, so that consecutive names cannot run into each other.
Fingerprint& add_name(Fingerprint& f, const std::string& name) { return f.add(name.size()).add(name); }

const char* const kLoopGroup = "loop";
const char* const kFingerprintGroup = "fingerprint";

}  // namespace

std::vector<std::pair<std::string, int64_t>> model_fingerprints(const Model& model) {
  std::vector<std::pair<std::string, int64_t>> sections;
  sections.emplace_back("mesh", stored(Fingerprint().add(model.nodes).add(model.triangles)));
  Fingerprint boundary = Fingerprint().add(model.fixed_nodes).add(model.roller_nodes).add(model.roller_normals);
  if (!model.friction_nodes.empty())  // a model without friction nodes keeps its earlier fingerprint
    boundary.add(model.friction_nodes).add(model.friction_normals).add(model.friction_coefficients);
  sections.emplace_back("boundary conditions", stored(boundary));
  sections.emplace_back("particles", stored(Fingerprint()
                                                .add(model.position)
                                                .add(model.velocity)
                                                .add(model.mass)
                                                .add(model.volume)
                                                .add(model.body)
                                                .add(model.element)));
  sections.emplace_back("initial stress", stored(Fingerprint().add(model.stress)));
  Fingerprint bodies;
  for (const auto& body : model.bodies) add_name(bodies, body.name).add(body.material).add(body.fixed);
  sections.emplace_back("bodies", stored(bodies));
  for (const auto& m : model.materials) {
    Fingerprint material;
    add_name(material, std::string(model_name(m)));
    for_each_parameter(m, [&](const Parameter&, double value) { material.add(value); });
    sections.emplace_back("materials." + m.name, stored(material));
  }
  if (!model.properties.empty()) {  // no section without them
    Fingerprint properties;
    for (const auto& property : model.properties)
      add_name(add_name(properties, property.material), property.parameter).add(property.values);
    sections.emplace_back("particle properties", stored(properties));
  }
  Fingerprint contact;
  contact.add(model.contact.enabled).add(model.contact.friction);
  for (const auto& pair : model.contact.pairs) {
    add_name(add_name(contact, pair.body_a), pair.body_b).add(pair.friction);
    if (pair.bonded) contact.add("bonded");  // only then, so older checkpoints still match
  }
  sections.emplace_back("contact", stored(contact));
  if (!model.loads.empty()) {  // absent without loads, so older checkpoints still match
    Fingerprint loads;
    for (const auto& load : model.loads) {
      add_name(add_name(loads, load.name), load.group).add(load.pressure.has_value()).add(load.pressure.value_or(0));
      add_setting(loads, load.traction.value_or(Eigen::Vector2d::Zero()));
      loads.add(load.ramp);
    }
    loads.add(model.load).add(model.load_length).add(model.load_normal);
    sections.emplace_back("loads", stored(loads));
  }
  Fingerprint run;
  for_each_run_setting(model.run, [&](const char*, const auto& value) { add_setting(run, value); });
  sections.emplace_back("run settings", stored(run));
  if (model.water.enabled()) {  // no section without water: dry checkpoints keep their fingerprints
    const WaterSettings& w = model.water;
    Fingerprint water;
    water.add(w.table).add(w.unit_weight).add(static_cast<int>(w.mode)).add(w.bulk_modulus).add(w.rise);
    sections.emplace_back("water", stored(water));
  }
  return sections;
}

std::string checkpoint_path(const std::string& out_dir) {
  return (std::filesystem::path(out_dir) / "checkpoint.h5").string();
}

void write_checkpoint(const std::string& out_dir, const Model& model, const Simulation& sim, const LoopState& loop,
                      const ResultsPosition& results) {
  write_checkpoint(out_dir, model_fingerprints(model), sim, loop, results);
}

void write_checkpoint(const std::string& out_dir, const Fingerprints& fingerprints, const Simulation& sim,
                      const LoopState& loop, const ResultsPosition& results) {
  write_checkpoint(out_dir, fingerprints, sim.particles, sim.time, sim.steps, loop, results, sim.absorbing_reaction);
}

void write_checkpoint(const std::string& out_dir, const Fingerprints& fingerprints, const Particles& P, double time,
                      long steps, const LoopState& loop, const ResultsPosition& results,
                      const std::vector<Vec2>& absorbing_reaction) {
  const std::string path = checkpoint_path(out_dir);
  h5::write_atomically(path, [&](const h5::File& file) {
    write_format_tag(file, "talus-checkpoint", kCheckpointFormatVersion);
    h5::create_group(file, kFingerprintGroup);
    for (const auto& [section, value] : fingerprints) h5::set_attribute(file, kFingerprintGroup, section, value);

    const std::size_t n = P.size();
    h5::set_attribute(file, "/", "particles", static_cast<int64_t>(n));
    h5::set_attribute(file, "/", "moving_count", static_cast<int64_t>(P.moving_count));
    h5::set_attribute(file, "/", "time", time);
    h5::set_attribute(file, "/", "steps", static_cast<int64_t>(steps));
    P.for_each_field([&](const FieldInfo& field, const auto& column) {
      if (field.roles & kCheckpointed) write_column(file, std::string("particles/") + field.name, column, n);
    });
    if (!absorbing_reaction.empty()) {
      std::vector<double> flat;
      for (const Vec2& r : absorbing_reaction) flat.push_back(r.x()), flat.push_back(r.y());
      h5::write(file, "absorbing_reaction", flat, {absorbing_reaction.size(), 2});
    }

    h5::create_group(file, kLoopGroup);
    h5::set_attribute(file, kLoopGroup, "next_output", loop.next_output);
    h5::set_attribute(file, kLoopGroup, "next_checkpoint", loop.next_checkpoint);
    h5::set_attribute(file, kLoopGroup, "peak_kinetic", loop.peak_kinetic);
    h5::set_attribute(file, kLoopGroup, "peak_time", loop.peak_time);
    h5::set_attribute(file, kLoopGroup, "rest_since", loop.rest_since);
    h5::set_attribute(file, kLoopGroup, "budget", loop.budget);
    h5::set_attribute(file, kLoopGroup, "budget_limit", loop.budget_limit);
    h5::set_attribute(file, kLoopGroup, "budget_supply", loop.budget_supply);
    h5::set_attribute(file, kLoopGroup, "start_potential", loop.start_potential);
    h5::set_attribute(file, kLoopGroup, "results_frames", static_cast<int64_t>(results.frames));
    h5::set_attribute(file, kLoopGroup, "results_history_rows", static_cast<int64_t>(results.history_rows));
  });
}

namespace {

// The sections of the model that differ from those the checkpoint was written for.
std::string changed_sections(const h5::File& file, const Model& model) {
  std::string changed;
  for (const auto& [section, value] : model_fingerprints(model))
    if (!h5::has_attribute(file, kFingerprintGroup, section) || h5::get_int(file, kFingerprintGroup, section) != value)
      changed += (changed.empty() ? "" : ", ") + section;
  const std::vector<std::pair<std::string, int64_t>> now = model_fingerprints(model);
  for (const std::string& stored : h5::list_attributes(file, kFingerprintGroup)) {
    bool known = false;
    for (const auto& section : now) known = known || section.first == stored;
    if (!known) changed += (changed.empty() ? "" : ", ") + stored + " (gone)";
  }
  return changed;
}

}  // namespace

void read_checkpoint(const std::string& out_dir, const Model& model, Simulation& sim, LoopState& loop,
                     ResultsPosition& results) {
  const std::string path = checkpoint_path(out_dir);
  if (!std::filesystem::exists(path))
    throw Error(located(path, "", "no checkpoint to restart from (solve with --checkpoint-interval T, or stop a "
                                  "solve with Ctrl-C, to write one)"));
  h5::File file = h5::File::open_read(path);
  check_format_tag(file, "talus-checkpoint", kCheckpointFormatVersion);
  const std::string changed = changed_sections(file, model);
  if (!changed.empty())
    throw Error(located(path, "", "written for another model: " + changed +
                                      " changed since (solve afresh, or restore the scene it was written for)"));

  const std::size_t n = model.particle_count();
  if (h5::get_int(file, "/", "particles") != static_cast<int64_t>(n))
    throw Error(located(path, "particles", "expected " + std::to_string(n) + " particles"));
  const int64_t moving = h5::get_int(file, "/", "moving_count");
  if (moving < 0 || moving > static_cast<int64_t>(n)) throw Error(located(path, "moving_count", "out of range"));

  // Every checkpointed field, in the widths make_simulation gave it for this model.
  Particles P = sim.particles;
  P.for_each_field([&](const FieldInfo& field, auto& column) {
    if (field.roles & kCheckpointed) read_column(file, std::string("particles/") + field.name, column, n);
  });
  P.moving_count = static_cast<std::size_t>(moving);
  std::vector<bool> seen(n, false);
  const auto& fixed = sim.config.body_fixed;
  for (std::size_t p = 0; p < n; ++p) {
    if (!(P.m[p] > 0) || !(P.volume[p] > 0))
      throw Error(located(path, "particles", "particle " + std::to_string(p) + " has a bad mass or volume"));
    if (P.body[p] < 0 || P.body[p] >= static_cast<int32_t>(fixed.size()) || P.element[p] < 0 ||
        P.element[p] >= static_cast<int32_t>(sim.config.mesh.element_count()) || P.id[p] < 0 ||
        P.id[p] >= static_cast<int32_t>(n) || seen[P.id[p]])
      throw Error(located(path, "particles", "particle " + std::to_string(p) + " has an index out of range"));
    seen[P.id[p]] = true;
    if (!P.load.empty() && (P.load[p] < -1 || P.load[p] >= static_cast<int32_t>(sim.config.load_ramp.size()) ||
                            !P.load_force[p].allFinite()))
      throw Error(located(path, "particles/load", "particle " + std::to_string(p) + " has a bad surface load"));
    if (fixed[P.body[p]] != (p >= P.moving_count))
      throw Error(located(path, "moving_count", "particles of fixed bodies must come after all the others"));
  }
  sim.particles = std::move(P);
  compute_stencil(sim.config.mesh, sim.particles, 0, n, sim.scratch.stencil, sim.config.threads);
  sim.time = h5::get_double(file, "/", "time");
  sim.steps = static_cast<long>(h5::get_int(file, "/", "steps"));
  if (!std::isfinite(sim.time) || sim.time < 0 || sim.steps < 0)
    throw Error(located(path, "time, steps", "out of range"));

  loop.next_output = h5::get_double(file, kLoopGroup, "next_output");
  loop.next_checkpoint = h5::get_double(file, kLoopGroup, "next_checkpoint");
  loop.peak_kinetic = h5::get_double(file, kLoopGroup, "peak_kinetic");
  loop.peak_time = h5::get_double(file, kLoopGroup, "peak_time");
  loop.rest_since = h5::get_double(file, kLoopGroup, "rest_since");
  loop.budget = h5::get_double(file, kLoopGroup, "budget");
  loop.budget_limit = h5::get_double(file, kLoopGroup, "budget_limit");
  // Checkpoints written before the blow-up test's second part keep the first part alone.
  if (h5::has_attribute(file, kLoopGroup, "budget_supply")) {
    loop.budget_supply = h5::get_double(file, kLoopGroup, "budget_supply");
    loop.start_potential = h5::get_double(file, kLoopGroup, "start_potential");
  }
  if (!std::isfinite(loop.next_output) || !(loop.next_output > sim.time) || !(loop.next_checkpoint > sim.time))
    throw Error(located(path, "loop@next_output, loop@next_checkpoint", "not ahead of the checkpoint's time"));
  sim.absorbing_reaction.clear();
  if (h5::exists(file, "absorbing_reaction")) {
    const std::vector<double> flat = h5::read_doubles(file, "absorbing_reaction");
    const std::size_t expected = 2 * sim.config.absorbing.node.size() * sim.scratch.grids.fields.size();
    if (flat.size() != expected || !std::all_of(flat.begin(), flat.end(), [](double v) { return std::isfinite(v); }))
      throw Error(located(path, "absorbing_reaction", "expected " + std::to_string(expected) + " finite values"));
    for (std::size_t k = 0; k + 1 < flat.size(); k += 2) sim.absorbing_reaction.emplace_back(flat[k], flat[k + 1]);
  }
  results.frames = static_cast<long>(h5::get_int(file, kLoopGroup, "results_frames"));
  results.history_rows = static_cast<long>(h5::get_int(file, kLoopGroup, "results_history_rows"));
}

}  // namespace talus::solver
