// Building a simulation from a model, sizing its scratch for a thread count, and keeping the
// particles ordered by element.
#include <algorithm>
#include <numeric>
#include <optional>
#include <type_traits>

#include "common/error.hpp"
#include "solver/stress/water.hpp"
#include "solver/step/simulation.hpp"
#include "solver/step/step.hpp"

namespace talus::solver {
namespace {

void resize_grid(Grid& grid, std::size_t nodes, bool contact, bool xpic) {
  grid.m.assign(nodes, 0);
  grid.p.assign(nodes, Vec2::Zero());
  grid.f.assign(nodes, Vec2::Zero());
  grid.a.assign(nodes, Vec2::Zero());
  grid.v.assign(nodes, Vec2::Zero());
  if (contact) grid.mass_gradient.assign(nodes, Vec2::Zero());
  if (xpic) grid.xpic_term.assign(nodes, Vec2::Zero());
}

// A copy of one of the model's particle columns, or, with `owned` (the same object as model,
// handed over by its owner), the column itself.
template <class T>
std::vector<T> column_of(const Model& model, Model* owned, std::vector<T> Model::*column) {
  return owned ? std::move(owned->*column) : model.*column;
}

// The particles of the model, in model order, each located in its element.
Particles particles_of(const Model& model, Model* owned, const Config& config) {
  Particles P;
  const std::size_t n = model.particle_count();
  if (!model.loads.empty()) {  // the force at full load: pressure along the inward normal, or traction x length
    P.load = model.load;       // (before the columns move out: particle_count() reads position)
    P.load_force = particle_load_forces(model);
  }
  P.properties = particle_properties(model, config);  // (before the columns move out, likewise)
  P.x = column_of(model, owned, &Model::position);
  P.v = column_of(model, owned, &Model::velocity);
  P.m = column_of(model, owned, &Model::mass);
  P.volume = column_of(model, owned, &Model::volume);
  P.sigma = column_of(model, owned, &Model::stress);
  P.eps_p.assign(n, 0);
  for (const auto& material : config.materials) P.history_width = std::max(P.history_width, material.history_width);
  P.history.assign(n * static_cast<std::size_t>(P.history_width), 0);
  if (config.transfer == Transfer::Apic) P.C.assign(n, Vec4::Zero());  // uniform initial velocities
  P.body = column_of(model, owned, &Model::body);
  P.element = column_of(model, owned, &Model::element);
  P.id.resize(n);
  std::iota(P.id.begin(), P.id.end(), 0);
  for (std::size_t p = 0; p < n; ++p) {
    const int32_t e = locate(config.mesh, P.element[p], P.x[p]);
    if (e < 0)
      throw Error("model: particle " + std::to_string(p) + " at (" + std::to_string(P.x[p].x()) + ", " +
                  std::to_string(P.x[p].y()) + ") is outside the background mesh");
    P.element[p] = e;
    if (config.body_fixed[P.body[p]]) P.v[p].setZero();
  }
  return P;
}

template <class T>
void permute_column(std::vector<T>& values, const std::vector<int32_t>& order) {
  const std::size_t width = width_of(values, order.size());
  if (width == 0) return;
  std::vector<T> sorted(values.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    std::copy_n(values.begin() + order[k] * width, width, sorted.begin() + k * width);
  values.swap(sorted);
}

}  // namespace

void permute_particles(Particles& particles, const std::vector<int32_t>& order) {
  particles.for_each_field([&](const FieldInfo&, auto& column) { permute_column(column, order); });
}

namespace {

// The model's shape-function family (run.shape_functions). B-splines take the grid pattern's
// lattice, add its ghost layer to the mesh's nodes and constraints, and step by the lattice's
// cell: a particle crosses no more than one cell per step at CFL <= 1.
ShapeFamily shape_family(const Model& model, Mesh& mesh, Constraints& constraints, Stencil& stencil) {
  if (model.run.shape_functions == ShapeFunctions::Linear) return ShapeFamily::LinearTriangle;
  if (model.run.shape_functions == ShapeFunctions::Cpdi) {
    if (model.run.full_cell_fill > 0)
      throw Error("model: run.integration = \"mixed\" is for linear triangles; CPDI integrates over the particles' domains");
    return ShapeFamily::LinearCpdi;
  }
  std::optional<Lattice> lattice = find_lattice(mesh);
  if (!lattice)
    throw Error("model: run.shape_functions = \"bspline\" needs the grid pattern's background mesh "
                "(mesh.pattern = \"grid\": a lattice of cells over the domain's rectangle)");
  if (model.run.evs)
    throw Error("model: run.evs: enhanced volumetric strain is for linear triangles; B-splines do not use it");
  if (model.run.full_cell_fill > 0)
    throw Error("model: run.integration = \"mixed\" is for linear triangles; B-splines integrate at the particles");
  add_ghost_layer(*lattice, mesh, constraints);
  mesh.h_min = lattice->spacing.minCoeff();
  stencil.lattice = std::move(*lattice);
  return ShapeFamily::QuadraticBspline;
}

// make_simulation; with `owned` (the same object as model) the model's particle columns are
// moved into the simulation and its other per-particle columns released.
Simulation build_simulation(const Model& model, Model* owned, int threads) {
  Simulation sim;
  Config& config = sim.config;
  config.mesh = build_mesh(model);
  config.constraints = build_constraints(model);
  const ShapeFamily family = shape_family(model, config.mesh, config.constraints, sim.scratch.stencil);
  config.gravity = model.run.gravity;
  config.gravity_ramp = model.run.gravity_ramp;
  config.damping = model.run.damping;
  config.transfer = model.run.transfer;
  config.pic_fraction = config.transfer == Transfer::PicBlend ? model.run.pic_fraction : 0.0;
  config.xpic_order = config.transfer == Transfer::Xpic ? model.run.xpic_order : 1;
  config.evs = model.run.evs;
  config.full_cell_fill = model.run.full_cell_fill;
  config.initial_volume = model.volume;
  for (const auto& load : model.loads) config.load_ramp.push_back(load.ramp);
  config.water = model.water;
  config.base_motion = model.base_motion;
  config.ground_moves = model.base_motion.enabled() && !model.base_motion.compliant;
  config.absorbing = model.absorbing;
  prepare_materials(config, model);
  for (const auto& body : model.bodies) {
    config.material_of_body.push_back(body.material);
    config.body_fixed.push_back(body.fixed);
  }
  sim.particles = particles_of(model, owned, config);
  if (family == ShapeFamily::LinearCpdi) initial_domains(config.mesh, sim.particles);
  prepare_particle_materials(config.materials, config.material_of_body, sim.particles);
  if (owned) release_particles(*owned);
  initial_pore_pressures(sim.particles, config, 0);
  sim.scratch.stencil.affine = config.transfer == Transfer::Apic;
  reset_stencil(sim.scratch.stencil, family, config.mesh, sim.particles.size());
  sort_particles(sim);
  sim.reorders = 0;

  // The contact pass runs only where bodies can meet: two or more field groups (bodies, or
  // groups of bonded bodies), contact on.
  std::vector<std::string> names;
  for (const auto& body : model.bodies) names.push_back(body.name);
  ContactGroups groups = contact_groups(model.contact, names, config.body_fixed);
  if (!groups.problem.empty()) throw Error("contact: " + groups.problem);
  config.contact = model.contact.enabled && groups.count() > 1;
  if (config.contact) {
    config.pair_friction = std::move(groups.friction);
    config.field_fixed = std::move(groups.fixed);
    if (std::find(config.field_fixed.begin(), config.field_fixed.end(), 1) != config.field_fixed.end())
      config.node_length = element_lengths_at_nodes(config.mesh);
    sim.scratch.grids.field_index = std::move(groups.of_body);
  } else {
    // One velocity field: a fixed body is a rigid support, so the nodes it touches do not move.
    const Particles& P = sim.particles;
    const Stencil& S = sim.scratch.stencil;
    for (std::size_t p = P.moving_count; p < P.size(); ++p)
      for (int k = 0; k < S.width; ++k) config.constraints.kind[S.nodes(p)[k]] = Constraint::Fixed;
  }

  Scratch& scratch = sim.scratch;
  const std::size_t nodes = config.mesh.node_count();
  scratch.grids.per_body = config.contact;
  if (!config.contact) scratch.grids.field_index.assign(model.bodies.size(), 0);
  scratch.grids.fields.resize(config.contact ? config.field_fixed.size() : 1);
  const bool xpic = config.transfer == Transfer::Xpic && config.xpic_order > 1;
  for (auto& grid : scratch.grids.fields) resize_grid(grid, nodes, config.contact, xpic);
  scratch.node_stamp.assign(nodes, 0);
  scratch.d_eps.assign(sim.particles.size(), Vec4::Zero());
  scratch.element_count.assign(config.mesh.element_count(), 0);
  if (config.evs) {
    const std::size_t elements = config.mesh.element_count();
    scratch.evs.strain.assign(elements, 0);
    scratch.evs.volume.assign(elements, 0);
    scratch.evs.node_strain.assign(nodes, 0);
    scratch.evs.node_area.assign(nodes, 0);
    scratch.evs.node_mean.assign(nodes, 0);
    evs_adjacency(config.mesh, scratch.evs);
  }
  if (config.full_cell_fill > 0) scratch.cell_scale.assign(config.mesh.element_count(), 1.0);
  set_threads(sim, threads);
  return sim;
}

}  // namespace

Simulation make_simulation(const Model& model, int threads) { return build_simulation(model, nullptr, threads); }

Simulation make_simulation(Model&& model, int threads) { return build_simulation(model, &model, threads); }

void release_particles(Model& model) {
  auto release = [](auto& column) { std::decay_t<decltype(column)>().swap(column); };
  release(model.position);
  release(model.velocity);
  release(model.volume);
  release(model.mass);
  release(model.stress);
  release(model.body);
  release(model.element);
  release(model.load);
  release(model.load_length);
  release(model.load_normal);
  for (auto& property : model.properties) release(property.values);
}

void set_threads(Simulation& sim, int threads) {
  threads = std::max(threads, 1);
  sim.config.threads = threads;
  Scratch& scratch = sim.scratch;
  const std::size_t nodes = sim.config.mesh.node_count();
  const std::size_t fields = scratch.grids.fields.size();
  const bool contact = sim.config.contact;
  scratch.buffers.assign(threads, std::vector<NodeBuffer>(fields));
  for (auto& per_thread : scratch.buffers)
    for (auto& buffer : per_thread) {
      buffer.m.assign(nodes, 0);
      buffer.p.assign(nodes, Vec2::Zero());
      buffer.f.assign(nodes, Vec2::Zero());
      if (contact) buffer.mass_gradient.assign(nodes, Vec2::Zero());
    }
  if (sim.config.evs) {
    const std::size_t elements = sim.config.mesh.element_count();
    scratch.evs.element_strain.assign(threads, std::vector<double>(elements, 0.0));
    scratch.evs.element_volume.assign(threads, std::vector<double>(elements, 0.0));
  }
  if (sim.config.full_cell_fill > 0)
    scratch.cell_volume.assign(threads, std::vector<double>(sim.config.mesh.element_count(), 0.0));
}

void sort_particles(Simulation& sim) {
  Particles& P = sim.particles;
  const std::size_t n = P.size();
  const auto& fixed = sim.config.body_fixed;
  // A counting sort on the key (fixed, element): stable, so particles of one element keep their
  // order, and linear in the particles and the elements (a comparison sort was 1 % of the
  // slope's instructions).
  const std::size_t elements = sim.config.mesh.element_count();
  const auto key = [&](std::size_t p) {
    return (fixed[P.body[p]] ? elements : 0) + static_cast<std::size_t>(P.element[p]);
  };
  std::vector<int32_t> start(2 * elements + 1, 0);
  for (std::size_t p = 0; p < n; ++p) ++start[key(p) + 1];
  for (std::size_t k = 0; k < 2 * elements; ++k) start[k + 1] += start[k];
  std::vector<int32_t> order(n);
  for (std::size_t p = 0; p < n; ++p) order[static_cast<std::size_t>(start[key(p)]++)] = static_cast<int32_t>(p);
  permute_particles(P, order);
  P.moving_count = 0;
  while (P.moving_count < n && !fixed[P.body[P.moving_count]]) ++P.moving_count;
  compute_stencil(sim.config.mesh, P, 0, n, sim.scratch.stencil, sim.config.threads);
  // The fixed particles' runs (contact.cpp) are rebuilt: on several ranks a migration leaves
  // the fixed particles out of element order, and the sort moves them.
  sim.scratch.contact.fixed_runs.clear();
  ++sim.reorders;
}

}  // namespace talus::solver
