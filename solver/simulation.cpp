#include "solver/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "common/error.hpp"

namespace talus::solver {
namespace {

// Zeroes the velocity component that a node's constraint forbids.
inline void constrain(const Constraints& c, int32_t i, Vec2& value) {
  if (c.kind[i] == 1) value.setZero();
  else if (c.kind[i] == 2) value -= value.dot(c.normal[i]) * c.normal[i];
}

inline int field_of(const Simulation& sim, int32_t body) { return sim.contact ? 1 + body : 0; }

void resize_grid(Grid& grid, std::size_t nodes) {
  grid.m.assign(nodes, 0);
  grid.p.assign(nodes, Vec2::Zero());
  grid.f.assign(nodes, Vec2::Zero());
  grid.a.assign(nodes, Vec2::Zero());
  grid.v.assign(nodes, Vec2::Zero());
}

template <class T>
void permute(std::vector<T>& values, const std::vector<int32_t>& order) {
  std::vector<T> sorted(values.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = values[order[k]];
  values.swap(sorted);
}

}  // namespace

Simulation make_simulation(const Model& model, int threads) {
  Simulation sim;
  sim.mesh = build_mesh(model);
  sim.constraints = build_constraints(model);
  sim.gravity = model.run.gravity;
  sim.gravity_ramp = model.run.gravity_ramp;
  sim.damping = model.run.damping;
  sim.pic_fraction = model.run.pic_fraction;
  sim.evs = model.run.evs;

  for (const auto& material : model.materials) sim.materials.push_back(make_material(material));
  for (const auto& body : model.bodies) {
    sim.material_of_body.push_back(body.material);
    sim.body_fixed.push_back(body.fixed);
  }

  Particles& P = sim.particles;
  const std::size_t n = model.particle_count();
  P.x = model.position;
  P.v = model.velocity;
  P.m = model.mass;
  P.volume = model.volume;
  P.sigma = model.stress;
  P.eps_p.assign(n, 0);
  P.d_eps.assign(n, Vec4::Zero());
  P.body = model.body;
  P.element = model.element;
  P.id.resize(n);
  std::iota(P.id.begin(), P.id.end(), 0);
  for (std::size_t p = 0; p < n; ++p) {
    const int32_t e = locate(sim.mesh, P.element[p], P.x[p]);
    if (e < 0)
      throw Error("model: particle " + std::to_string(p) + " at (" + std::to_string(P.x[p].x()) + ", " +
                  std::to_string(P.x[p].y()) + ") is outside the background mesh");
    P.element[p] = e;
    if (sim.body_fixed[P.body[p]]) P.v[p].setZero();
  }
  sort_particles(sim);

  // The contact pass runs only where bodies can meet: two or more bodies, contact on.
  sim.contact = model.contact.enabled && model.bodies.size() > 1;
  const std::size_t field_count = sim.contact ? 1 + model.bodies.size() : 1;
  sim.fields.resize(field_count);
  for (auto& grid : sim.fields) resize_grid(grid, sim.mesh.node_count());
  if (sim.contact) {
    const std::size_t b = model.bodies.size();
    sim.pair_friction.assign(b, std::vector<double>(b, model.contact.friction));
    for (std::size_t i = 0; i < b; ++i)
      for (std::size_t j = 0; j < b; ++j)
        sim.pair_friction[i][j] = pair_friction(model.contact, model.bodies[i].name, model.bodies[j].name);
  } else {
    // One velocity field: a fixed body is a rigid support, so its nodes do not move.
    for (std::size_t p = P.moving_count; p < n; ++p)
      for (int32_t i : sim.mesh.triangles[P.element[p]]) sim.constraints.kind[i] = 1;
  }

  threads = std::max(threads, 1);
  sim.buffers.resize(threads);
  for (auto& per_thread : sim.buffers) {
    per_thread.resize(field_count);
    for (auto& buffer : per_thread) {
      buffer.m.assign(sim.mesh.node_count(), 0);
      buffer.p.assign(sim.mesh.node_count(), Vec2::Zero());
      buffer.f.assign(sim.mesh.node_count(), Vec2::Zero());
      if (sim.contact) buffer.mass_gradient.assign(sim.mesh.node_count(), Vec2::Zero());
    }
  }
  for (auto& grid : sim.fields)
    if (sim.contact) grid.mass_gradient.assign(sim.mesh.node_count(), Vec2::Zero());
  sim.node_stamp.assign(sim.mesh.node_count(), 0);
  if (sim.evs) {
    sim.element_strain.assign(sim.mesh.element_count(), 0);
    sim.element_volume.assign(sim.mesh.element_count(), 0);
    sim.node_strain.assign(sim.mesh.node_count(), 0);
    sim.node_area.assign(sim.mesh.node_count(), 0);
  }
  return sim;
}

void sort_particles(Simulation& sim) {
  Particles& P = sim.particles;
  const std::size_t n = P.size();
  std::vector<int32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int32_t a, int32_t b) {
    const bool fa = sim.body_fixed[P.body[a]], fb = sim.body_fixed[P.body[b]];
    return fa != fb ? fb : P.element[a] < P.element[b];
  });
  permute(P.x, order);
  permute(P.v, order);
  permute(P.m, order);
  permute(P.volume, order);
  permute(P.sigma, order);
  permute(P.eps_p, order);
  permute(P.d_eps, order);
  permute(P.body, order);
  permute(P.element, order);
  permute(P.id, order);
  P.moving_count = 0;
  while (P.moving_count < n && !sim.body_fixed[P.body[P.moving_count]]) ++P.moving_count;
}

Vec2 gravity_at(const Simulation& sim, double t) {
  if (t >= sim.gravity_ramp) return sim.gravity;
  return 0.5 * (1 - std::cos(M_PI * t / sim.gravity_ramp)) * sim.gravity;
}

double stable_time_step(const Simulation& sim, double cfl) {
  double wave_speed = 0;
  for (const auto& material : sim.materials) wave_speed = std::max(wave_speed, material.wave_speed);
  double max_speed = 0;
  const Particles& P = sim.particles;
  const long n = static_cast<long>(P.moving_count);
#pragma omp parallel for reduction(max : max_speed) schedule(static)
  for (long p = 0; p < n; ++p) max_speed = std::max(max_speed, P.v[p].norm());
  return cfl * sim.mesh.h_min / (wave_speed + max_speed);  // (A.13)
}

bool step(Simulation& sim, double dt) {
  mark_active_nodes(sim);
  particles_to_grid(sim);
  update_grid_accelerations(sim, dt);
  update_particle_velocities(sim, dt);
  remap_grid_velocities(sim);
  update_particle_kinematics(sim, dt);
  if (sim.evs) enhance_volumetric_strain(sim);
  update_stresses(sim);
  const bool ok = relocate_particles(sim) && sim.bad_particle < 0;
  sim.time += dt;
  ++sim.steps;
  return ok;
}

void mark_active_nodes(Simulation& sim) {
  ++sim.stamp;
  const Particles& P = sim.particles;
  const long n = static_cast<long>(P.size());
  const int32_t stamp = sim.stamp;
#pragma omp parallel for schedule(static)
  for (long p = 0; p < n; ++p)
    for (int32_t i : sim.mesh.triangles[P.element[p]])
      std::atomic_ref<int32_t>(sim.node_stamp[i]).store(stamp, std::memory_order_relaxed);
  auto& active = sim.fields[0].active;
  active.clear();
  for (int32_t i = 0; i < static_cast<int32_t>(sim.node_stamp.size()); ++i)
    if (sim.node_stamp[i] == stamp) active.push_back(i);
}

void particles_to_grid(Simulation& sim) {
  const Particles& P = sim.particles;
  const Mesh& mesh = sim.mesh;
  const long n = static_cast<long>(P.size());
  const long moving = static_cast<long>(P.moving_count);
  const Vec2 g = gravity_at(sim, sim.time);
  const bool gradients = sim.contact;
#pragma omp parallel
  {
    auto& buffers = sim.buffers[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long p = 0; p < n; ++p) {
      const int32_t e = P.element[p];
      const auto& nodes = mesh.triangles[e];
      const Vec3 N = mesh.weights(e, P.x[p]);
      NodeBuffer& b = buffers[field_of(sim, P.body[p])];
      const double m = P.m[p];
      if (p >= moving) {  // a fixed body lends its mass (and, for contact, its normals) only
        for (int k = 0; k < 3; ++k) {
          b.m[nodes[k]] += N[k] * m;
          if (gradients) b.mass_gradient[nodes[k]] += m * mesh.gradient(e, k);
        }
        continue;
      }
      const Vec2 mv = m * P.v[p];
      const Vec4& s = P.sigma[p];
      const double V = P.volume[p];
      for (int k = 0; k < 3; ++k) {
        const Vec2 dN = mesh.gradient(e, k);
        const int32_t i = nodes[k];
        b.m[i] += N[k] * m;                                       // (A.6), lumped
        b.p[i] += N[k] * mv;
        b.f[i] += N[k] * m * g                                    // (A.7)
                  - V * Vec2(s[0] * dN.x() + s[3] * dN.y(), s[3] * dN.x() + s[1] * dN.y());  // (A.8)
        if (gradients) b.mass_gradient[i] += m * dN;
      }
    }
    // Reduce the per-thread buffers on the active nodes, and clear them for the next step.
    const auto& active = sim.fields[0].active;
    const long count = static_cast<long>(active.size());
    const std::size_t threads = sim.buffers.size();
#pragma omp for schedule(static)
    for (long k = 0; k < count; ++k) {
      const int32_t i = active[k];
      for (std::size_t field = 0; field < sim.fields.size(); ++field) {
        Grid& grid = sim.fields[field];
        double m = 0;
        Vec2 mom = Vec2::Zero(), force = Vec2::Zero(), gradient = Vec2::Zero();
        for (std::size_t t = 0; t < threads; ++t) {
          NodeBuffer& b = sim.buffers[t][field];
          m += b.m[i];
          mom += b.p[i];
          force += b.f[i];
          b.m[i] = 0;
          b.p[i].setZero();
          b.f[i].setZero();
          if (gradients) {
            gradient += b.mass_gradient[i];
            b.mass_gradient[i].setZero();
          }
        }
        grid.m[i] = m;
        grid.p[i] = mom;
        grid.f[i] = force;
        if (gradients) grid.mass_gradient[i] = gradient;
      }
    }
  }
}

void update_grid_accelerations(Simulation& sim, double dt) {
  const auto& active = sim.fields[0].active;
  const long count = static_cast<long>(active.size());
  const double alpha = sim.damping;
  // With contact, fields[0] only carries the active-node list: every particle maps to its body.
  for (std::size_t field = sim.contact ? 1 : 0; field < sim.fields.size(); ++field) {
    Grid& grid = sim.fields[field];
    const bool fixed_body = field > 0 && sim.body_fixed[field - 1];
#pragma omp parallel for schedule(static)
    for (long k = 0; k < count; ++k) {
      const int32_t i = active[k];
      if (grid.m[i] <= 0 || fixed_body) {
        grid.a[i].setZero();
        grid.p[i].setZero();
        continue;
      }
      Vec2 f = grid.f[i];
      if (alpha > 0) {  // local damping against the sign of the nodal velocity (Cundall)
        const Vec2& mom = grid.p[i];
        for (int d = 0; d < 2; ++d) f[d] -= alpha * std::abs(f[d]) * (mom[d] > 0 ? 1.0 : mom[d] < 0 ? -1.0 : 0.0);
      }
      // The constraint holds for the velocity at the end of the step: a constrained node's
      // acceleration is whatever brings its velocity to the allowed one in dt. Zeroing the
      // acceleration alone would leave the particles beside a fixed node with whatever velocity
      // they carried in, moving nowhere but counted as kinetic energy.
      const Vec2 v = grid.p[i] / grid.m[i];
      Vec2 v_end = v + dt * f / grid.m[i];
      constrain(sim.constraints, i, v_end);
      grid.a[i] = dt > 0 ? Vec2((v_end - v) / dt) : Vec2(f / grid.m[i]);
      if (dt == 0) constrain(sim.constraints, i, grid.a[i]);
    }
  }
  if (sim.contact) apply_contact(sim, dt);
}

void update_particle_velocities(Simulation& sim, double dt) {
  Particles& P = sim.particles;
  const Mesh& mesh = sim.mesh;
  const long moving = static_cast<long>(P.moving_count);
#pragma omp parallel
  {
    auto& buffers = sim.buffers[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      const int32_t e = P.element[p];
      const auto& nodes = mesh.triangles[e];
      const Vec3 N = mesh.weights(e, P.x[p]);
      const int field = field_of(sim, P.body[p]);
      const Grid& grid = sim.fields[field];
      Vec2 a = Vec2::Zero();
      for (int k = 0; k < 3; ++k) a += N[k] * grid.a[nodes[k]];
      P.v[p] += dt * a;  // (A.10)
      // Momentum for the remap (A.11), scattered in the same pass.
      NodeBuffer& b = buffers[field];
      const Vec2 mv = P.m[p] * P.v[p];
      for (int k = 0; k < 3; ++k) b.p[nodes[k]] += N[k] * mv;
    }
  }
}

void remap_grid_velocities(Simulation& sim) {
  const auto& active = sim.fields[0].active;
  const long count = static_cast<long>(active.size());
  const std::size_t threads = sim.buffers.size();
#pragma omp parallel for schedule(static)
  for (long k = 0; k < count; ++k) {
    const int32_t i = active[k];
    for (std::size_t field = sim.contact ? 1 : 0; field < sim.fields.size(); ++field) {
      Grid& grid = sim.fields[field];
      Vec2 mom = Vec2::Zero();
      for (std::size_t t = 0; t < threads; ++t) {
        mom += sim.buffers[t][field].p[i];
        sim.buffers[t][field].p[i].setZero();
      }
      const bool fixed_body = field > 0 && sim.body_fixed[field - 1];
      grid.v[i] = grid.m[i] > 0 && !fixed_body ? Vec2(mom / grid.m[i]) : Vec2::Zero();  // (A.11)
      constrain(sim.constraints, i, grid.v[i]);
    }
  }
  if (sim.contact) apply_contact_velocities(sim);
}

void update_particle_kinematics(Simulation& sim, double dt) {
  Particles& P = sim.particles;
  const Mesh& mesh = sim.mesh;
  const long moving = static_cast<long>(P.moving_count);
#pragma omp parallel for schedule(static)
  for (long p = 0; p < moving; ++p) {
    const int32_t e = P.element[p];
    const auto& nodes = mesh.triangles[e];
    const Vec3 N = mesh.weights(e, P.x[p]);
    const Grid& grid = sim.fields[field_of(sim, P.body[p])];
    Vec2 v = Vec2::Zero();
    Eigen::Matrix2d L = Eigen::Matrix2d::Zero();  // velocity gradient, L_ab = dv_a / dx_b
    for (int k = 0; k < 3; ++k) {
      const Vec2& vi = grid.v[nodes[k]];
      v += N[k] * vi;
      L += vi * mesh.gradient(e, k).transpose();
    }
    P.x[p] += dt * v;  // (A.12)
    P.v[p] += sim.pic_fraction * (v - P.v[p]);  // FLIP-PIC blend; no-op for the pure FLIP of (A.10)
    P.d_eps[p] = Vec4(dt * L(0, 0), dt * L(1, 1), 0, 0.5 * dt * (L(0, 1) + L(1, 0)));
    // Jaumann rate: sigma += W sigma - sigma W with the spin w = dt (L_xy - L_yx) / 2.
    const double w = 0.5 * dt * (L(0, 1) - L(1, 0));
    Vec4& s = P.sigma[p];
    const double rotation_xx = 2 * w * s[3], rotation_xy = w * (s[1] - s[0]);
    s[0] += rotation_xx;
    s[1] -= rotation_xx;
    s[3] += rotation_xy;
  }
}

void enhance_volumetric_strain(Simulation& sim) {
  // Detournay and Dzik (2006): element volumetric strain increment (volume-weighted over its
  // particles) -> nodes (area-weighted over active elements) -> back to each element from its
  // three nodes -> replaces the volumetric part of each particle's increment.
  Particles& P = sim.particles;
  const Mesh& mesh = sim.mesh;
  const long moving = static_cast<long>(P.moving_count);
  std::fill(sim.element_strain.begin(), sim.element_strain.end(), 0.0);
  std::fill(sim.element_volume.begin(), sim.element_volume.end(), 0.0);
#pragma omp parallel for schedule(static)
  for (long p = 0; p < moving; ++p) {
    const int32_t e = P.element[p];
    const double V = P.volume[p];
    std::atomic_ref<double>(sim.element_strain[e]).fetch_add(V * (P.d_eps[p][0] + P.d_eps[p][1]),
                                                             std::memory_order_relaxed);
    std::atomic_ref<double>(sim.element_volume[e]).fetch_add(V, std::memory_order_relaxed);
  }
  for (int32_t i : sim.fields[0].active) sim.node_strain[i] = sim.node_area[i] = 0;
  const long elements = static_cast<long>(mesh.element_count());
  for (long e = 0; e < elements; ++e) {
    if (sim.element_volume[e] <= 0) continue;
    const double strain = sim.element_strain[e] / sim.element_volume[e];
    for (int32_t i : mesh.triangles[e]) {
      sim.node_strain[i] += mesh.area[e] * strain;
      sim.node_area[i] += mesh.area[e];
    }
  }
#pragma omp parallel for schedule(static)
  for (long p = 0; p < moving; ++p) {
    const auto& nodes = mesh.triangles[P.element[p]];
    double smoothed = 0;
    for (int32_t i : nodes) smoothed += sim.node_strain[i] / sim.node_area[i];
    smoothed /= 3;
    Vec4& d = P.d_eps[p];
    const double correction = 0.5 * (smoothed - (d[0] + d[1]));  // in-plane, so d_eps_zz stays 0
    d[0] += correction;
    d[1] += correction;
  }
}

void update_stresses(Simulation& sim) {
  Particles& P = sim.particles;
  const long moving = static_cast<long>(P.moving_count);
  long bad = -1;
#pragma omp parallel for schedule(static) reduction(max : bad)
  for (long p = 0; p < moving; ++p) {
    const MaterialState& material = sim.materials[sim.material_of_body[P.body[p]]];
    const Vec4& d = P.d_eps[p];
    P.eps_p[p] += update_stress(material, P.sigma[p], d);
    P.volume[p] *= 1 + d[0] + d[1] + d[2];
    if (!std::isfinite(P.sigma[p].sum() + P.x[p].sum() + P.v[p].sum()) || !(P.volume[p] > 0)) bad = std::max(bad, p);
  }
  sim.bad_particle = bad;
}

bool relocate_particles(Simulation& sim) {
  Particles& P = sim.particles;
  const long moving = static_cast<long>(P.moving_count);
  long lost = -1;
#pragma omp parallel for schedule(static) reduction(max : lost)
  for (long p = 0; p < moving; ++p) {
    const int32_t e = locate(sim.mesh, P.element[p], P.x[p]);
    if (e < 0) lost = std::max(lost, p);
    else P.element[p] = e;
  }
  sim.lost_particle = lost;
  return lost < 0;
}

std::vector<Vec2> grid_velocity_at_particles(const Simulation& sim) {
  const Particles& P = sim.particles;
  std::vector<Vec2> velocity(P.size(), Vec2::Zero());
  if (sim.steps == 0) return P.v;  // no grid field yet: the initial velocities
  const long moving = static_cast<long>(P.moving_count);
#pragma omp parallel for schedule(static)
  for (long p = 0; p < moving; ++p) {
    const int32_t e = P.element[p];
    const Vec3 N = sim.mesh.weights(e, P.x[p]);
    const Grid& grid = sim.fields[field_of(sim, P.body[p])];
    for (int k = 0; k < 3; ++k) velocity[p] += N[k] * grid.v[sim.mesh.triangles[e][k]];
  }
  return velocity;
}

Energies energies(const Simulation& sim) {
  const Particles& P = sim.particles;
  const long moving = static_cast<long>(P.moving_count);
  double kinetic = 0, potential = 0, strain = 0;
#pragma omp parallel for schedule(static) reduction(+ : kinetic, potential, strain)
  for (long p = 0; p < moving; ++p) {
    kinetic += 0.5 * P.m[p] * P.v[p].squaredNorm();
    potential -= P.m[p] * sim.gravity.dot(P.x[p]);
    strain += P.volume[p] * elastic_energy_density(sim.materials[sim.material_of_body[P.body[p]]], P.sigma[p]);
  }
  // The kinetic energy of the velocity field that moves the material (A.12): the grid's, with
  // lumped masses. Particle (FLIP) velocities also carry components the grid cannot see; they
  // move nothing and would keep a deposit at rest from ever looking so.
  double grid_kinetic = 0;
  const auto& active = sim.fields[0].active;
  const long count = static_cast<long>(active.size());
  for (std::size_t field = sim.contact ? 1 : 0; field < sim.fields.size(); ++field) {
    const Grid& grid = sim.fields[field];
#pragma omp parallel for schedule(static) reduction(+ : grid_kinetic)
    for (long k = 0; k < count; ++k) grid_kinetic += 0.5 * grid.m[active[k]] * grid.v[active[k]].squaredNorm();
  }
  return {kinetic, potential, strain, grid_kinetic};
}

}  // namespace talus::solver
