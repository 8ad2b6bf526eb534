#include "preproc/scene_groups.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "preproc/lattice.hpp"

namespace talus::preproc {

std::string point_text(const Eigen::Vector2d& p) {
  std::ostringstream text;
  text << "(" << p.x() << ", " << p.y() << ")";
  return text.str();
}

namespace {

[[noreturn]] void missing_group(const GeoMesh& geo, const std::string& group, const std::string& kind,
                                const std::string& scene_item, const Scene& scene) {
  throw Error(located(geo.path, kind + " \"" + group + "\"",
                      "named by " + scene_item + " in " + scene.path +
                          ", is not a physical group of this .geo; its named physical groups are: " +
                          geo.group_names()));
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

// Mesh segments of a physical curve in background node ids; segments leaving the mesh are dropped.
std::vector<std::array<int32_t, 2>> mesh_segments(const GeoMesh& geo, const PhysicalGroup& curve,
                                                  const BackgroundMesh& mesh) {
  if (mesh.lattice) return lattice_segments(geo, curve, mesh);
  std::vector<std::array<int32_t, 2>> segments;
  for (int entity : curve.entities)
    for (const auto& [a, b] : geo.curve_segments.at(entity)) {
      const int32_t i = mesh.node(a), j = mesh.node(b);
      if (i >= 0 && j >= 0) segments.push_back({i, j});
    }
  return segments;
}

// One edge of an outline, with its bounding box.
struct OutlineEdge {
  Eigen::Vector2d a, b;
  Eigen::AlignedBox2d box;
};

std::vector<OutlineEdge> outline_edges(const std::vector<Loop>& loops) {
  std::vector<OutlineEdge> edges;
  for (const Loop& loop : loops)
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Eigen::Vector2d& a = loop[k];
      const Eigen::Vector2d& b = loop[(k + 1) % loop.size()];
      Eigen::AlignedBox2d box(a);
      box.extend(b);
      edges.push_back({a, b, box});
    }
  return edges;
}

// Where two edges cross: each has its ends on both sides of the other's line, farther from it
// than `tolerance` (edges that meet at an end, touch, or run along each other do not cross; nor
// do an outline and a domain meshed apart that follow one curve to round-off).
std::optional<Eigen::Vector2d> crossing(const OutlineEdge& e, const OutlineEdge& f, double tolerance) {
  auto side = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
    const Eigen::Vector2d d = b - a;
    const double length = d.norm();
    return length > 0 ? (d.x() * (p.y() - a.y()) - d.y() * (p.x() - a.x())) / length : 0.0;
  };
  const double fa = side(e.a, e.b, f.a), fb = side(e.a, e.b, f.b);
  const double ea = side(f.a, f.b, e.a), eb = side(f.a, f.b, e.b);
  const bool apart = std::min(std::abs(fa), std::abs(fb)) > tolerance && std::min(std::abs(ea), std::abs(eb)) > tolerance;
  if (!apart || fa * fb >= 0 || ea * eb >= 0) return std::nullopt;
  return e.a + (e.b - e.a) * (ea / (ea - eb));
}

// The first crossing of an edge of `first` with an edge of `second` (with a list and itself:
// of two of its edges), scanning in order of the edges' lowest x.
std::optional<Eigen::Vector2d> first_crossing(const std::vector<OutlineEdge>& first, const std::vector<OutlineEdge>& second,
                                              double tolerance) {
  std::vector<const OutlineEdge*> sorted;
  for (const OutlineEdge& f : second) sorted.push_back(&f);
  std::sort(sorted.begin(), sorted.end(),
            [](const OutlineEdge* x, const OutlineEdge* y) { return x->box.min().x() < y->box.min().x(); });
  for (const OutlineEdge& e : first)
    for (const OutlineEdge* f : sorted) {
      if (f->box.min().x() > e.box.max().x()) break;  // this one and all after it lie to the right
      if (f == &e || !e.box.intersects(f->box)) continue;
      if (const auto point = crossing(e, *f, tolerance)) return point;
    }
  return std::nullopt;
}

}  // namespace

const PhysicalGroup& domain_group(const GeoMesh& geo, const Scene& scene) {
  const PhysicalGroup* group = geo.find(scene.mesh.domain, 2);
  if (!group) missing_group(geo, scene.mesh.domain, "physical surface", "mesh.domain", scene);
  return *group;
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

void check_inside_domain(const Region& body_region, const Region& domain, const Body& body, const Scene& scene) {
  const double tolerance = 1e-6 * domain.bounds().diagonal().norm();
  const std::string item = "bodies." + body.name;
  const std::string where = "physical surface \"" + scene.mesh.domain + "\" of " + scene.geometry;
  for (const auto& loop : body_region.loops())
    for (const auto& v : loop)
      if (!domain.covers(v) && domain.distance_to_boundary(v) > tolerance)
        throw Error(located(scene.path, item,
                            "lies outside the domain (" + where + "): its outline point " + point_text(v) +
                                " is not on the background mesh"));
  const std::vector<OutlineEdge> edges = outline_edges(body_region.loops());
  auto reaches_out = [&](const Eigen::Vector2d& point) {
    throw Error(located(scene.path, item,
                        "the outline of the body crosses the edge of the domain (" + where + ") at " +
                            point_text(point) +
                            ": the body reaches into a hole of the domain or out of it, where no mesh is"));
  };
  // An edge that crosses the domain's edge through one of its vertices: its middle is off the mesh.
  for (const OutlineEdge& e : edges) {
    const Eigen::Vector2d middle = 0.5 * (e.a + e.b);
    if (!domain.covers(middle) && domain.distance_to_boundary(middle) > tolerance) reaches_out(middle);
  }
  if (const auto crossing = first_crossing(edges, edges, tolerance))
    throw Error(located(scene.path, item,
                        "the outline of the body crosses itself at " + point_text(*crossing) +
                            " (a bow-tie outline bounds no region: draw it as loops that do not cross)"));
  if (const auto crossing = first_crossing(edges, outline_edges(domain.loops()), tolerance)) reaches_out(*crossing);
}

std::vector<int32_t> node_set(const GeoMesh& geo, const PhysicalGroup& curve, const BackgroundMesh& mesh) {
  std::set<int32_t> nodes;
  if (mesh.lattice) {
    for (const auto& segment : lattice_segments(geo, curve, mesh)) nodes.insert(segment.begin(), segment.end());
    return {nodes.begin(), nodes.end()};
  }
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

}  // namespace talus::preproc
