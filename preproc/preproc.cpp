// build_model, step by step:
//   1. gmsh reads and meshes the .geo (gmsh_geometry.cpp);
//   2. the domain's triangles become the background mesh (background_mesh.cpp);
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
#include "preproc/boundary_conditions.hpp"
#include "preproc/estimate.hpp"
#include "preproc/gmsh_geometry.hpp"
#include "preproc/polygon.hpp"
#include "preproc/seeding.hpp"
#include "preproc/surface_loads.hpp"

namespace talus::preproc {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

std::string point_text(const Eigen::Vector2d& p) {
  std::ostringstream text;
  text << "(" << p.x() << ", " << p.y() << ")";
  return text.str();
}

[[noreturn]] void missing_group(const GeoMesh& geo, const std::string& group, const std::string& kind,
                                const std::string& scene_item, const Scene& scene) {
  throw Error(located(geo.path, kind + " \"" + group + "\"",
                      "named by " + scene_item + " in " + scene.path +
                          ", is not a physical group of this .geo; its named physical groups are: " +
                          geo.group_names()));
}

const PhysicalGroup& domain_group(const GeoMesh& geo, const Scene& scene) {
  const PhysicalGroup* group = geo.find(scene.mesh.domain, 2);
  if (!group) missing_group(geo, scene.mesh.domain, "physical surface", "mesh.domain", scene);
  return *group;
}

// The physical group of a body: a physical surface, or a closed physical curve (a surface wins
// when the .geo has both under one name).
const PhysicalGroup& body_group(const GeoMesh& geo, const Body& body, const Scene& scene) {
  const PhysicalGroup* group = geo.find(body.group, 2);
  if (!group) group = geo.find(body.group, 1);
  if (!group) missing_group(geo, body.group, "physical surface or closed curve", "bodies." + body.name, scene);
  return *group;
}

// The curves of a body's outline: the combined boundary of its surface, or its closed curve's.
const std::vector<int>& outline_curves(const PhysicalGroup& group) {
  return group.dim == 2 ? group.boundary_curves : group.entities;
}

// Outline segments of a body.
std::vector<Segment> body_outline(const GeoMesh& geo, const Body& body, const Scene& scene,
                                  const PhysicalGroup** found) {
  const PhysicalGroup* group = &body_group(geo, body, scene);
  *found = group;
  std::vector<Segment> segments;
  for (int curve : outline_curves(*group)) {
    const auto& curve_segments = geo.curve_segments.at(curve);
    segments.insert(segments.end(), curve_segments.begin(), curve_segments.end());
  }
  return segments;
}

std::vector<Loop> body_loops(const GeoMesh& geo, const Body& body, const Scene& scene) {
  const PhysicalGroup* group = nullptr;
  const std::vector<Segment> segments = body_outline(geo, body, scene, &group);
  std::size_t open_end = 0;
  const auto loops = chain_loops(segments, &open_end);
  const std::string item = std::string(group->dim == 2 ? "physical surface" : "physical curve") + " \"" +
                           group->name + "\"";
  if (!loops)
    throw Error(located(geo.path, item,
                        "the outline of body '" + body.name + "' is not closed (open end at " +
                            point_text(geo.node_position[open_end]) + ")"));
  if (loops->empty()) throw Error(located(geo.path, item, "body '" + body.name + "' has an empty outline"));
  std::vector<Loop> outline;
  for (const auto& loop : *loops) {
    Loop points;
    for (NodeTag tag : loop) points.push_back(geo.node_position[tag]);
    outline.push_back(std::move(points));
  }
  return outline;
}

// Every vertex of the body's outline must be inside or on the background mesh (to a tolerance
// relative to the domain's size, for outlines meshed apart from the domain).
void check_inside_domain(const Region& body_region, const Region& domain, const Body& body, const Scene& scene) {
  const double tolerance = 1e-6 * domain.bounds().diagonal().norm();
  for (const auto& loop : body_region.loops())
    for (const auto& v : loop)
      if (!domain.covers(v) && domain.distance_to_boundary(v) > tolerance)
        throw Error(located(scene.path, "bodies." + body.name,
                            "lies outside the domain (physical surface \"" + scene.mesh.domain + "\" of " +
                                scene.geometry + "): its outline point " + point_text(v) +
                                " is not on the background mesh"));
}

// Mesh segments of a physical curve in background node ids; segments leaving the mesh are dropped.
std::vector<std::array<int32_t, 2>> mesh_segments(const GeoMesh& geo, const PhysicalGroup& curve,
                                                  const BackgroundMesh& mesh) {
  std::vector<std::array<int32_t, 2>> segments;
  for (int entity : curve.entities)
    for (const auto& [a, b] : geo.curve_segments.at(entity)) {
      const int32_t i = mesh.node(a), j = mesh.node(b);
      if (i >= 0 && j >= 0) segments.push_back({i, j});
    }
  return segments;
}

std::vector<int32_t> node_set(const GeoMesh& geo, const PhysicalGroup& curve, const BackgroundMesh& mesh) {
  std::set<int32_t> nodes;
  for (int entity : curve.entities)
    for (const auto& segment : geo.curve_segments.at(entity))
      for (NodeTag tag : segment)
        if (mesh.node(tag) >= 0) nodes.insert(mesh.node(tag));
  return {nodes.begin(), nodes.end()};
}

std::vector<BoundaryCurve> boundary_curves(const GeoMesh& geo, const BackgroundMesh& mesh, const Scene& scene) {
  std::vector<BoundaryCurve> curves;
  for (const auto& boundary : scene.boundaries) {
    const PhysicalGroup* group = geo.find(boundary.group, 1);
    if (!group && geo.find(boundary.group, 2))
      throw Error(located(geo.path, "physical surface \"" + boundary.group + "\"",
                          "named by boundaries." + boundary.name + " in " + scene.path +
                              ", is a surface; a boundary needs a physical curve"));
    if (!group) missing_group(geo, boundary.group, "physical curve", "boundaries." + boundary.name, scene);
    BoundaryCurve curve{boundary.name, boundary.type, boundary.normal, mesh_segments(geo, *group, mesh),
                        boundary.friction};
    if (curve.segments.empty())
      throw Error(located(geo.path, "physical curve \"" + boundary.group + "\"",
                          "named by boundaries." + boundary.name + " in " + scene.path +
                              ", has no edge on the background mesh (is it outside the domain?)"));
    curves.push_back(std::move(curve));
  }
  return curves;
}

// Each load's physical curve as segments, each on the outline of the one body that holds its
// curve (a load may run along several bodies, never between two or along a fixed one).
std::vector<LoadCurve> load_curves(const GeoMesh& geo, const Scene& scene) {
  std::vector<std::vector<int>> outlines;
  for (const auto& body : scene.bodies) outlines.push_back(outline_curves(body_group(geo, body, scene)));
  std::vector<LoadCurve> curves;
  for (const auto& load : scene.loads) {
    const std::string item = "loads." + load.name;
    const PhysicalGroup* group = geo.find(load.group, 1);
    if (!group && geo.find(load.group, 2))
      throw Error(located(geo.path, "physical surface \"" + load.group + "\"",
                          "named by " + item + " in " + scene.path + ", is a surface; a load needs a physical curve"));
    if (!group) missing_group(geo, load.group, "physical curve", item, scene);
    const std::string where = "physical curve \"" + load.group + "\" of " + scene.geometry;
    LoadCurve curve;
    curve.name = load.name;
    for (int entity : group->entities) {
      std::vector<int32_t> holders;
      for (std::size_t b = 0; b < outlines.size(); ++b)
        if (std::find(outlines[b].begin(), outlines[b].end(), entity) != outlines[b].end())
          holders.push_back(static_cast<int32_t>(b));
      if (holders.empty())
        throw Error(located(scene.path, item,
                            where + " is not on any body's outline (its curve " + std::to_string(entity) +
                                " bounds no body): a load acts on a body's edge"));
      if (holders.size() > 1)
        throw Error(located(scene.path, item,
                            where + " lies between bodies '" + scene.bodies[holders[0]].name + "' and '" +
                                scene.bodies[holders[1]].name + "': a load acts on a body's free edge"));
      if (scene.bodies[holders[0]].fixed)
        throw Error(located(scene.path, item,
                            where + " is on the outline of body '" + scene.bodies[holders[0]].name +
                                "', which is fixed: a load on a body that never moves does nothing"));
      for (const auto& [a, b] : geo.curve_segments.at(entity))
        curve.segments.push_back({geo.node_position[a], geo.node_position[b], holders[0]});
    }
    if (curve.segments.empty())
      throw Error(located(scene.path, item, where + " has no segments"));
    curves.push_back(std::move(curve));
  }
  return curves;
}

int material_of(const Scene& scene, const Body& body) {
  for (std::size_t m = 0; m < scene.materials.size(); ++m)
    if (scene.materials[m].name == body.material) return static_cast<int>(m);
  throw Error(located(scene.path, "bodies." + body.name + ".material", "no material named '" + body.material + "'"));
}

// Geostatic stress of horizontally layered ground, tension positive: the weight of the
// material above, sigma_yy = -rho |g| (surface - y), and sigma_xx = sigma_zz = k0 sigma_yy.
// Above the surface there is no overburden. With a water table at height h (at the point's x,
// capped at the surface) the ground below it weighs rho_sat, the pore pressure is
// u = gamma_w (h - y) below it, and k0 acts on the effective stress:
//   sigma'_yy = sigma_yy + u, sigma'_xx = sigma'_zz = k0 sigma'_yy, sigma = sigma' - u I.
Eigen::Vector4d geostatic_stress(const InitialStress& initial, double surface, const Material& material,
                                 double gravity, const WaterSettings& water, const Eigen::Vector2d& point) {
  const double y = point.y();
  if (!water.enabled()) {
    const double sigma_yy = -material.density * gravity * std::max(0.0, surface - y);
    return {initial.k0 * sigma_yy, sigma_yy, initial.k0 * sigma_yy, 0};
  }
  const double table = std::min(water.height(point.x()), surface);
  const double saturated = material.saturated_density > 0 ? material.saturated_density : material.density;
  const double dry_depth = std::max(0.0, surface - std::max(y, table));
  const double wet_depth = std::max(0.0, table - y);
  const double sigma_yy = -gravity * (material.density * dry_depth + saturated * wet_depth);
  const double u = water.pore_pressure(point);
  const double effective_yy = sigma_yy + u;
  return {initial.k0 * effective_yy - u, sigma_yy, initial.k0 * effective_yy - u, 0};
}

// The density of a particle: saturated below the water table (at t = 0), dry above it.
double density_at(const Material& material, const WaterSettings& water, const Eigen::Vector2d& point) {
  if (water.enabled() && material.saturated_density > 0 && point.y() < water.height(point.x()))
    return material.saturated_density;
  return material.density;
}

// A water table must reach over the domain: its x range overlaps the domain's, and it is not
// wholly below it even at its highest rise.
void check_water_table(const WaterSettings& water, const Region& domain, const Scene& scene) {
  if (!water.enabled()) return;
  const Eigen::AlignedBox2d box = domain.bounds();
  double highest = -INFINITY, rise = 0;  // the table's highest point, and its highest rise
  for (const auto& point : water.table) highest = std::max(highest, point.y());
  for (const auto& point : water.rise) rise = std::max(rise, point.y());
  if (water.table.back().x() <= box.min().x() || water.table.front().x() >= box.max().x() ||
      highest + rise <= box.min().y()) {
    std::ostringstream message;
    message << "the table (x from " << water.table.front().x() << " to " << water.table.back().x() << " m, highest y "
            << highest << " m) lies outside the domain (x from " << box.min().x() << " to " << box.max().x()
            << " m, y from " << box.min().y() << " to " << box.max().y() << " m)";
    throw Error(located(scene.path, "water.table", message.str()));
  }
}

// Water standing above the ground is not modelled: its weight on the surface is not applied,
// so soil under it would carry a pore pressure with no load above it (tensile effective stress,
// no strength). The table, at its highest rise, must therefore stay at or below the ground
// wherever there are bodies: the top of the highest particle (y + sqrt(V)/2) of each vertical
// strip two particle spacings wide, within one spacing. Strips without particles are not
// checked (the table may run over empty parts of the domain).
void check_table_below_ground(const WaterSettings& water, const std::vector<Eigen::Vector2d>& position,
                              const std::vector<double>& volume, const Scene& scene) {
  if (!water.enabled() || position.empty()) return;
  // The table is highest at t = 0 or at one of the rise's points (it is linear between them).
  double highest_time = 0, mean_volume = 0, lowest_x = INFINITY;
  for (const auto& point : water.rise)
    if (water.rise_at(point.x()) > water.rise_at(highest_time)) highest_time = point.x();
  const bool risen = !water.rise.empty() && water.rise_at(highest_time) > 0;
  for (std::size_t p = 0; p < position.size(); ++p) {
    mean_volume += volume[p] / static_cast<double>(position.size());
    lowest_x = std::min(lowest_x, position[p].x());
  }
  const double strip = 2 * std::sqrt(mean_volume);
  std::vector<std::ptrdiff_t> top;  // per strip: the particle whose top is highest, or -1
  auto top_of = [&](std::size_t p) { return position[p].y() + 0.5 * std::sqrt(volume[p]); };
  for (std::size_t p = 0; p < position.size(); ++p) {
    const auto k = static_cast<std::size_t>((position[p].x() - lowest_x) / strip);
    if (k >= top.size()) top.resize(k + 1, -1);
    if (top[k] < 0 || top_of(p) > top_of(static_cast<std::size_t>(top[k]))) top[k] = static_cast<std::ptrdiff_t>(p);
  }
  for (const std::ptrdiff_t t : top) {
    if (t < 0) continue;
    const auto p = static_cast<std::size_t>(t);
    const double ground = top_of(p), table = water.height(position[p].x(), highest_time);
    if (table - ground > std::sqrt(volume[p])) {
      std::ostringstream message;
      message << std::setprecision(4) << "at x = " << position[p].x() << " m the table" << (risen ? " at its highest rise" : "")
              << " (y = " << table << " m) is " << table - ground << " m above the ground (y = " << ground
              << " m): water standing above the ground is not modelled (its weight on the surface is not applied); "
                 "let the table follow the ground surface where the water reaches it";
      throw Error(located(scene.path, "water.table", message.str()));
    }
  }
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
  const BackgroundMesh mesh = background_mesh(geo, domain_group(geo, scene));
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
  const NodeConstraints constraints =
      resolve_constraints(mesh.nodes, boundary_curves(geo, mesh, scene), model.triangles);
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

void print_report(const MeshReport& report, std::ostream& out) {
  const auto flags = out.flags();
  const auto precision = out.precision();
  out << "mesh " << report.scene << " (" << report.geometry << ")\n";
  out << "  background mesh: " << report.nodes << " nodes, " << report.elements << " triangles";
  if (report.quadrilaterals > 0) {
    out << " (crossed: " << report.quadrilaterals << " quadrilaterals";
    if (report.quadrilaterals_cut_in_two > 0)
      out << ", " << report.quadrilaterals_cut_in_two << " of them not convex and cut in two";
    out << ")";
  }
  out << "\n";
  out << "  boundary: " << report.fixed_nodes << " fixed nodes, " << report.roller_nodes << " roller nodes";
  if (report.friction_nodes > 0) out << ", " << report.friction_nodes << " friction nodes";
  out << "\n";
  std::size_t width = 4;
  for (const auto& body : report.bodies) width = std::max(width, body.name.size());
  for (const auto& body : report.bodies) {
    out << "  body " << std::left << std::setw(static_cast<int>(width)) << body.name << std::right << " "
        << std::setw(9) << body.particles << " particles, volume " << std::setprecision(6) << body.particle_volume
        << " m^2 vs polygon " << body.polygon_area << " m^2 (" << std::showpos << std::scientific
        << std::setprecision(1) << 100 * body.relative_difference << std::noshowpos << " %)\n";
    out.flags(flags);
  }
  for (const auto& load : report.loads)
    out << "  load " << load.name << ": carried by " << load.particles << " particles along " << std::setprecision(6)
        << load.length << " m\n";
  out << "  particles: " << report.particles << "\n";
  if (!report.locking_material.empty())
    out << "  note: Mohr-Coulomb material '" << report.locking_material
        << "' on Delaunay triangles with EVS off: they lock in plastic flow at\n"
           "        constant volume, which stiffens the failure and shortens the runout. For a runout,\n"
           "        set [mesh] pattern = \"crossed\" (docs/slope.md, \"Crossed triangles\").\n";
  out << std::fixed << std::setprecision(3) << "  time: gmsh " << report.gmsh_seconds << " s, seeding "
      << report.seeding_seconds << " s, total " << report.seconds << " s\n";
  out.flags(flags);
  out.precision(precision);
}

}  // namespace talus::preproc
