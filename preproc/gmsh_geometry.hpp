// Reading and meshing a .geo through the gmsh C++ API, and copying out of gmsh everything the
// preprocessor needs (nodes, 1D and 2D elements per entity, named physical groups), so that
// the rest of the stage works on plain data and gmsh's global state lives only here.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace talus::preproc {

using NodeTag = std::size_t;  // gmsh's node tag (strictly positive, not necessarily compact)
using Segment = std::array<NodeTag, 2>;
using TriangleTags = std::array<NodeTag, 3>;

struct PhysicalGroup {
  std::string name;
  int dim = 0;  // 1: physical curve, 2: physical surface
  int tag = 0;
  std::vector<int> entities;  // curves or surfaces of the group
  // For a physical surface: the curves of the combined boundary of its surfaces (the curves
  // shared by two of its surfaces cancel). Empty for a physical curve.
  std::vector<int> boundary_curves;
};

struct GeoMesh {
  std::string path;
  std::vector<Eigen::Vector2d> node_position;  // indexed by NodeTag (unused tags hold NaN)
  std::map<int, std::vector<Segment>> curve_segments;        // by curve tag
  std::map<int, std::vector<TriangleTags>> surface_triangles;  // by surface tag
  std::set<int> surfaces_with_other_elements;  // surfaces meshed with quadrangles or worse
  std::vector<PhysicalGroup> groups;           // named physical groups of dimension 1 and 2
  // The crossed pattern: quadrilaterals gmsh made, and those of them cut in two instead of four
  // because they were not convex.
  std::size_t quadrilaterals = 0, quadrilaterals_cut_in_two = 0;

  // The named group of dimension `dim`, or nullptr.
  const PhysicalGroup* find(const std::string& name, int dim) const;
  // "a (surface), b (curve), ...": for error messages.
  std::string group_names() const;
};

// In an open gmsh session: reads `geo_path` with the ONELAB numbers "Parameters/NAME" of
// `parameters` set (after Talus's meshing defaults, which the .geo may change). Throws
// talus::Error for a parameter the .geo does not declare or a value outside its Min and Max.
void open_geometry(const std::string& geo_path, const std::map<std::string, double>& parameters);

// Opens `geo_path` with the ONELAB numbers "Parameters/NAME" of `parameters` set, overrides its
// element sizes with `size` when given, and generates a 2D mesh of linear triangles (`crossed`:
// quadrilaterals of that size, each cut by its diagonals into four triangles). Throws
// talus::Error naming the file, with gmsh's own message when gmsh cannot read or mesh it, and
// for a parameter the .geo does not declare. `named_by` says where the path came from, for the
// message about a missing file.
GeoMesh mesh_geometry(const std::string& geo_path, const std::optional<double>& size,
                      const std::string& named_by = "", const std::map<std::string, double>& parameters = {},
                      bool crossed = false);

}  // namespace talus::preproc
