#include "solver/interpolation/lattice.hpp"

#include <algorithm>
#include <cmath>

namespace talus::solver {
namespace {

// Within a millionth of a cell: the grid pattern's nodes are computed as origin + i h.
bool near(const Vec2& a, const Vec2& b, double tolerance) { return (a - b).cwiseAbs().maxCoeff() <= tolerance; }

// The reflection across an edge whose nodes have constraint `kind` with normal `n`.
Eigen::Matrix2d reflection(Constraint kind, const Vec2& n) {
  if (kind == Constraint::Fixed) return -Eigen::Matrix2d::Identity();
  return Eigen::Matrix2d::Identity() - 2 * n * n.transpose();  // roller, friction: the normal part reversed
}

// A node index along an edge of n cells, one in from the corners where the edge has inner nodes.
int inner(int k, int n) { return n >= 2 ? std::clamp(k, 1, n - 1) : std::clamp(k, 0, n); }

}  // namespace

std::optional<Lattice> find_lattice(const Mesh& mesh) {
  const auto& x = mesh.nodes;
  const std::size_t count = x.size();
  if (count < 4) return std::nullopt;
  Lattice L;
  L.origin = x[0];
  L.spacing.x() = x[1].x() - x[0].x();
  if (!(L.spacing.x() > 0)) return std::nullopt;
  double tolerance = 1e-6 * L.spacing.x();
  if (std::abs(x[1].y() - x[0].y()) > tolerance) return std::nullopt;
  auto corner = [&](int i, int j) { return Vec2(L.origin + Vec2(i * L.spacing.x(), j * L.spacing.y())); };
  L.nx = 1;
  while (static_cast<std::size_t>(L.nx) + 1 < count && near(x[L.nx + 1], corner(L.nx + 1, 0), tolerance)) ++L.nx;
  const std::size_t row = static_cast<std::size_t>(L.nx) + 1;
  if (row >= count) return std::nullopt;
  L.spacing.y() = x[row].y() - x[0].y();
  if (!(L.spacing.y() > 0)) return std::nullopt;
  tolerance = 1e-6 * L.spacing.minCoeff();
  auto row_matches = [&](int j) {
    if ((static_cast<std::size_t>(j) + 1) * row > count) return false;
    for (int i = 0; i <= L.nx; ++i)
      if (!near(x[static_cast<std::size_t>(j) * row + static_cast<std::size_t>(i)], corner(i, j), tolerance)) return false;
    return true;
  };
  if (!row_matches(0)) return std::nullopt;
  while (row_matches(L.ny + 1)) ++L.ny;
  if (L.ny == 0) return std::nullopt;
  // Every triangle within one cell, and so every node within the lattice's rectangle.
  for (const auto& t : mesh.triangles) {
    const Vec2 centroid = (x[t[0]] + x[t[1]] + x[t[2]]) / 3;
    const Vec2 cell = ((centroid - L.origin).array() / L.spacing.array()).floor();
    if (cell.x() < 0 || cell.y() < 0 || cell.x() >= L.nx || cell.y() >= L.ny) return std::nullopt;
    const Vec2 low = corner(static_cast<int>(cell.x()), static_cast<int>(cell.y()));
    for (int32_t i : t) {
      const Vec2 d = x[i] - low;
      if (d.x() < -tolerance || d.y() < -tolerance || d.x() > L.spacing.x() + tolerance ||
          d.y() > L.spacing.y() + tolerance)
        return std::nullopt;
    }
  }
  L.node_id.assign(static_cast<std::size_t>(L.nx + 3) * static_cast<std::size_t>(L.ny + 3), -1);
  for (int j = 0; j <= L.ny; ++j)
    for (int i = 0; i <= L.nx; ++i)
      L.node_id[static_cast<std::size_t>(j + 1) * (L.nx + 3) + (i + 1)] = static_cast<int32_t>(j * row + i);
  return L;
}

void add_ghost_layer(Lattice& L, Mesh& mesh, Constraints& constraints) {
  const int32_t first_ghost = static_cast<int32_t>(mesh.node_count());
  const std::size_t stride = static_cast<std::size_t>(L.nx + 3);
  std::vector<std::pair<int, int>> ghosts;  // (i, j) of each ghost, in id order
  for (int j = -1; j <= L.ny + 1; ++j)
    for (int i = -1; i <= L.nx + 1; ++i) {
      if (i >= 0 && i <= L.nx && j >= 0 && j <= L.ny) continue;
      L.node_id[static_cast<std::size_t>(j + 1) * stride + (i + 1)] = static_cast<int32_t>(mesh.nodes.size());
      mesh.nodes.push_back(L.origin + Vec2(i * L.spacing.x(), j * L.spacing.y()));
      ghosts.emplace_back(i, j);
    }
  const std::size_t nodes = mesh.node_count();
  constraints.kind.resize(nodes, Constraint::Free);
  constraints.normal.resize(nodes, Vec2::Zero());
  constraints.friction.resize(nodes, 0.0);
  constraints.first_ghost = first_ghost;
  constraints.mirrors.assign(ghosts.size(), Mirror{});
  auto mirrored = [](int k, int n) { return k < 0 ? -k : k > n ? 2 * n - k : k; };
  for (std::size_t g = 0; g < ghosts.size(); ++g) {
    const auto [i, j] = ghosts[g];
    Mirror mirror;
    mirror.partner = L.id(mirrored(i, L.nx), mirrored(j, L.ny));
    // Across each edge the ghost lies beyond; a free edge leaves it an ordinary node.
    auto across = [&](int32_t edge_node) {
      const Constraint kind = constraints.kind[edge_node];
      if (kind == Constraint::Free) return false;
      mirror.reflection = mirror.reflection * reflection(kind, constraints.normal[edge_node]);
      return true;
    };
    bool held = true;
    if (i < 0 || i > L.nx) held = across(L.id(i < 0 ? 0 : L.nx, inner(j, L.ny)));
    if (held && (j < 0 || j > L.ny)) held = across(L.id(inner(i, L.nx), j < 0 ? 0 : L.ny));
    if (held) constraints.mirrors[g] = mirror;
  }
}

void reachable_nodes(const Lattice& L, const Mesh& mesh, int32_t e, std::vector<int32_t>& nodes) {
  const auto& t = mesh.triangles[e];
  const Vec2 centroid = (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]]) / 3;
  const int ci = std::clamp(static_cast<int>(std::floor((centroid.x() - L.origin.x()) / L.spacing.x())), 0, L.nx - 1);
  const int cj = std::clamp(static_cast<int>(std::floor((centroid.y() - L.origin.y()) / L.spacing.y())), 0, L.ny - 1);
  nodes.clear();
  for (int j = cj - 1; j <= cj + 2; ++j)
    for (int i = ci - 1; i <= ci + 2; ++i) nodes.push_back(L.id(i, j));
}

}  // namespace talus::solver
