#include "preproc/gmsh_geometry.hpp"

#include <gmsh.h>

#include <Eigen/LU>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <limits>
#include <new>

#include "common/error.hpp"
#include "preproc/geo_guard.hpp"
#include "preproc/gmsh_session.hpp"

namespace talus::preproc {
namespace {

constexpr int kLineType = 1;      // gmsh element type: 2-node line
constexpr int kTriangleType = 2;  // gmsh element type: 3-node triangle
constexpr int kQuadrangleType = 3;  // gmsh element type: 4-node quadrangle

// gmsh 4.8 throws the error text as a std::string; later versions throw std::runtime_error.
template <class Action>
void with_gmsh_errors(const std::string& path, const std::string& doing, Action action) {
  std::string message;
  try {
    action();
  } catch (const std::bad_alloc&) {
    throw;  // out of memory, not a problem of the .geo (talus exits with status 3)
  } catch (const std::string& text) {
    message = text;
  } catch (const std::exception& e) {
    message = e.what();
  }
  const std::string logged = GmshSession::logged_errors();
  if (message.empty() && logged.empty()) return;
  throw Error(located(path, "", "gmsh could not " + doing + ": " + (message.empty() ? logged : message)));
}

void override_sizes(double size) {
  gmsh::vectorpair points;
  gmsh::model::getEntities(points, 0);
  gmsh::model::mesh::setSize(points, size);
  // Sizes also come from fields and curvature; pinning both bounds makes `size` win everywhere.
  gmsh::option::setNumber("Mesh.MeshSizeMin", size);
  gmsh::option::setNumber("Mesh.MeshSizeMax", size);
}

// Without [mesh] size the .geo's own sizes are used: a largest size of 0 or less leaves gmsh
// no size at all (it logs an error for every point of every curve).
void check_size_options(const std::string& geo_path) {
  double largest = 1;
  gmsh::option::getNumber("Mesh.MeshSizeMax", largest);
  if (largest > 0) return;
  std::ostringstream message;
  message << "got " << largest << " (also set as Mesh.CharacteristicLengthMax): the largest element size must be "
          << "positive; fix the .geo, or set [mesh] size in the scene";
  throw Error(located(geo_path, "Mesh.MeshSizeMax", message.str()));
}

void copy_nodes(GeoMesh& mesh) {
  std::vector<std::size_t> tags;
  std::vector<double> xyz, parametric;
  gmsh::model::mesh::getNodes(tags, xyz, parametric, -1, -1, false, false);
  NodeTag largest = 0;
  for (NodeTag tag : tags) largest = std::max(largest, tag);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  mesh.node_position.assign(largest + 1, Eigen::Vector2d(nan, nan));
  for (std::size_t i = 0; i < tags.size(); ++i) mesh.node_position[tags[i]] = {xyz[3 * i], xyz[3 * i + 1]};
}

// Appends the crossed triangles of quadrilateral q (its corners in order around it): the four
// triangles from each edge to a new node where the diagonals cross. That point, not the
// centroid, is what makes the four triangles' volume changes linearly dependent (Nagtegaal,
// Parks and Rice 1974), so that the quadrilateral constrains the flow's volume once, not four
// times. A quadrilateral that is not convex (its diagonals do not cross inside it) is cut in two
// along the diagonal that keeps both halves positive, and counted.
void cross_quadrilateral(const std::array<NodeTag, 4>& q, GeoMesh& mesh, std::vector<TriangleTags>& triangles) {
  Eigen::Vector2d corner[4];
  for (int k = 0; k < 4; ++k) corner[k] = mesh.node_position[q[k]];
  // corner0 + s (corner2 - corner0) = corner1 + t (corner3 - corner1)
  Eigen::Matrix2d M;
  M.col(0) = corner[2] - corner[0];
  M.col(1) = corner[1] - corner[3];
  const Eigen::Vector2d st = M.fullPivLu().solve(corner[1] - corner[0]);
  constexpr double kMargin = 0.02;  // the crossing at least 2 % of a diagonal from its ends
  const bool convex = std::abs(M.determinant()) > 0 && st.minCoeff() > kMargin && st.maxCoeff() < 1 - kMargin;
  if (convex) {
    const NodeTag centre = mesh.node_position.size();
    mesh.node_position.push_back(corner[0] + st[0] * (corner[2] - corner[0]));
    for (int k = 0; k < 4; ++k) triangles.push_back({q[k], q[(k + 1) % 4], centre});
    return;
  }
  auto twice_area = [&](int a, int b, int c) {
    const Eigen::Vector2d u = corner[b] - corner[a], v = corner[c] - corner[a];
    return u.x() * v.y() - u.y() * v.x();
  };
  // The diagonal 0-2 keeps both halves on the quadrilateral's side if they turn the same way.
  const double sign = twice_area(0, 1, 2) + twice_area(0, 2, 3) + twice_area(1, 2, 3) + twice_area(1, 3, 0);
  if (twice_area(0, 1, 2) * sign > 0 && twice_area(0, 2, 3) * sign > 0) {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  } else if (twice_area(1, 2, 3) * sign > 0 && twice_area(1, 3, 0) * sign > 0) {
    triangles.push_back({q[1], q[2], q[3]});
    triangles.push_back({q[1], q[3], q[0]});
  } else {
    std::ostringstream where;
    where << "(" << corner[0].x() << ", " << corner[0].y() << ") m";
    throw Error(located(mesh.path, "", "gmsh made a degenerate quadrilateral at " + where.str() +
                                           ": it cannot be cut into triangles (try another mesh.size)"));
  }
  ++mesh.quadrilaterals_cut_in_two;
}

void copy_elements(GeoMesh& mesh) {
  // getElementsByType takes non-empty output vectors as preallocated (for its multi-task
  // mode) and then insists on their size: hand it empty ones every time.
  std::vector<std::size_t> element_tags, node_tags;
  gmsh::vectorpair curves, surfaces;
  gmsh::model::getEntities(curves, 1);
  for (const auto& [dim, tag] : curves) {
    element_tags.clear();
    node_tags.clear();
    gmsh::model::mesh::getElementsByType(kLineType, element_tags, node_tags, tag);
    auto& segments = mesh.curve_segments[tag];
    for (std::size_t i = 0; i + 1 < node_tags.size(); i += 2) segments.push_back({node_tags[i], node_tags[i + 1]});
  }
  gmsh::model::getEntities(surfaces, 2);
  for (const auto& [dim, tag] : surfaces) {
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, 2, tag);
    for (int type : types)
      if (type != kTriangleType && type != kQuadrangleType) mesh.surfaces_with_other_elements.insert(tag);
    element_tags.clear();
    node_tags.clear();
    gmsh::model::mesh::getElementsByType(kTriangleType, element_tags, node_tags, tag);
    auto& triangles = mesh.surface_triangles[tag];
    for (std::size_t i = 0; i + 2 < node_tags.size(); i += 3)
      triangles.push_back({node_tags[i], node_tags[i + 1], node_tags[i + 2]});
    // Quadrilaterals: only the crossed pattern asks gmsh for them (a .geo's own Recombine is
    // turned off otherwise).
    element_tags.clear();
    node_tags.clear();
    gmsh::model::mesh::getElementsByType(kQuadrangleType, element_tags, node_tags, tag);
    for (std::size_t i = 0; i + 3 < node_tags.size(); i += 4) {
      cross_quadrilateral({node_tags[i], node_tags[i + 1], node_tags[i + 2], node_tags[i + 3]}, mesh, triangles);
      ++mesh.quadrilaterals;
    }
  }
}

void copy_groups(GeoMesh& mesh) {
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  for (const auto& [dim, tag] : groups) {
    if (dim != 1 && dim != 2) continue;
    PhysicalGroup group;
    group.dim = dim;
    group.tag = tag;
    gmsh::model::getPhysicalName(dim, tag, group.name);
    if (group.name.empty()) continue;  // a scene refers to groups by name only
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, group.entities);
    if (dim == 2) {
      gmsh::vectorpair surfaces, boundary;
      for (int surface : group.entities) surfaces.emplace_back(2, surface);
      gmsh::model::getBoundary(surfaces, boundary, /*combined=*/true, /*oriented=*/false);
      for (const auto& [curve_dim, curve] : boundary) group.boundary_curves.push_back(std::abs(curve));
    }
    mesh.groups.push_back(group);
  }
}

}  // namespace

const PhysicalGroup* GeoMesh::find(const std::string& name, int dim) const {
  for (const auto& group : groups)
    if (group.name == name && group.dim == dim) return &group;
  return nullptr;
}

std::string GeoMesh::group_names() const {
  if (groups.empty()) return "(none)";
  std::string names;
  for (const auto& group : groups)
    names += (names.empty() ? "" : ", ") + group.name + (group.dim == 2 ? " (surface)" : " (curve)");
  return names;
}

namespace {

// The number after "key": in a ONELAB entry's JSON text, if there is one.
std::optional<double> json_number(const std::string& entry, const std::string& key) {
  const std::string tag = "\"" + key + "\":";
  const std::size_t at = entry.find(tag);
  if (at == std::string::npos) return std::nullopt;
  try {
    return std::stod(entry.substr(at + tag.size()));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::string shown(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

void open_geometry(const std::string& geo_path, const std::map<std::string, double>& parameters) {
  // Defaults that the .geo may change (it is read after these are set).
  gmsh::option::setNumber("Mesh.Algorithm", 6);  // frontal-Delaunay
  for (const auto& [name, value] : parameters) gmsh::onelab::setNumber("Parameters/" + name, {value});
  with_gmsh_errors(geo_path, "read the geometry", [&] { gmsh::open(geo_path); });
  for (const auto& [name, value] : parameters) {
    // A parameter that a DefineConstant of the .geo read lists gmsh among its clients.
    std::string entry;
    gmsh::onelab::get(entry, "Parameters/" + name);
    const std::string item = "mesh.parameters." + name;
    if (entry.find("\"clients\"") == std::string::npos)
      throw Error(located(geo_path, "", item + ": the geometry declares no such parameter " +
                                            "(expected DefineConstant[ " + name + " = {VALUE, Name \"Parameters/" +
                                            name + "\"} ])"));
    // gmsh keeps a value outside the declared Min and Max; the .geo's author meant them as bounds.
    const auto low = json_number(entry, "min");
    const auto high = json_number(entry, "max");
    if ((low && value < *low) || (high && value > *high))
      throw Error(located(geo_path, "", item + ": got " + shown(value) + ", expected a value in [" +
                                            (low ? shown(*low) : "-inf") + ", " + (high ? shown(*high) : "inf") +
                                            "] (the Min and Max of its DefineConstant)"));
  }
}

GeoMesh mesh_geometry(const std::string& geo_path, const std::optional<double>& size, const std::string& named_by,
                      const std::map<std::string, double>& parameters, bool crossed) {
  namespace fs = std::filesystem;
  // gmsh::open of a missing file logs a warning and yields an empty model: check first.
  std::error_code error;
  if (!fs::is_regular_file(geo_path, error))
    throw Error(located(geo_path, "", "no such geometry file" + (named_by.empty() ? "" : " (named by " + named_by + ")")));
  check_geo_program(geo_path);  // gmsh runs the .geo as it parses it: refuse commands first

  GmshSession session;
  open_geometry(geo_path, parameters);
  // What the solver requires, whatever the .geo says: linear triangles only, or for the crossed
  // pattern linear quadrilaterals that copy_elements cuts into triangles. gmsh makes those by
  // recombining a triangle mesh of twice the size into quadrilaterals (Blossom) and subdividing
  // each into four, so every element is a quadrilateral of about the size asked for.
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  gmsh::option::setNumber("Mesh.RecombineAll", crossed ? 1 : 0);
  gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", crossed ? 1 : 0);
  if (crossed) {
    gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1);  // Blossom
    if (!size) {
      double factor = 1;
      gmsh::option::getNumber("Mesh.MeshSizeFactor", factor);
      gmsh::option::setNumber("Mesh.MeshSizeFactor", 2 * factor);
    }
  }
  if (size) with_gmsh_errors(geo_path, "set the element size", [&] { override_sizes(crossed ? 2 * *size : *size); });
  else check_size_options(geo_path);
  with_gmsh_errors(geo_path, "mesh the geometry", [&] { GmshSession::generate(2); });

  GeoMesh mesh;
  mesh.path = geo_path;
  with_gmsh_errors(geo_path, "return the mesh", [&] {
    copy_nodes(mesh);
    copy_elements(mesh);
    copy_groups(mesh);
  });
  return mesh;
}

}  // namespace talus::preproc
