// APIC (Jiang et al. 2015) on the quadratic B-spline family (docs/shape-functions.md): its
// inertia D_p = sum_i N_ip (x_i - x_p)(x_i - x_p)^T is h^2 / 4 I for every particle, so the
// transfer P2G -> G2P carries an affine velocity field (a rigid rotation among them) exactly and
// conserves angular momentum, the particles' own plus their affine part,
//   L = sum_p m_p (x_p x v_p + (B_p)_yx - (B_p)_xy),  B_p = C_p D_p;
// and an elastic vibration keeps its energy.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "solver/step/step.hpp"
#include "solver/stress/stress.hpp"
#include "support/test_support.hpp"

namespace talus::solver {
namespace {

using testing::add_box_body;
using testing::crossed_rectangle_mesh;
using testing::elastic;

constexpr double kCell = 0.125;

// A block of 8 x 8 cells in the middle of a free 24 x 24 lattice (no boundary within reach),
// no gravity.
Model free_block(double youngs_modulus, Transfer transfer, ShapeFunctions family) {
  Model model = crossed_rectangle_mesh(0, 0, 24, 24, kCell);
  add_box_body(model, "block", elastic(1000, youngs_modulus, 0.3), 1.0, 2.0, 1.0, 2.0);
  testing::set_run(model, 1.0, Eigen::Vector2d::Zero());
  model.run.transfer = transfer;
  model.run.shape_functions = family;
  return model;
}

Vec4 as_vec4(const Eigen::Matrix2d& G) { return Vec4(G(0, 0), G(0, 1), G(1, 0), G(1, 1)); }

// v(x) = v0 + G x with C_p = G, no stress: after a step every particle has v0 + G x_p(start)
// and C_p = G, to round-off.
void expect_affine_field_kept(const Eigen::Matrix2d& G, const Vec2& v0,
                              ShapeFunctions family = ShapeFunctions::QuadraticBspline) {
  Model model = free_block(1e6, Transfer::Apic, family);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    model.velocity[p] = v0 + G * model.position[p];
    model.stress[p].setZero();
  }
  Simulation sim = make_simulation(model, 1);
  for (auto& C : sim.particles.C) C = as_vec4(G);
  const std::vector<Vec2> x = sim.particles.x;
  ASSERT_TRUE(step(sim, 1e-5));
  double velocity_error = 0, gradient_error = 0;
  const Particles& P = sim.particles;
  for (std::size_t p = 0; p < P.moving_count; ++p) {
    velocity_error = std::max(velocity_error, (P.v[p] - (v0 + G * x[p])).norm());
    gradient_error = std::max(gradient_error, (P.C[p] - as_vec4(G)).norm());
  }
  EXPECT_LT(velocity_error, 1e-12);
  EXPECT_LT(gradient_error, 1e-11);
}

TEST(ApicBspline, CarriesAnAffineVelocityFieldExactly) {
  Eigen::Matrix2d G;
  G << 0.4, -1.1, 0.7, -0.25;
  expect_affine_field_kept(G, Vec2(0.3, -0.2));
}

TEST(ApicBspline, CarriesARigidRotationExactly) {
  const double omega = 2.0;  // rad/s about the block's centre (1.5, 1.5)
  Eigen::Matrix2d W;
  W << 0, -omega, omega, 0;
  expect_affine_field_kept(W, -W * Vec2(1.5, 1.5));
}

// With CPDI on crossed triangles C_p = B_p D_p^-1 with each particle's own D_p (stencil.hpp,
// fill_cpdi): an affine field is carried exactly, since the weights reproduce affine fields.
TEST(ApicCpdi, CarriesAnAffineVelocityFieldExactly) {
  Eigen::Matrix2d G;
  G << 0.4, -1.1, 0.7, -0.25;
  expect_affine_field_kept(G, Vec2(0.3, -0.2), ShapeFunctions::Cpdi);
}

TEST(ApicCpdi, CarriesARigidRotationExactly) {
  const double omega = 2.0;
  Eigen::Matrix2d W;
  W << 0, -omega, omega, 0;
  expect_affine_field_kept(W, -W * Vec2(1.5, 1.5), ShapeFunctions::Cpdi);
}

// Each moving particle's APIC inertia D_p: for quadratic B-splines h^2 / 4 per axis (the inverse
// of Stencil::inverse_inertia), for CPDI its own sum_i S_ip (x_i - x_p)(x_i - x_p)^T from its
// stencil row.
std::vector<Eigen::Matrix2d> inertia(const Simulation& sim) {
  const Particles& P = sim.particles;
  const Stencil& S = sim.scratch.stencil;
  const Eigen::Matrix2d lattice = S.inverse_inertia.cwiseInverse().asDiagonal();
  std::vector<Eigen::Matrix2d> D(P.moving_count, lattice);
  if (S.family != ShapeFamily::LinearCpdi) return D;
  for (std::size_t p = 0; p < P.moving_count; ++p) {
    D[p].setZero();
    for (int k = 0; k < S.width; ++k) {
      const Vec2 r = sim.config.mesh.nodes[S.nodes(p)[k]] - P.x[p];
      D[p] += S.weights(p)[k] * r * r.transpose();
    }
  }
  return D;
}

Eigen::Matrix2d affine_of(const Particles& P, std::size_t p) {
  Eigen::Matrix2d C;
  C << P.C[p][0], P.C[p][1], P.C[p][2], P.C[p][3];
  return C;
}

// The total angular momentum about the origin of the particles' masses and velocities at the
// positions x, the affine part B_p = C_p D_p included.
double angular_momentum(const Particles& P, const std::vector<Vec2>& x, const std::vector<Eigen::Matrix2d>& D) {
  double L = 0;
  for (std::size_t p = 0; p < P.moving_count; ++p) {
    const Eigen::Matrix2d B = affine_of(P, p) * D[p];
    L += P.m[p] * (x[p].x() * P.v[p].y() - x[p].y() * P.v[p].x() + B(1, 0) - B(0, 1));
  }
  return L;
}

// A spinning block with random velocities and affine matrices on top.
Simulation spinning_block(double youngs_modulus, ShapeFunctions family = ShapeFunctions::QuadraticBspline) {
  Model model = free_block(youngs_modulus, Transfer::Apic, family);
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0, 0.2);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const Vec2 r = model.position[p] - Vec2(1.5, 1.5);
    model.velocity[p] = 3.0 * Vec2(-r.y(), r.x()) + Vec2(noise(random), noise(random));
    model.stress[p].setZero();
  }
  Simulation sim = make_simulation(model, 1);
  for (auto& C : sim.particles.C) C = Vec4(noise(random), noise(random), noise(random), noise(random));
  return sim;
}

// The transfers conserve it exactly: particles -> grid (the remap's grid holds the particles'
// new state) and grid -> particles, with no force, at the positions and inertias the step
// started from.
void expect_transfers_conserve_angular_momentum(ShapeFunctions family) {
  Simulation sim = spinning_block(1.0, family);  // stress-free and nearly rigid-free: no force in one step
  const std::vector<Vec2> x = sim.particles.x;
  const std::vector<Eigen::Matrix2d> D = inertia(sim);
  const double before = angular_momentum(sim.particles, x, D);
  ASSERT_GT(std::abs(before), 1.0);
  ASSERT_TRUE(step(sim, 1e-6));
  const double after = angular_momentum(sim.particles, x, D);
  const Grid& grid = sim.scratch.grids.fields[0];
  double on_grid = 0;
  for (const int32_t i : sim.scratch.grids.active) {
    const Vec2& xi = sim.config.mesh.nodes[i];
    on_grid += grid.m[i] * (xi.x() * grid.v[i].y() - xi.y() * grid.v[i].x());
  }
  EXPECT_LT(std::abs(after - before), 1e-6 * std::abs(before));  // the one force: E = 1 Pa over 1e-6 s
  EXPECT_LT(std::abs(on_grid - after), 1e-12 * std::abs(before));
}

TEST(ApicBspline, ItsTransfersConserveAngularMomentum) {
  expect_transfers_conserve_angular_momentum(ShapeFunctions::QuadraticBspline);
}

// Over 400 steps of a stressed, spinning block it drifts by less than 1e-4 of itself: the step
// moves a particle with the remapped grid velocity (A.12), not its own, which APIC's proof
// (Jiang et al. 2015) assumes (measured: 6e-6 of it).
TEST(ApicBspline, ConservesAngularMomentumOverARun) {
  Simulation sim = spinning_block(1e5);
  const double before = angular_momentum(sim.particles, sim.particles.x, inertia(sim));
  for (int k = 0; k < 400; ++k) ASSERT_TRUE(step(sim, stable_time_step(sim, 0.5)));
  EXPECT_LT(std::abs(angular_momentum(sim.particles, sim.particles.x, inertia(sim)) - before), 1e-4 * std::abs(before));
}

// With CPDI, C_p = B_p D_p^-1 with the particle's own D_p (the domain keeps it invertible, where
// a point's linear D_p vanishes at the nodes): the transfers conserve it exactly too.
TEST(ApicCpdi, ItsTransfersConserveAngularMomentum) {
  expect_transfers_conserve_angular_momentum(ShapeFunctions::Cpdi);
}

// Energy of the particles: kinetic, with APIC's affine part 1/2 m tr(C D C^T) (inertia()), and
// elastic.
double total_energy(const Simulation& sim) {
  const Particles& P = sim.particles;
  const std::vector<Eigen::Matrix2d> D = inertia(sim);
  double energy = 0;
  for (std::size_t p = 0; p < P.moving_count; ++p) {
    energy += 0.5 * P.m[p] * P.v[p].squaredNorm() + P.volume[p] * elastic_energy_density(sim.config, P, p);
    if (sim.config.transfer != Transfer::Apic) continue;
    const Eigen::Matrix2d C = affine_of(P, p);
    energy += 0.5 * P.m[p] * (C * D[p] * C.transpose()).trace();
  }
  return energy;
}

// A lone grain sliding at 2 m/s along a rough (fixed) base under gravity, as the grains thrown
// ahead of a granular front: the base stops it, and nothing may speed it up. Its lower nodes are
// held at rest, so the grid hands it a velocity gradient across its support; an isolated
// particle must not keep that as its affine velocity C_p (stress.hpp, is_isolated): a grain at
// rest would carry |C_p| ~ 1e3 1/s, velocities of metres per second at its nodes, into every
// P2G. (Measured before the rule: lone grains ahead of the rods' front at a = 2 with CPDI went
// from 1.3 to 2.9 m/s in 0.02 s with |C_p| ~ 2e3 1/s, and the run blew up.)
void expect_lone_grain_stops(ShapeFunctions family) {
  const double h = 0.005;
  Model model = crossed_rectangle_mesh(0, 0, 200, 4, h);
  // The middle particle of the bottom triangle of the cell [0.1, 0.105] x [0, 0.005], a sixth of
  // a cell above the base: one particle, alone in its element. The rods' material.
  const Vec2 centre(0.1 + h / 2, h / 6);
  testing::add_disc_body(model, "grain", elastic(2650, 0.84e6, 0.3), centre, h / 100);
  ASSERT_EQ(model.particle_count(), 1u);
  model.fixed_nodes = model.node_sets["bottom"];
  model.velocity[0] = Vec2(2.0, 0.0);
  testing::set_run(model, 0.2, Vec2(0, -9.81));
  model.run.transfer = Transfer::Apic;
  model.run.shape_functions = family;
  Simulation sim = make_simulation(model, 1);
  double fastest = 0;
  while (sim.time < 0.2) {
    ASSERT_TRUE(step(sim, std::min(stable_time_step(sim, 0.5), 0.2 - sim.time))) << "t = " << sim.time;
    fastest = std::max(fastest, sim.particles.v[0].norm());
  }
  EXPECT_LE(fastest, 2.0 * (1 + 1e-9));
  EXPECT_LT(sim.particles.v[0].norm(), 1e-3);
  // The velocity field it carries, v_p + C_p (x - x_p) over a cell, at rest too.
  EXPECT_LT(sim.particles.C[0].norm() * h, 1e-3) << "|C_p| = " << sim.particles.C[0].norm() << " 1/s";
}

TEST(ApicCpdi, ALoneGrainOnARoughBaseStopsAndKeepsNoVelocityGradient) { expect_lone_grain_stops(ShapeFunctions::Cpdi); }

TEST(ApicBspline, ALoneGrainOnARoughBaseStopsAndKeepsNoVelocityGradient) {
  expect_lone_grain_stops(ShapeFunctions::QuadraticBspline);
}

// The first axial mode of an elastic bar fixed at its top and free at its foot (Poisson's
// ratio 0, rollers on its sides), started with its mode shape as velocity, v(Z) = v0 sin(pi Z /
// 2L): over 5 periods the energy falls by less than 1 % per period.
double energy_loss_per_period(Transfer transfer, ShapeFunctions family = ShapeFunctions::QuadraticBspline) {
  const double L = 2.0, E = 1e6, rho = 1000;
  Model model = crossed_rectangle_mesh(0, 0, 2, 20, 0.1);
  // CPDI's domains tile the bar with the preprocessor's seeding.
  add_box_body(model, "bar", elastic(rho, E, 0.0), 0, 0.2, 0, L, false,
               family == ShapeFunctions::Cpdi ? testing::Seeding::SubTriangles : testing::Seeding::FourPoints);
  testing::fix_base_roll_sides(model, "top");
  const double period = 4 * L / std::sqrt(E / rho);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const double Z = L - model.position[p].y();
    model.velocity[p] = Vec2(0, 0.05 * std::sin(M_PI * Z / (2 * L)));
  }
  testing::set_run(model, 5 * period, Eigen::Vector2d::Zero());
  model.run.transfer = transfer;
  model.run.shape_functions = family;
  Simulation sim = make_simulation(model, 1);
  const double start = total_energy(sim);
  while (sim.time < 5 * period) {
    const double dt = std::min(stable_time_step(sim, 0.5), 5 * period - sim.time);
    if (!step(sim, dt)) {
      ADD_FAILURE() << "the step failed at t = " << sim.time;
      return 1;
    }
  }
  return 1 - std::pow(total_energy(sim) / start, 1.0 / 5);
}

TEST(ApicBspline, AnElasticVibrationLosesLessThanOnePercentPerPeriod) {
  const double loss = energy_loss_per_period(Transfer::Apic);
  EXPECT_LT(std::abs(loss), 0.01);
}

TEST(ApicCpdi, AnElasticVibrationLosesLessThanOnePercentPerPeriod) {
  const double loss = energy_loss_per_period(Transfer::Apic, ShapeFunctions::Cpdi);
  std::printf("CPDI, APIC: %.4f %% of the energy lost per period\n", 100 * loss);
  EXPECT_LT(std::abs(loss), 0.01);
}

}  // namespace
}  // namespace talus::solver
