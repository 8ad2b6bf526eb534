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
}

void lagrangian_grid_velocities(double dt, Grids& grids, int threads) {
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
  if (!exchange) {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long k = 0; k < count; ++k)
      for (std::size_t field = 0; field < grids.fields.size(); ++field)
        remapped(field, active[k], take_thread_sum(buffers, field, &NodeBuffer::p, active[k]));
    return;
  }
  // Several ranks: this rank's momentum into grid.v, the ranks' sums at the shared nodes, then (A.11).
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k)
    for (std::size_t field = 0; field < grids.fields.size(); ++field)
      grids.fields[field].v[active[k]] = take_thread_sum(buffers, field, &NodeBuffer::p, active[k]);
  exchange();
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k)
    for (std::size_t field = 0; field < grids.fields.size(); ++field)
      remapped(field, active[k], grids.fields[field].v[active[k]]);
}

}  // namespace talus::solver
