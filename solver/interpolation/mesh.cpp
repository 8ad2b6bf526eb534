#include <cmath>
#include <limits>

#include "common/error.hpp"
#include "solver/interpolation/mesh.hpp"

namespace talus::solver {

Mesh build_mesh(const Model& model) {
  Mesh mesh;
  mesh.nodes = model.nodes;
  mesh.triangles = model.triangles;
  mesh.neighbours = model.neighbours;
  const std::size_t count = mesh.triangles.size();
  mesh.constant.resize(count);
  auto gradients = std::make_shared<std::vector<Vec2>>(count * 3);
  mesh.area.resize(count);
  mesh.h_min = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < count; ++e) {
    const auto& t = mesh.triangles[e];
    const Vec2 x[3] = {mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]]};
    const double twice_area = (x[1] - x[0]).x() * (x[2] - x[0]).y() - (x[1] - x[0]).y() * (x[2] - x[0]).x();
    if (!(twice_area > 0))
      throw Error("model: element " + std::to_string(e) + " is degenerate or clockwise (twice its area is " +
                  std::to_string(twice_area) + ")");
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      // N_k = (a_k + b_k x + c_k y) / 2A with (k, i, j) cyclic.
      const Vec2& xi = x[(k + 1) % 3];
      const Vec2& xj = x[(k + 2) % 3];
      mesh.constant[e][k] = (xi.x() * xj.y() - xj.x() * xi.y()) / twice_area;
      (*gradients)[e * 3 + k] = Vec2((xi.y() - xj.y()) / twice_area, (xj.x() - xi.x()) / twice_area);
      longest = std::max(longest, (xj - xi).norm());
    }
    mesh.area[e] = 0.5 * twice_area;
    mesh.h_min = std::min(mesh.h_min, twice_area / longest);
  }
  mesh.gradients = std::move(gradients);
  return mesh;
}

}  // namespace talus::solver
