#include "preproc/lattice.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.hpp"

namespace talus::preproc {
namespace {

// Interleaves the bits of i and j (a Morton key): cells in this order keep a run of elements, and
// so of the solver's sorted particles, in a compact patch of the lattice.
uint64_t morton(uint32_t i, uint32_t j) {
  uint64_t key = 0;
  for (int bit = 0; bit < 32; ++bit)
    key |= (static_cast<uint64_t>((i >> bit) & 1u) << (2 * bit)) | (static_cast<uint64_t>((j >> bit) & 1u) << (2 * bit + 1));
  return key;
}

double distance_to_segment(const Eigen::Vector2d& x, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0 ? std::clamp((x - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - x).norm();
}

}  // namespace

BackgroundMesh lattice_mesh(const GeoMesh& geo, const PhysicalGroup& domain, double size) {
  // The rectangle: the bounds of the domain's triangles, which must fill it.
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), high = -low;
  double area = 0;
  for (int surface : domain.entities) {
    const auto found = geo.surface_triangles.find(surface);
    if (found == geo.surface_triangles.end()) continue;
    for (const auto& t : found->second) {
      const Eigen::Vector2d a = geo.node_position[t[0]], b = geo.node_position[t[1]], c = geo.node_position[t[2]];
      low = low.cwiseMin(a).cwiseMin(b).cwiseMin(c);
      high = high.cwiseMax(a).cwiseMax(b).cwiseMax(c);
      area += 0.5 * std::abs((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    }
  }
  const Eigen::Vector2d extent = high - low;
  if (!(extent.minCoeff() > 0) || std::abs(area - extent.prod()) > 1e-6 * extent.prod()) {
    std::ostringstream message;
    message << "mesh.pattern = \"grid\" needs a domain that is an axis-aligned rectangle; the physical surface \""
            << domain.name << "\" covers " << area << " m^2 of its bounding box of " << extent.x() << " m by "
            << extent.y() << " m";
    throw Error(located(geo.path, "", message.str()));
  }
  const int nx = std::max(1, static_cast<int>(std::lround(extent.x() / size)));
  const int ny = std::max(1, static_cast<int>(std::lround(extent.y() / size)));
  const Eigen::Vector2d h(extent.x() / nx, extent.y() / ny);

  BackgroundMesh mesh;
  mesh.lattice = true;
  auto corner = [&](int i, int j) { return static_cast<int32_t>(j * (nx + 1) + i); };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) mesh.nodes.emplace_back(low.x() + i * h.x(), low.y() + j * h.y());
  std::vector<std::pair<uint64_t, std::array<int, 2>>> cells;
  cells.reserve(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) cells.push_back({morton(static_cast<uint32_t>(i), static_cast<uint32_t>(j)), {i, j}});
  std::sort(cells.begin(), cells.end());
  for (const auto& [key, cell] : cells) {
    const auto [i, j] = cell;
    const int32_t centre = static_cast<int32_t>(mesh.nodes.size());
    mesh.nodes.emplace_back(low.x() + (i + 0.5) * h.x(), low.y() + (j + 0.5) * h.y());
    const int32_t around[4] = {corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)};
    for (int k = 0; k < 4; ++k) mesh.triangles.push_back({around[k], around[(k + 1) % 4], centre});  // counter-clockwise
  }
  find_neighbours(mesh.triangles, mesh.neighbours);
  return mesh;
}

std::vector<std::array<int32_t, 2>> lattice_segments(const GeoMesh& geo, const PhysicalGroup& curve,
                                                     const BackgroundMesh& lattice) {
  // The lattice's boundary edges, each kept when its midpoint lies on one of the curve's segments.
  std::vector<std::array<int32_t, 2>> segments;
  double tolerance = std::numeric_limits<double>::infinity();
  for (const auto& t : lattice.triangles)
    for (int k = 0; k < 3; ++k)
      tolerance = std::min(tolerance, 1e-6 * (lattice.nodes[t[k]] - lattice.nodes[t[(k + 1) % 3]]).norm());
  for (const auto& [a, b] : boundary_edges(lattice)) {
    const Eigen::Vector2d middle = 0.5 * (lattice.nodes[a] + lattice.nodes[b]);
    bool on = false;
    for (int entity : curve.entities) {
      const auto found = geo.curve_segments.find(entity);
      if (found == geo.curve_segments.end()) continue;
      for (const auto& [p, q] : found->second)
        if (distance_to_segment(middle, geo.node_position[p], geo.node_position[q]) <= tolerance) on = true;
    }
    if (on) segments.push_back({static_cast<int32_t>(a), static_cast<int32_t>(b)});
  }
  return segments;
}

}  // namespace talus::preproc
