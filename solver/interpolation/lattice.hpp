// The lattice of the grid pattern (mesh.pattern = "grid", preproc/lattice.cpp): square (or
// rectangular) cells over the domain's rectangle, each cut by its diagonals into four triangles,
// whose corners are the mesh's first nodes, row by row. The B-spline family takes its nodes from
// it. A particle within half a cell of the domain's edge reaches one node beyond it, so the
// family adds a layer of ghost nodes around the lattice (after the mesh's nodes; they belong to
// no triangle) and mirrors their velocities across the fixed and roller edges (boundary.hpp,
// Mirror).
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "solver/boundary/boundary.hpp"
#include "solver/interpolation/mesh.hpp"

namespace talus::solver {

struct Lattice {
  Vec2 origin = Vec2::Zero();   // m, the corner (0, 0)
  Vec2 spacing = Vec2::Zero();  // m, cell width and height
  int nx = 0, ny = 0;           // cells
  // Node ids of the corners (i, j), i in [-1, nx + 1], j in [-1, ny + 1]: the mesh's for the
  // lattice itself, the ghosts' (from the mesh's node count on) for the layer around it.
  std::vector<int32_t> node_id;

  int32_t id(int i, int j) const {
    return node_id[static_cast<std::size_t>(j + 1) * static_cast<std::size_t>(nx + 3) + static_cast<std::size_t>(i + 1)];
  }
  bool valid() const { return nx > 0 && ny > 0; }
};

// The lattice whose corners are the mesh's first (nx + 1)(ny + 1) nodes, row by row from the
// lowest left corner, covering every node of the mesh; nullopt when the mesh is not so made.
std::optional<Lattice> find_lattice(const Mesh& mesh);

// Appends the ghost layer around `lattice` to mesh.nodes, numbers it in lattice.node_id, and
// gives `constraints` (sized for the mesh's nodes before) the ghosts' mirrors: each ghost's
// partner is the node as far inside the edge as the ghost is outside it; across a fixed edge
// the velocity is reversed, across a roller or friction edge its normal component (a corner
// ghost is reflected across both edges). The edge's kind is that of its node nearest the
// ghost but one in from a corner (so that a fixed corner node does not fix a roller edge).
void add_ghost_layer(Lattice& lattice, Mesh& mesh, Constraints& constraints);

// The lattice nodes (ghosts included) that a particle in element e can reach with a 3 x 3
// B-spline stencil: the 4 x 4 block around the lattice cell that holds the element.
void reachable_nodes(const Lattice& lattice, const Mesh& mesh, int32_t e, std::vector<int32_t>& nodes);

}  // namespace talus::solver
