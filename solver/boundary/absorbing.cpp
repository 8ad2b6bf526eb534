#include "solver/boundary/absorbing.hpp"

namespace talus::solver {

void apply_dashpots(const AbsorbingNodes& d, const BaseMotion& motion, double t, double dt, Grids& grids) {
  if (!(dt > 0)) return;
  const Vec2 ground = motion.compliant ? motion.ground_velocity(t + dt) : Vec2::Zero();
  for (Grid& grid : grids.fields)
    for (std::size_t k = 0; k < d.node.size(); ++k) {
      const int32_t i = d.node[k];
      const double m = grid.m[i];
      if (!(m > 0)) continue;
      const Vec2 n = d.normal[k], tangent(-n.y(), n.x());
      const Vec2 v = grid.p[i] / m, free = v + dt * grid.a[i];
      const Vec2 reference = d.input[k] ? ground : Vec2::Zero();
      const double c_n = d.length[k] * d.impedance[k].x(), c_t = d.length[k] * d.impedance[k].y();
      const double v_n = (m * free.dot(n) + dt * c_n * reference.dot(n)) / (m + dt * c_n);
      const double v_t = (m * free.dot(tangent) + dt * c_t * reference.dot(tangent)) / (m + dt * c_t);
      grid.a[i] = (v_n * n + v_t * tangent - v) / dt;
    }
}

}  // namespace talus::solver
