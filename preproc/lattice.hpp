// The grid pattern (mesh.pattern = "grid"): the background mesh as a lattice of cells of edge
// about mesh.size over the domain's rectangle, each cut by its diagonals into four triangles
// (crossed, as mesh.pattern = "crossed"). The cells' corners are the first nodes, row by row
// from the lowest left corner, then the cells' centres: the B-spline shape functions
// (run.shape_functions = "bspline", solver/interpolation/lattice.hpp) take their nodes from the
// corners. The lattice does not follow the bodies' outlines, which the particles' seeding does;
// the boundaries must lie on the rectangle's edges (an inclined support is a fixed body).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "preproc/background_mesh.hpp"
#include "preproc/gmsh_geometry.hpp"

namespace talus::preproc {

// The lattice over the rectangle that the domain's surfaces (meshed by gmsh) cover: nx x ny
// cells, nx = round(width / size), the same for the height, so the cells are the rectangle's
// width / nx by its height / ny. Throws talus::Error naming the .geo when the domain is not an
// axis-aligned rectangle.
BackgroundMesh lattice_mesh(const GeoMesh& geo, const PhysicalGroup& domain, double size);

// The lattice's boundary edges that lie on the physical curve's segments, as node-id pairs (what
// the segments of the curve are on a mesh that follows it); none for a curve off the edges.
std::vector<std::array<int32_t, 2>> lattice_segments(const GeoMesh& geo, const PhysicalGroup& curve,
                                                     const BackgroundMesh& lattice);

}  // namespace talus::preproc
