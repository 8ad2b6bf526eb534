#include "preproc/seeding.hpp"

#include <Eigen/Geometry>
#include <sstream>

#include "common/error.hpp"

namespace talus::preproc {
namespace {

// Split a triangle into n^2 similar triangles of equal area (n along each edge); the n(n+1)/2
// that point the same way as the triangle have centroids with barycentric coordinates
// ((i + 1/3)/n, (j + 1/3)/n, (k + 1/3)/n), i + j + k = n - 1. They form an even lattice, one
// point per equal share of the area, strictly inside the triangle.
std::vector<Eigen::Vector3d> upward_centroids(int n) {
  std::vector<Eigen::Vector3d> points;
  for (int i = n - 1; i >= 0; --i)
    for (int j = n - 1 - i; j >= 0; --j) {
      const int k = n - 1 - i - j;
      points.emplace_back((i + 1.0 / 3) / n, (j + 1.0 / 3) / n, (k + 1.0 / 3) / n);
    }
  return points;
}

}  // namespace

std::vector<Eigen::Vector3d> seed_pattern(int particles_per_cell) {
  switch (particles_per_cell) {
    case 1: return upward_centroids(1);   // the centroid
    case 3: return upward_centroids(2);   // (2/3, 1/6, 1/6) and permutations
    case 6: return upward_centroids(3);
    case 10: return upward_centroids(4);
    case 4: {
      // The centroids of all four midpoint sub-triangles: the three corner ones and the
      // inverted middle one, whose centroid is the triangle's centroid.
      auto points = upward_centroids(2);
      points.emplace_back(1.0 / 3, 1.0 / 3, 1.0 / 3);
      return points;
    }
    default: return {};
  }
}

Seeds seed_particles(const BackgroundMesh& mesh, const std::vector<SeedBody>& bodies, const std::string& scene_path) {
  std::vector<std::vector<Eigen::Vector3d>> patterns;
  std::vector<Eigen::AlignedBox2d> bounds;
  for (const auto& body : bodies) {
    patterns.push_back(seed_pattern(body.particles_per_cell));
    if (patterns.back().empty())
      throw Error(located(scene_path, "bodies." + body.name + ".particles_per_cell",
                          "no seeding pattern for " + std::to_string(body.particles_per_cell) +
                              " (expected 1, 3, 4, 6 or 10)"));
    bounds.push_back(body.region->bounds());
  }

  Seeds seeds;
  for (int32_t e = 0; e < static_cast<int32_t>(mesh.triangles.size()); ++e) {
    const auto& t = mesh.triangles[e];
    const Eigen::Vector2d a = mesh.nodes[t[0]], b = mesh.nodes[t[1]], c = mesh.nodes[t[2]];
    Eigen::AlignedBox2d triangle_box(a);
    triangle_box.extend(b).extend(c);
    const double area = 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    for (int32_t body = 0; body < static_cast<int32_t>(bodies.size()); ++body) {
      if (!bounds[body].intersects(triangle_box)) continue;
      const double volume = area / static_cast<double>(patterns[body].size());
      for (const Eigen::Vector3d& w : patterns[body]) {
        const Eigen::Vector2d x = w[0] * a + w[1] * b + w[2] * c;
        if (!bodies[body].region->contains(x)) continue;
        for (int32_t other = 0; other < static_cast<int32_t>(bodies.size()); ++other) {
          if (other == body || !bounds[other].contains(x) || !bodies[other].region->contains(x)) continue;
          std::ostringstream where;
          where << "(" << x.x() << ", " << x.y() << ")";
          throw Error(located(scene_path, "bodies." + bodies[body].name + " and bodies." + bodies[other].name,
                              "the bodies overlap (both contain the point " + where.str() +
                                  "); a point may belong to one body only"));
        }
        seeds.position.push_back(x);
        seeds.volume.push_back(volume);
        seeds.body.push_back(body);
        seeds.element.push_back(e);
      }
    }
  }
  return seeds;
}

}  // namespace talus::preproc
