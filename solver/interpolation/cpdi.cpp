// CPDI's particle domains (stencil.hpp, fill_cpdi, for the shape functions they give): where they
// start and how their corners move.
#include <cmath>

#include "solver/interpolation/interpolation.hpp"

namespace talus::solver {
namespace {

Vec2 corner(const Mesh& mesh, int32_t e, int k) { return mesh.nodes[mesh.triangles[e][k]]; }

double twice_signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

// The triangle similar to element e, of area `volume`, with its centroid at x (rotated half a
// turn when `inverted`).
void similar_domain(const Mesh& mesh, int32_t e, const Vec2& x, double volume, bool inverted, Vec2* y) {
  const Vec2 centroid = (corner(mesh, e, 0) + corner(mesh, e, 1) + corner(mesh, e, 2)) / 3;
  const double scale = std::sqrt(volume / mesh.area[e]) * (inverted ? -1 : 1);
  for (int c = 0; c < 3; ++c) y[c] = x + scale * (corner(mesh, e, c) - centroid);
}

}  // namespace

void initial_domains(const Mesh& mesh, Particles& P) {
  const std::size_t n = P.size();
  P.domain.assign(3 * n, Vec2::Zero());
  for (std::size_t p = 0; p < n; ++p) {
    const int32_t e = P.element[p];
    const Vec3 w = mesh.weights(e, P.x[p]);
    // The seeding's middle particle of four (seeding.cpp): at the centroid, a quarter of the area.
    const bool middle = (w - Vec3::Constant(1.0 / 3)).cwiseAbs().maxCoeff() < 1e-6 &&
                        std::abs(P.volume[p] / mesh.area[e] - 0.25) < 1e-6;
    // Kept inside the particle's element: the similar triangle scaled by s about a point of
    // barycentric weights w has its corners at w + s (e_k - 1/3), inside while s <= 3 min(w).
    // The patterns of 3, 6 and 10 per cell put particles a third of a sub-triangle's height
    // from the element's edges, where a domain of the particle's whole volume would reach
    // across them: into a support under a body, or from a heavy body into a light one
    // (docs/shape-functions.md, "CPDI's initial domains"). Four per cell tile the element.
    double volume = P.volume[p];
    const double fits = 3 * w.minCoeff();
    if (!middle && fits * fits * mesh.area[e] < volume * (1 - 1e-9)) volume = fits * fits * mesh.area[e];
    similar_domain(mesh, e, P.x[p], volume, middle, &P.domain[3 * p]);
  }
}

void move_domains(const Mesh& mesh, Particles& P, const Stencil& stencil, const Grids& grids, double dt, int threads) {
  const long moving = static_cast<long>(P.moving_count);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long p = 0; p < moving; ++p) {
    const Grid& grid = grids.fields[grids.field_of(P.body[p])];
    const int32_t* nodes = stencil.nodes(p);
    const double* N = stencil.weights(p);
    const int32_t e = P.element[p];
    // A corner outside the mesh or the row moves with the particle.
    auto particle_velocity = [&] {
      Vec2 v_p = Vec2::Zero();
      for (int k = 0; k < stencil.width; ++k) v_p += N[k] * grid.v[nodes[k]];
      return v_p;
    };
    auto in_row = [&](int32_t element) {
      for (int32_t i : mesh.triangles[element]) {
        bool found = false;
        for (int k = 0; k < stencil.width && !found; ++k) found = nodes[k] == i;
        if (!found) return false;
      }
      return true;
    };
    Vec2* y = &P.domain[3 * static_cast<std::size_t>(p)];
    const int32_t* found_in = &stencil.corner_element[3 * static_cast<std::size_t>(p)];
    for (int c = 0; c < 3; ++c) {
      int32_t ce = found_in[c];
      Vec3 w;
      if (ce >= 0) {  // where fill_cpdi found it: the element's nodes are in the row
        w = mesh.weights(ce, y[c]);
      } else {
        ce = locate(mesh, e, y[c], &w);
        if (ce >= 0 && !in_row(ce)) ce = -1;
      }
      Vec2 v = Vec2::Zero();
      if (ce >= 0) {
        for (int k = 0; k < 3; ++k) v += w[k] * grid.v[mesh.triangles[ce][k]];
      } else {
        v = particle_velocity();
      }
      y[c] += dt * v;
    }
    // Centred again on the particle, which moved with the mean of these velocities unless a
    // corner was held back.
    const Vec2 shift = P.x[p] - (y[0] + y[1] + y[2]) / 3;
    for (int c = 0; c < 3; ++c) y[c] += shift;
    const double volume = P.volume[p];
    const double area = 0.5 * twice_signed_area(y[0], y[1], y[2]);
    const double element_area =
        0.5 * twice_signed_area(corner(mesh, e, 0), corner(mesh, e, 1), corner(mesh, e, 2));
    double longest = 0;
    for (int c = 0; c < 3; ++c) longest = std::max(longest, (y[(c + 1) % 3] - y[c]).squaredNorm());
    if (!(area / element_area > 0) || std::abs(area) < 0.1 * volume || longest > 25 * volume)
      similar_domain(mesh, e, P.x[p], volume, false, y);
  }
}

}  // namespace talus::solver
