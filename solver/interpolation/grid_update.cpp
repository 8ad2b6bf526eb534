// The grid's own work between the two transfers: the nodal accelerations (A.9, with the
// boundary conditions and local damping), the velocities XPIC and APIC hand to the particles,
// and the remap's velocities (A.11).
#include "solver/interpolation/interpolation.hpp"

namespace talus::solver {

void update_grid_accelerations(const Constraints& constraints, const std::vector<uint8_t>& field_fixed, double damping,
                               double dt, Grids& grids, int threads) {
  const auto& active = grids.active;
  const long count = static_cast<long>(active.size());
  for (std::size_t field = 0; field < grids.fields.size(); ++field) {
    Grid& grid = grids.fields[field];
    const bool fixed_body = grids.per_body && field_fixed[field];
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long k = 0; k < count; ++k) {
      const int32_t i = active[k];
      if (grid.m[i] <= 0 || fixed_body) {
        grid.a[i].setZero();
        grid.p[i].setZero();
        continue;
      }
      Vec2 f = grid.f[i];
      if (damping > 0) {  // local damping against the sign of the nodal velocity (Cundall)
        const Vec2& mom = grid.p[i];
        for (int d = 0; d < 2; ++d) f[d] -= damping * std::abs(f[d]) * (mom[d] > 0 ? 1.0 : mom[d] < 0 ? -1.0 : 0.0);
      }
      // The constraint holds for the velocity at the end of the step: a constrained node's
      // acceleration is whatever brings its velocity to the allowed one in dt. Zeroing the
      // acceleration alone would leave the particles beside a fixed node with whatever velocity
      // they carried in, moving nowhere but counted as kinetic energy.
      const Vec2 v = grid.p[i] / grid.m[i];
      Vec2 v_end = v + dt * f / grid.m[i];
      constrain(constraints, i, v_end);
      grid.a[i] = dt > 0 ? Vec2((v_end - v) / dt) : Vec2(f / grid.m[i]);
      if (dt == 0) constrain(constraints, i, grid.a[i]);
    }
  }
  mirror_accelerations(constraints, grids);
}

void fold_ghosts(const Constraints& constraints, Grids& grids) {
  for (Grid& grid : grids.fields)
    constraints.for_each_mirror(grids.active, [&](int32_t g, int32_t partner, const Eigen::Matrix2d& R) {
      grid.m[partner] += grid.m[g];
      grid.p[partner] += R * grid.p[g];
      grid.f[partner] += R * grid.f[g];
      if (!grid.mass_gradient.empty()) grid.mass_gradient[partner] += R * grid.mass_gradient[g];
      grid.m[g] = 0;
      grid.p[g].setZero();
      grid.f[g].setZero();
      if (!grid.mass_gradient.empty()) grid.mass_gradient[g].setZero();
    });
}

void mirror_accelerations(const Constraints& constraints, Grids& grids) {
  for (Grid& grid : grids.fields)
    constraints.for_each_mirror(grids.active, [&](int32_t g, int32_t partner, const Eigen::Matrix2d& R) {
      grid.a[g] = R * grid.a[partner];
    });
}

void mirror_velocities(const Constraints& constraints, Grids& grids) {
  for (Grid& grid : grids.fields)
    constraints.for_each_mirror(grids.active, [&](int32_t g, int32_t partner, const Eigen::Matrix2d& R) {
      grid.v[g] = R * grid.v[partner];
    });
}

void lagrangian_grid_velocities(const Constraints& constraints, double dt, Grids& grids, int threads) {
  const auto& active = grids.active;
  const long count = static_cast<long>(active.size());
  for (Grid& grid : grids.fields) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long k = 0; k < count; ++k) {
      const int32_t i = active[k];
      // Empty nodes and a fixed body's field carry no momentum (update_grid_accelerations).
      grid.v[i] = grid.m[i] > 0 ? Vec2(grid.p[i] / grid.m[i] + dt * grid.a[i]) : Vec2::Zero();
    }
  }
  mirror_velocities(constraints, grids);
}

void remap_grid_velocities(const Constraints& constraints, const std::vector<uint8_t>& field_fixed, Grids& grids,
                           ThreadBuffers& buffers, int threads, const std::function<void()>& exchange) {
  const auto& active = grids.active;
  const long count = static_cast<long>(active.size());
  // (A.11) at node i of a field whose momentum sum is `momentum`, constrained.
  auto remapped = [&](std::size_t field, int32_t i, const Vec2& momentum) {
    Grid& grid = grids.fields[field];
    const bool fixed_body = grids.per_body && field_fixed[field];
    grid.v[i] = grid.m[i] > 0 && !fixed_body ? Vec2(momentum / grid.m[i]) : Vec2::Zero();
    constrain(constraints, i, grid.v[i]);
  };
  if (!exchange && !constraints.has_ghosts()) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long k = 0; k < count; ++k)
      for (std::size_t field = 0; field < grids.fields.size(); ++field)
        remapped(field, active[k], take_thread_sum(buffers, field, &NodeBuffer::p, active[k]));
    return;
  }
  // Several ranks, or ghost nodes: the momentum into grid.v first; then the ranks' sums at the
  // shared nodes, and the ghosts' momentum folded into their partners'; then (A.11) and the
  // ghosts' mirrored velocities.
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k)
    for (std::size_t field = 0; field < grids.fields.size(); ++field)
      grids.fields[field].v[active[k]] = take_thread_sum(buffers, field, &NodeBuffer::p, active[k]);
  if (exchange) exchange();
  for (Grid& grid : grids.fields)
    constraints.for_each_mirror(active, [&](int32_t g, int32_t partner, const Eigen::Matrix2d& R) {
      grid.v[partner] += R * grid.v[g];
    });
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k)
    for (std::size_t field = 0; field < grids.fields.size(); ++field)
      remapped(field, active[k], grids.fields[field].v[active[k]]);
  mirror_velocities(constraints, grids);
}

}  // namespace talus::solver
