// The explicit step on structured meshes made in code: shape functions, conservation in the
// grid transfers, free fall, rigid motion, and an elastic column under gravity.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "solver/step/step.hpp"
#include "support/test_support.hpp"

using namespace talus;
using namespace talus::solver;
using talus::testing::add_box_body;
using talus::testing::elastic;
using talus::testing::fix_base_roll_sides;
using talus::testing::rectangle_mesh;
using talus::testing::set_run;

namespace {

// A mesh with its nodes jittered, so that no test relies on right angles.
Model jittered_mesh(int nx, int ny, double h, unsigned seed) {
  Model model = rectangle_mesh(0, 0, nx, ny, h);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.2 * h, 0.2 * h);
  for (int j = 1; j < ny; ++j)
    for (int i = 1; i < nx; ++i) model.nodes[j * (nx + 1) + i] += Eigen::Vector2d(jitter(random), jitter(random));
  return model;
}

double total_mass(const Grids& grids) {
  double m = 0;
  for (int32_t i : grids.active) m += grids.fields[0].m[i];
  return m;
}

// The first phases of step(), called as it calls them: the active nodes, then P2G (A.6)-(A.8).
void map_to_grid(Simulation& sim) {
  Scratch& s = sim.scratch;
  const int threads = sim.config.threads;
  mark_active_nodes(s.stencil, sim.particles.size(), s.node_stamp, s.stamp, s.grids, threads);
  particles_to_grid({sim.particles, s.stencil, sim.config.mesh.nodes, gravity_at(sim.config, sim.time), {}, {}}, s.grids,
                    s.buffers, threads);
}

}  // namespace

TEST(ShapeFunctions, PartitionOfUnityZeroGradientSumAndLinearExactness) {
  Model model = jittered_mesh(6, 5, 0.3, 7);
  const Mesh mesh = build_mesh(model);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> unit(0, 1);
  const auto linear = [](const Vec2& x) { return 1.5 - 2.0 * x.x() + 0.75 * x.y(); };
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    const auto& t = mesh.triangles[e];
    double a = unit(random), b = unit(random) * (1 - a);
    const Vec2 x = a * mesh.nodes[t[0]] + b * mesh.nodes[t[1]] + (1 - a - b) * mesh.nodes[t[2]];
    const Vec3 N = mesh.weights(static_cast<int32_t>(e), x);
    EXPECT_NEAR(N.sum(), 1.0, 1e-13);
    EXPECT_NEAR(N[0], a, 1e-12);
    EXPECT_NEAR(N[1], b, 1e-12);
    Vec2 gradient_sum = Vec2::Zero(), gradient_of_linear = Vec2::Zero();
    double interpolated = 0;
    for (int k = 0; k < 3; ++k) {
      gradient_sum += mesh.gradient(static_cast<int32_t>(e), k);
      gradient_of_linear += linear(mesh.nodes[t[k]]) * mesh.gradient(static_cast<int32_t>(e), k);
      interpolated += N[k] * linear(mesh.nodes[t[k]]);
    }
    EXPECT_NEAR(gradient_sum.norm(), 0.0, 1e-12);
    EXPECT_NEAR(interpolated, linear(x), 1e-12);
    EXPECT_NEAR(gradient_of_linear.x(), -2.0, 1e-11);
    EXPECT_NEAR(gradient_of_linear.y(), 0.75, 1e-11);
  }
}

TEST(ShapeFunctions, NeighbourWalkFindsTheContainingElement) {
  Model model = jittered_mesh(8, 8, 0.25, 11);
  const Mesh mesh = build_mesh(model);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> coordinate(0.01, 1.99);
  for (int trial = 0; trial < 500; ++trial) {
    const Vec2 x(coordinate(random), coordinate(random));
    const int32_t e = locate(mesh, 0, x);
    ASSERT_GE(e, 0);
    EXPECT_GE(mesh.weights(e, x).minCoeff(), -1e-12);
  }
  EXPECT_EQ(locate(mesh, 0, Vec2(2.5, 1.0)), -1);  // outside the domain
}

TEST(GridTransfer, ParticleToGridConservesMassAndMomentum) {
  Model model = jittered_mesh(10, 10, 0.1, 13);
  add_box_body(model, "block", elastic(1500, 1e6, 0.3), 0.2, 0.8, 0.2, 0.7);
  std::mt19937 random(17);
  std::normal_distribution<double> speed(0, 1);
  Vec2 momentum = Vec2::Zero();
  double mass = 0;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    model.velocity[p] = Vec2(speed(random), speed(random));
    momentum += model.mass[p] * model.velocity[p];
    mass += model.mass[p];
  }
  set_run(model, 1.0);
  Simulation sim = make_simulation(model, 2);
  map_to_grid(sim);
  const Grids& grids = sim.scratch.grids;
  const Grid& grid = grids.fields[0];
  Vec2 grid_momentum = Vec2::Zero();
  for (int32_t i : grids.active) grid_momentum += grid.p[i];
  EXPECT_NEAR(total_mass(grids), mass, 1e-13 * mass);
  EXPECT_NEAR((grid_momentum - momentum).norm(), 0.0, 1e-12 * mass);

  // G2P with zero acceleration, then the remap (A.11): momentum is carried back unchanged.
  Scratch& s = sim.scratch;
  const Config& c = sim.config;
  update_grid_accelerations(c.constraints, c.body_fixed, c.damping, 0.0, s.grids, c.threads);
  update_particle_velocities(sim.particles, s.stencil, c.mesh.nodes, c.transfer, 0.0, s.grids, s.buffers, c.threads);
  remap_grid_velocities(c.constraints, c.body_fixed, s.grids, s.buffers, c.threads);
  Vec2 remapped = Vec2::Zero();
  for (int32_t i : grids.active) remapped += grid.m[i] * grid.v[i];
  EXPECT_NEAR((remapped - momentum).norm(), 0.0, 1e-12 * mass);
}

TEST(GridTransfer, InternalForcesSumToZero) {
  // Newton's third law on the grid: internal forces of any stress field add up to nothing.
  Model model = jittered_mesh(8, 8, 0.125, 19);
  add_box_body(model, "block", elastic(1000, 1e6, 0.3), 0.1, 0.9, 0.1, 0.9);
  std::mt19937 random(23);
  std::normal_distribution<double> stress(0, 1e4);
  for (auto& s : model.stress) s = Vec4(stress(random), stress(random), stress(random), stress(random));
  set_run(model, 1.0);
  Simulation sim = make_simulation(model, 2);
  map_to_grid(sim);
  const Grids& grids = sim.scratch.grids;
  Vec2 total = Vec2::Zero();
  double scale = 0;
  for (int32_t i : grids.active) total += grids.fields[0].f[i], scale += grids.fields[0].f[i].norm();
  EXPECT_LT(total.norm(), 1e-12 * scale);
}

TEST(TimeStep, FreeFallFollowsTheDiscreteSolutionAndConverges) {
  // Semi-implicit Euler: v_n = n dt g and x_n = x_0 + g dt^2 n (n + 1) / 2 = x_0 + g t (t + dt) / 2,
  // which tends to 0.5 g t^2 as dt -> 0.
  const Vec2 g(0, -9.81);
  double previous_error = 0;
  for (double dt : {1e-3, 5e-4, 2.5e-4}) {
    Model model = jittered_mesh(10, 20, 0.1, 29);
    add_box_body(model, "block", elastic(2000, 1e6, 0.25), 0.3, 0.7, 1.4, 1.8);
    set_run(model, 0.2, g);
    Simulation sim = make_simulation(model, 2);
    const std::vector<Vec2> start = sim.particles.x;
    const int steps = static_cast<int>(std::lround(0.2 / dt));
    for (int n = 0; n < steps; ++n) ASSERT_TRUE(step(sim, dt));
    const double t = steps * dt;
    double worst_discrete = 0, worst_exact = 0, worst_stress = 0;
    for (std::size_t p = 0; p < sim.particles.size(); ++p) {
      const Vec2 moved = sim.particles.x[p] - start[p];
      worst_discrete = std::max(worst_discrete, (moved - 0.5 * g * t * (t + dt)).norm());
      worst_exact = std::max(worst_exact, (moved - 0.5 * g * t * t).norm());
      worst_stress = std::max(worst_stress, sim.particles.sigma[p].norm());
      EXPECT_NEAR((sim.particles.v[p] - g * t).norm(), 0.0, 1e-11);
    }
    EXPECT_LT(worst_discrete, 1e-12);
    EXPECT_LT(worst_stress, 1e-6);  // a rigid motion strains nothing
    EXPECT_NEAR(worst_exact, 0.5 * g.norm() * t * dt, 1e-12);
    if (previous_error > 0) {  // first order in dt
      EXPECT_NEAR(worst_exact / previous_error, 0.5, 1e-6);
    }
    previous_error = worst_exact;
  }
}

TEST(TimeStep, RigidTranslationMakesNoStrainAndConservesMomentum) {
  Model model = jittered_mesh(12, 12, 0.1, 31);
  add_box_body(model, "block", elastic(1000, 1e7, 0.3), 0.2, 0.6, 0.3, 0.7);
  for (auto& v : model.velocity) v = Vec2(0.8, -0.3);
  set_run(model, 0.2);
  Simulation sim = make_simulation(model, 2);
  const double dt = stable_time_step(sim, 0.5);
  for (int n = 0; n < 200; ++n) ASSERT_TRUE(step(sim, dt));
  for (std::size_t p = 0; p < sim.particles.size(); ++p) {
    EXPECT_LT(sim.particles.sigma[p].norm(), 1e-6);
    EXPECT_NEAR((sim.particles.v[p] - Vec2(0.8, -0.3)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(sim.particles.eps_p[p], 0.0, 0.0);
  }
}

TEST(TimeStep, ElasticImpactConservesMomentumWithoutBoundaries) {
  // Two blocks colliding in one velocity field, far from any boundary: no external force, so
  // the total momentum stays what it was to round-off, through impact and rebound.
  Model model = jittered_mesh(20, 10, 0.1, 37);
  add_box_body(model, "left", elastic(1000, 1e6, 0.3), 0.3, 0.8, 0.3, 0.7);
  add_box_body(model, "right", elastic(1000, 1e6, 0.3), 1.1, 1.6, 0.3, 0.7);
  Vec2 momentum = Vec2::Zero();
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    model.velocity[p] = model.body[p] == 0 ? Vec2(2.0, 0.0) : Vec2(-1.0, 0.5);
    momentum += model.mass[p] * model.velocity[p];
  }
  model.contact.enabled = false;
  set_run(model, 0.3);
  Simulation sim = make_simulation(model, 2);
  for (int n = 0; n < 400; ++n) ASSERT_TRUE(step(sim, stable_time_step(sim, 0.4)));
  Vec2 after = Vec2::Zero();
  for (std::size_t p = 0; p < sim.particles.size(); ++p) after += sim.particles.m[p] * sim.particles.v[p];
  EXPECT_LT((after - momentum).norm(), 1e-10 * momentum.norm());
}

TEST(TimeStep, ElasticColumnUnderGravitySettlesToTheLithostaticStress) {
  // A column of height H on a fixed base with roller sides, damped to rest. The weight above a
  // material point gives sigma_yy = -rho g (H - Y) at its initial height Y (tension positive).
  // Linear triangles carry one stress per element, so a single particle can differ from it by
  // up to rho g h / 2; averaged over each layer of elements the stress must be within 2% of
  // rho g H. Poisson's ratio 0 makes the column one-dimensional.
  const double H = 1.0, rho = 1000, g = 10, h = 0.05;
  const int layers = static_cast<int>(std::lround(H / h));
  Model model = rectangle_mesh(0, 0, 4, layers + 4, h);
  add_box_body(model, "column", elastic(rho, 1e6, 0.0), 0, 0.2, 0, H);
  fix_base_roll_sides(model);
  set_run(model, 1.5, Vec2(0, -g));
  model.run.damping = 0.1;
  Simulation sim = make_simulation(model, 2);
  while (sim.time < model.run.end_time) ASSERT_TRUE(step(sim, stable_time_step(sim, 0.5)));

  std::vector<double> error_sum(layers, 0.0);
  std::vector<int> count(layers, 0);
  for (std::size_t p = 0; p < sim.particles.size(); ++p) {
    const double Y = model.position[sim.particles.id[p]].y();
    const int layer = std::min(layers - 1, static_cast<int>(Y / h));
    error_sum[layer] += sim.particles.sigma[p][1] + rho * g * (H - Y);
    ++count[layer];
  }
  for (int layer = 0; layer < layers; ++layer) {
    ASSERT_GT(count[layer], 0);
    EXPECT_LT(std::abs(error_sum[layer] / count[layer]), 0.02 * rho * g * H) << "layer " << layer;
  }
  EXPECT_LT(energies(sim).kinetic, 1e-6 * rho * g * H * H);
}

TEST(TimeStep, BlockSlidesFreelyAlongAnInclinedRoller) {
  // The whole mesh rotated by theta: its base becomes an incline whose nodes are rollers with
  // the incline's normal. Roller reactions are normal and internal forces cancel, so the centre
  // of mass moves along the incline exactly as a frictionless point mass: with a fixed step,
  // s_n = g sin(theta) dt^2 n (n + 1) / 2 down the slope, and not at all into it on average.
  const double theta = 25 * M_PI / 180, g = 9.81, dt = 2e-4;
  Model model = rectangle_mesh(0, 0, 24, 8, 0.1);
  add_box_body(model, "block", elastic(1500, 2e6, 0.3), 1.6, 2.2, 0.0, 0.3);
  const Eigen::Rotation2Dd rotation(theta);
  for (auto& x : model.nodes) x = rotation * x;
  for (auto& x : model.position) x = rotation * x;
  const Vec2 along = rotation * Vec2(1, 0), normal = rotation * Vec2(0, 1);
  for (int32_t i : model.node_sets["bottom"]) {
    model.roller_nodes.push_back(i);
    model.roller_normals.push_back(normal);
  }
  set_run(model, 0.3, Vec2(0, -g));
  Simulation sim = make_simulation(model, 2);
  double mass = 0;
  Vec2 start = Vec2::Zero();
  for (std::size_t p = 0; p < sim.particles.size(); ++p) mass += sim.particles.m[p], start += sim.particles.m[p] * sim.particles.x[p];
  const int steps = 1000;
  for (int n = 0; n < steps; ++n) ASSERT_TRUE(step(sim, dt));
  Vec2 centre = Vec2::Zero();
  for (std::size_t p = 0; p < sim.particles.size(); ++p) centre += sim.particles.m[p] * sim.particles.x[p];
  const Vec2 moved = (centre - start) / mass;
  const double exact = -g * std::sin(theta) * dt * dt * steps * (steps + 1) / 2;
  EXPECT_NEAR(moved.dot(along), exact, 1e-9 * std::abs(exact));
  // Into the incline only as far as the elastic block's own settlement, rho g h / E' ~ 1e-3 x h.
  EXPECT_LT(std::abs(moved.dot(normal)), 1e-3);
}

TEST(Constraints, AFrictionNodeRemovesTheApproachAndResistsSlidingByCoulomb) {
  Model model = rectangle_mesh(0, 0, 2, 2, 1.0);
  model.friction_nodes = {0};
  model.friction_normals = {Vec2(0, -2)};  // out of the domain, normalised when read
  model.friction_coefficients = {0.5};
  const Constraints c = build_constraints(model);
  Vec2 v(1.0, -0.5);  // into the base at 0.5: slides on at 1 - 0.5 x 0.5
  constrain(c, 0, v);
  EXPECT_NEAR(v.x(), 0.75, 1e-15);
  EXPECT_EQ(v.y(), 0);
  v = Vec2(0.2, -0.5);  // friction 0.25 > 0.2: sticks
  constrain(c, 0, v);
  EXPECT_EQ(v, Vec2::Zero());
  v = Vec2(1.0, 0.5);  // leaving the base: free
  constrain(c, 0, v);
  EXPECT_EQ(v, Vec2(1.0, 0.5));
  Vec2 delta(0.3, -0.4);  // a contact correction keeps only its tangential part
  constrain_change(c, 0, delta);
  EXPECT_EQ(delta, Vec2(0.3, 0));
}

TEST(TimeStep, BlockSlidesOnAFrictionBaseAsCoulombSays) {
  // As BlockSlidesFreelyAlongAnInclinedRoller, with the incline's nodes frictional. At
  // theta = 25 deg and mu = 0.2 < tan theta the block slides at a = g (sin theta - mu cos theta):
  // the normal reaction builds up through the elastic block in ~ 0.01 s and then oscillates
  // about the weight, so the distance after 0.4 s is compared within 3 %. With mu = 0.6 >
  // tan theta it stays put.
  const double theta = 25 * M_PI / 180, g = 9.81, dt = 2e-4;
  const Eigen::Rotation2Dd rotation(theta);
  const Vec2 along = rotation * Vec2(1, 0), normal = rotation * Vec2(0, 1);
  const int steps = 2000;
  auto slide = [&](double mu) {
    Model model = rectangle_mesh(0, 0, 24, 8, 0.1);
    add_box_body(model, "block", elastic(1500, 2e6, 0.3), 1.6, 2.2, 0.0, 0.3);
    for (auto& x : model.nodes) x = rotation * x;
    for (auto& x : model.position) x = rotation * x;
    for (int32_t i : model.node_sets["bottom"]) {
      model.friction_nodes.push_back(i);
      model.friction_normals.push_back(-normal);
      model.friction_coefficients.push_back(mu);
    }
    set_run(model, 0.5, Vec2(0, -g));
    Simulation sim = make_simulation(model, 2);
    double mass = 0;
    Vec2 start = Vec2::Zero();
    for (std::size_t p = 0; p < sim.particles.size(); ++p)
      mass += sim.particles.m[p], start += sim.particles.m[p] * sim.particles.x[p];
    for (int n = 0; n < steps; ++n) EXPECT_TRUE(step(sim, dt));
    Vec2 centre = Vec2::Zero();
    for (std::size_t p = 0; p < sim.particles.size(); ++p) centre += sim.particles.m[p] * sim.particles.x[p];
    return Vec2((centre - start) / mass);
  };
  const double t = steps * dt, mu = 0.2;
  const double exact = -0.5 * g * (std::sin(theta) - mu * std::cos(theta)) * t * t;
  const Vec2 moved = slide(mu);
  EXPECT_NEAR(moved.dot(along), exact, 0.03 * std::abs(exact));
  EXPECT_LT(std::abs(moved.dot(normal)), 1e-3);
  // Stuck: along the incline it moves only by the elastic block's shear and settlement under
  // gravity applied at once (dynamic: twice the static rho g H / E' ~ 2 mm), far below the
  // 0.33 m of a frictionless slide.
  const Vec2 stuck = slide(0.6);
  const double free_slide = 0.5 * g * std::sin(theta) * t * t;
  EXPECT_LT(std::abs(stuck.dot(along)), 0.02 * free_slide) << stuck.transpose();
  EXPECT_LT(std::abs(stuck.dot(normal)), 5e-3) << stuck.transpose();
}

TEST(GridTransfer, RunSumsEqualTheParticleByParticleSums) {
  // P2G and the remap's scatter add a run's sums (particles that share a stencil row) to each
  // node once. Against the per-particle sums of (A.6)-(A.8) and (A.11), with the particles moved
  // after their sort so that some runs are broken and some cells' particles are not contiguous,
  // and two threads so that a thread's share can start in the middle of a run.
  Model model = jittered_mesh(8, 8, 0.125, 29);
  add_box_body(model, "block", elastic(1200, 1e6, 0.3), 0.15, 0.85, 0.15, 0.85);
  std::mt19937 random(31);
  std::normal_distribution<double> normal(0, 1);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    model.velocity[p] = Vec2(normal(random), normal(random));
    model.stress[p] = 1e4 * Vec4(normal(random), normal(random), normal(random), normal(random));
  }
  set_run(model, 1.0);
  Simulation sim = make_simulation(model, 2);
  Particles& P = sim.particles;
  std::uniform_real_distribution<double> shift(-0.06, 0.06);
  for (std::size_t p = 0; p < P.size(); ++p) P.x[p] += Vec2(shift(random), shift(random));
  ASSERT_LT(relocate_particles(sim.config.mesh, P, sim.scratch.stencil, 2), 0);
  // Cells whose particles form more than one run (not contiguous in memory).
  std::vector<int> runs_of_cell(sim.config.mesh.element_count(), 0);
  for (std::size_t p = 0; p < P.size(); ++p)
    if (p == 0 || P.element[p] != P.element[p - 1]) ++runs_of_cell[P.element[p]];
  ASSERT_GT(std::count_if(runs_of_cell.begin(), runs_of_cell.end(), [](int runs) { return runs > 1; }), 5);

  map_to_grid(sim);
  const Stencil& S = sim.scratch.stencil;
  const std::size_t nodes = sim.config.mesh.nodes.size();
  const Vec2 g = gravity_at(sim.config, sim.time);
  std::vector<double> m(nodes, 0);
  std::vector<Vec2> momentum(nodes, Vec2::Zero()), force(nodes, Vec2::Zero());
  for (std::size_t p = 0; p < P.size(); ++p)
    for (int k = 0; k < S.width; ++k) {
      const int32_t i = S.nodes(p)[k];
      const double N = S.weights(p)[k];
      const Vec2& dN = S.gradients(p)[k];
      const Vec4& s = P.sigma[p];
      m[i] += N * P.m[p];
      momentum[i] += N * P.m[p] * P.v[p];
      force[i] += N * P.m[p] * g - P.volume[p] * Vec2(s[0] * dN.x() + s[3] * dN.y(), s[3] * dN.x() + s[1] * dN.y());
    }
  const Grid& grid = sim.scratch.grids.fields[0];
  double mass_scale = 0, momentum_scale = 0, force_scale = 0;
  for (int32_t i : sim.scratch.grids.active)
    mass_scale += m[i], momentum_scale += momentum[i].norm(), force_scale += force[i].norm();
  for (int32_t i : sim.scratch.grids.active) {
    EXPECT_NEAR(grid.m[i], m[i], 1e-14 * mass_scale);
    EXPECT_NEAR((grid.p[i] - momentum[i]).norm(), 0.0, 1e-14 * momentum_scale);
    EXPECT_NEAR((grid.f[i] - force[i]).norm(), 0.0, 1e-14 * force_scale);
  }

  // The velocity update with zero acceleration keeps v_p; the remap then divides the run sums
  // of m_p N_ip v_p by the mass: the per-particle momentum above over the same mass.
  Scratch& s = sim.scratch;
  const Config& c = sim.config;
  update_grid_accelerations(c.constraints, c.body_fixed, c.damping, 0.0, s.grids, c.threads);
  update_particle_velocities(P, S, c.mesh.nodes, c.transfer, 0.0, s.grids, s.buffers, c.threads);
  remap_grid_velocities(c.constraints, c.body_fixed, s.grids, s.buffers, c.threads);
  for (int32_t i : s.grids.active) {
    if (c.constraints.kind[i] != Constraint::Free) continue;
    EXPECT_NEAR((grid.m[i] * grid.v[i] - momentum[i]).norm(), 0.0, 1e-14 * momentum_scale);
  }
}

TEST(MixedIntegration, CellsInsideTheMaterialTakeTheirAreaAndCellsAtItsSurfaceTheirParticles) {
  // A block under a uniform stress, its particles' volumes scaled by J as if it had been
  // compressed or dilated without a particle leaving its cell. The internal force on the nodes of
  // an edge adds up to sigma_xx times the edge's height (a vertical edge) or sigma_yy times its
  // width (a horizontal one), each cell adding its quadrature weight over h. Integrating over the
  // particles gives J times that. Mixed integration gives it exactly where the cells are inside
  // the material (fill J >= 0.9 in the cell and across its edges), and keeps the particles' J at
  // a free surface: on the block's top edge the row of triangles that has its top edge there
  // borders empty cells (J), the other half of the row does not (1), so the sum is (1 + J) / 2 of
  // the exact one. Where J < 0.9 no cell counts as full.
  const double h = 0.125, W = 1.0, H = 0.5, sxx = 3e4, syy = -2e4;
  Model model = rectangle_mesh(0, 0, 8, 6, h);  // 1 m x 0.75 m: the block leaves the top row empty
  add_box_body(model, "block", elastic(1000, 1e6, 0.3), 0, W, 0, H);
  for (auto& s : model.stress) s = Vec4(sxx, syy, 0.3 * (sxx + syy), 0);
  set_run(model, 1.0);
  model.run.full_cell_fill = 0.9;
  for (const double J : {0.95, 1.1, 0.85}) {
    Simulation sim = make_simulation(model, 2);
    Scratch& s = sim.scratch;
    const Config& c = sim.config;
    for (double& V : sim.particles.volume) V *= J;
    // x: the sum of f_x over the right side's nodes at y < H - h (below the block's top row of
    // cells, which borders the empty row); y: the sum of f_y over the top edge's nodes.
    auto edge_forces = [&](bool mixed) {
      if (mixed) full_cell_scales(c.mesh, sim.particles, c.full_cell_fill, s.cell_volume, s.cell_scale, c.threads);
      mark_active_nodes(s.stencil, sim.particles.size(), s.node_stamp, s.stamp, s.grids, c.threads);
      const std::vector<double> scale = mixed ? s.cell_scale : std::vector<double>{};
      particles_to_grid({sim.particles, s.stencil, c.mesh.nodes, Vec2::Zero(), {}, scale}, s.grids, s.buffers, c.threads);
      Vec2 sums = Vec2::Zero();
      for (int32_t i : s.grids.active) {
        const Vec2& x = c.mesh.nodes[i];
        const Vec2& f = s.grids.fields[0].f[i];
        if (std::abs(x.x() - W) < 1e-9 && x.y() < H - h - 1e-9) sums.x() += f.x();
        if (std::abs(x.y() - H) < 1e-9) sums.y() += f.y();
      }
      return sums;
    };
    // The right side's nodes at y = 0, h and 2h: the last column's two bottom rows of cells
    // (h each) and, of the third row, the triangle in which the node at 2h has a gradient
    // (h / 2): 2.5 h, from cells that all count as full.
    const Vec2 points = edge_forces(false), mixed = edge_forces(true);
    const Vec2 exact_points(-sxx * J * 2.5 * h, -syy * W * J);
    EXPECT_NEAR(points.x(), exact_points.x(), 1e-12 * std::abs(exact_points.x())) << "J = " << J;
    EXPECT_NEAR(points.y(), exact_points.y(), 1e-12 * std::abs(exact_points.y())) << "J = " << J;
    const bool full = J >= 0.9;
    EXPECT_NEAR(mixed.y(), -syy * W * (full ? (1 + J) / 2 : J), 1e-12 * std::abs(syy * W)) << "J = " << J;
    if (full) EXPECT_NEAR(mixed.x(), -sxx * 2.5 * h, 1e-12 * std::abs(sxx)) << "J = " << J;
    else EXPECT_NEAR(mixed.x(), points.x(), 1e-12 * std::abs(sxx)) << "J = " << J;
  }
}
