// What the time loop and the outputs read off a simulation without changing it: the energies,
// and the velocity that moves each particle.
#include <cmath>

#include "solver/parallel/mpi.hpp"
#include "solver/parallel/threads.hpp"
#include "solver/step/simulation.hpp"
#include "solver/stress/stress.hpp"

namespace talus::solver {

namespace {

struct ParticleEnergies {
  double kinetic = 0, potential = 0, strain = 0;
  ParticleEnergies& operator+=(const ParticleEnergies& o) {
    kinetic += o.kinetic;
    potential += o.potential;
    strain += o.strain;
    return *this;
  }
};

}  // namespace

Energies energies(const Simulation& sim) {
  const Particles& P = sim.particles;
  const Config& c = sim.config;
  const int threads = c.threads;
  const ParticleEnergies sums =
      ordered_sum<ParticleEnergies>(static_cast<long>(P.moving_count), threads, [&](long p) {
        return ParticleEnergies{0.5 * P.m[p] * P.v[p].squaredNorm(), -P.m[p] * c.gravity.dot(P.x[p]),
                                P.volume[p] * elastic_energy_density(c, P, p)};
      });
  // The kinetic energy of the velocity field that moves the material (A.12): the grid's, with
  // lumped masses. Particle (FLIP) velocities also carry components the grid cannot see; they
  // move nothing and would keep a deposit at rest from ever looking so.
  // On several ranks a shared node counts on one of them only (Domain::counts).
  double grid_kinetic = 0;
  const Grids& grids = sim.scratch.grids;
  const Domain& domain = sim.domain;
  const long count = static_cast<long>(grids.active.size());
  for (const Grid& grid : grids.fields)
    grid_kinetic += ordered_sum<double>(count, threads, [&](long k) {
      const int32_t i = grids.active[k];
      return domain.counts(i) ? 0.5 * grid.m[i] * grid.v[i].squaredNorm() : 0.0;
    });
  if (!domain.distributed()) return {sums.kinetic, sums.potential, sums.strain, grid_kinetic};
  double all[4] = {sums.kinetic, sums.potential, sums.strain, grid_kinetic};
  mpi::sum_in_rank_order(all, 4);
  return {all[0], all[1], all[2], all[3]};
}

namespace {

// sum S_ip v_i with the stencil the solver holds now.
Vec2 interpolated(const Simulation& sim, std::size_t p) {
  const Particles& P = sim.particles;
  if (p >= P.moving_count) return Vec2::Zero();
  const Stencil& S = sim.scratch.stencil;
  const Grid& grid = sim.scratch.grids.fields[sim.scratch.grids.field_of(P.body[p])];
  const double* N = S.weights(p);
  const int32_t* nodes = S.nodes(p);
  Vec2 velocity = Vec2::Zero();
  for (int k = 0; k < S.width; ++k) velocity += N[k] * grid.v[nodes[k]];
  return velocity;
}

// interpolated() at every particle.
std::vector<Vec2> interpolated_at_particles(const Simulation& sim) {
  std::vector<Vec2> velocity(sim.particles.size());
  const long count = static_cast<long>(velocity.size());
#pragma omp parallel for schedule(static) num_threads(sim.config.threads)
  for (long p = 0; p < count; ++p) velocity[p] = interpolated(sim, static_cast<std::size_t>(p));
  return velocity;
}

}  // namespace

Vec2 grid_velocity_at_particle(const Simulation& sim, std::size_t p) {
  const Particles& P = sim.particles;
  if (sim.steps == 0) return P.v[p];  // no grid field yet: the initial velocities
  if (P.step_velocity.size() == P.size()) return P.step_velocity[p];
  return interpolated(sim, p);
}

std::vector<Vec2> grid_velocity_at_particles(const Simulation& sim) {
  const Particles& P = sim.particles;
  if (sim.steps == 0) return P.v;
  if (P.step_velocity.size() == P.size()) return P.step_velocity;
  return interpolated_at_particles(sim);
}

void keep_step_velocities(Simulation& sim) { sim.particles.step_velocity = interpolated_at_particles(sim); }

}  // namespace talus::solver
