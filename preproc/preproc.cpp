// build_model, step by step:
//   1. gmsh reads and meshes the .geo (gmsh_geometry.cpp);
//   2. the domain's triangles become the background mesh (background_mesh.cpp), or for the grid
//      pattern a lattice over the domain's rectangle (lattice.cpp);
//   3. each body's outline is chained into loops and checked against the domain (polygon.cpp);
//   4. particles are seeded in every triangle and kept inside their body (seeding.cpp);
//   5. boundary curves become fixed and roller nodes (boundary_conditions.cpp);
//   6. loaded curves are shared out among the particles along them (surface_loads.cpp);
//   7. materials and settings are copied from the scene.
#include "preproc/preproc.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "preproc/background_mesh.hpp"
#include "preproc/absorbing.hpp"
#include "preproc/boundary_conditions.hpp"
#include "preproc/estimate.hpp"
#include "preproc/gmsh_geometry.hpp"
#include "preproc/initial_state.hpp"
#include "preproc/lattice.hpp"
#include "preproc/polygon.hpp"
#include "preproc/scene_groups.hpp"
#include "preproc/seeding.hpp"
#include "preproc/surface_loads.hpp"

namespace talus::preproc {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

Model build_model(const Scene& scene, MeshReport* report) {
  const Clock::time_point start = Clock::now();
  if (scene.bodies.empty()) throw Error(located(scene.path, "bodies", "the scene has no bodies"));

  check_size(scene);  // before gmsh meshes: refuse a mesh too large for memory or too coarse for a body

  // 1. Mesh.
  const GeoMesh geo = mesh_geometry(scene.geometry, scene.mesh.size, "scene.geometry in " + scene.path,
                                    scene.mesh.parameters, scene.mesh.pattern == MeshPattern::Crossed);
  const Clock::time_point meshed = Clock::now();

  // 2. Background mesh.
  const BackgroundMesh mesh = scene.mesh.pattern == MeshPattern::Grid
                                  ? lattice_mesh(geo, domain_group(geo, scene), *scene.mesh.size)
                                  : background_mesh(geo, domain_group(geo, scene));
  Model model;
  model.scene_name = scene.name;
  model.nodes = mesh.nodes;
  model.triangles = mesh.triangles;
  model.neighbours = mesh.neighbours;
  for (const auto& group : geo.groups)
    if (group.dim == 1) {
      // Node sets are stored as mesh/node_sets/NAME in model.h5: a '/' would nest groups.
      if (group.name.empty() || group.name.find('/') != std::string::npos || group.name == ".")
        throw Error(located(scene.geometry, "Physical Curve(\"" + group.name + "\")",
                            "a physical curve needs a non-empty name without '/'"));
      model.node_sets[group.name] = node_set(geo, group, mesh);
    }

  std::vector<Loop> domain_loops;
  // The edges of a triangulation without a neighbour always close into loops.
  const std::vector<std::vector<std::size_t>> boundary_loops = chain_loops(boundary_edges(mesh)).value();
  for (const auto& loop : boundary_loops) {
    Loop points;
    for (std::size_t node : loop) points.push_back(mesh.nodes[node]);
    domain_loops.push_back(std::move(points));
  }
  const Region domain(std::move(domain_loops));
  check_water_table(scene.water, domain, scene);

  // 3. Bodies.
  std::vector<Region> regions;
  regions.reserve(scene.bodies.size());  // SeedBody points into this vector
  std::vector<SeedBody> seed_bodies;
  for (const auto& body : scene.bodies) {
    BodyInfo info;
    info.name = body.name;
    info.material = material_of(scene, body);
    info.fixed = body.fixed;
    info.loops = body_loops(geo, body, scene);
    regions.emplace_back(info.loops);
    check_inside_domain(regions.back(), domain, body, scene);
    seed_bodies.push_back({body.name, &regions.back(), body.particles_per_cell});
    model.bodies.push_back(std::move(info));
  }
  model.materials = scene.materials;

  // 4. Particles.
  Seeds seeds = seed_particles(mesh, seed_bodies, scene.path);
  std::vector<std::size_t> count(scene.bodies.size(), 0);
  std::vector<double> seeded_volume(scene.bodies.size(), 0);
  for (std::size_t p = 0; p < seeds.position.size(); ++p) {
    ++count[seeds.body[p]];
    seeded_volume[seeds.body[p]] += seeds.volume[p];
  }
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (count[b] == 0)
      throw Error(located(scene.path, "bodies." + scene.bodies[b].name,
                          "no particle falls inside the body: the mesh is too coarse for it (lower mesh.size or "
                          "the .geo's element sizes, or raise particles_per_cell)"));

  const double gravity = scene.run.gravity.norm();
  const std::size_t n = seeds.position.size();
  model.position = std::move(seeds.position);
  model.volume = std::move(seeds.volume);
  model.body = std::move(seeds.body);
  model.element = std::move(seeds.element);
  check_table_below_ground(scene.water, model.position, model.volume, scene);
  model.velocity.resize(n);
  model.mass.resize(n);
  model.stress.resize(n);
  for (std::size_t p = 0; p < n; ++p) {
    const Body& body = scene.bodies[model.body[p]];
    const Material& material = model.materials[model.bodies[model.body[p]].material];
    model.mass[p] = density_at(material, scene.water, model.position[p]) * model.volume[p];
    // A fixed body is a support: it never moves, whatever initial velocity it was given.
    model.velocity[p] = body.fixed ? Eigen::Vector2d::Zero() : body.initial_velocity;
    model.stress[p].setZero();
    if (body.initial_stress) {
      const double surface = body.initial_stress->surface.value_or(regions[model.body[p]].highest_y());
      model.stress[p] =
          geostatic_stress(*body.initial_stress, surface, material, gravity, scene.water, model.position[p]);
    }
  }

  // 5. Boundary conditions.
  const std::vector<BoundaryCurve> curves = boundary_curves(geo, mesh, scene);
  const NodeConstraints constraints = resolve_constraints(mesh.nodes, curves, model.triangles);
  model.absorbing = absorbing_nodes(mesh.nodes, curves, model.triangles, scene);
  model.fixed_nodes = constraints.fixed_nodes;
  model.roller_nodes = constraints.roller_nodes;
  model.roller_normals = constraints.roller_normals;
  model.friction_nodes = constraints.friction_nodes;
  model.friction_normals = constraints.friction_normals;
  model.friction_coefficients = constraints.friction_coefficients;

  // 6. Surface loads.
  model.loads = scene.loads;
  if (!scene.loads.empty()) distribute_loads(load_curves(geo, scene), regions, model, scene.path);

  // 7. Settings.
  model.run = scene.run;
  model.contact = scene.contact;
  model.post = scene.post;
  model.water = scene.water;
  model.seismic = scene.seismic;
  model.base_motion = scene.base_motion;
  check_initial_state(model, scene);

  if (report) {
    const Clock::time_point done = Clock::now();
    *report = MeshReport{};
    report->scene = scene.name;
    report->geometry = scene.geometry;
    report->nodes = model.nodes.size();
    report->elements = model.triangles.size();
    report->quadrilaterals = geo.quadrilaterals;
    report->quadrilaterals_cut_in_two = geo.quadrilaterals_cut_in_two;
    report->particles = n;
    report->fixed_nodes = model.fixed_nodes.size();
    report->roller_nodes = model.roller_nodes.size();
    report->friction_nodes = model.friction_nodes.size();
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      BodyReport body{scene.bodies[b].name, count[b], seeded_volume[b], regions[b].area(), 0};
      body.relative_difference = (body.particle_volume - body.polygon_area) / body.polygon_area;
      report->bodies.push_back(body);
    }
    for (std::size_t L = 0; L < model.loads.size(); ++L) {
      LoadReport load{model.loads[L].name, 0, 0};
      for (std::size_t p = 0; p < n; ++p)
        if (model.load[p] == static_cast<int32_t>(L)) ++load.particles, load.length += model.load_length[p];
      report->loads.push_back(load);
    }
    if (scene.mesh.pattern == MeshPattern::Delaunay && !scene.run.evs)
      for (const Body& body : scene.bodies) {
        const int m = scene.material_index(body.material);
        if (!body.fixed && m >= 0 && has_strength(scene.materials[m])) {
          report->locking_material = body.material;
          break;
        }
      }
    report->gmsh_seconds = seconds_between(start, meshed);
    report->seeding_seconds = seconds_between(meshed, done);
    report->seconds = seconds_between(start, done);
  }
  return model;
}

}  // namespace talus::preproc
