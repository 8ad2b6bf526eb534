// The velocity transfers (docs/transfer.md) on meshes made in code: XPIC(m) against its
// particle-space definition with explicit matrices, momentum kept by every transfer, APIC
// carrying an affine velocity field exactly, and the isolated-particle rule.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "solver/io/io.hpp"
#include "solver/step/step.hpp"
#include "solver/stress/stress.hpp"
#include "support/test_support.hpp"

using namespace talus;
using namespace talus::solver;
using talus::testing::add_box_body;
using talus::testing::elastic;
using talus::testing::rectangle_mesh;
using talus::testing::set_run;

namespace {

// A jittered mesh with a block of random velocities and stresses in its middle, nothing
// constrained, under gravity.
Model random_block(Transfer transfer, int xpic_order, unsigned seed) {
  Model model = rectangle_mesh(0, 0, 8, 8, 0.125);
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> jitter(-0.025, 0.025);
  for (int j = 1; j < 8; ++j)
    for (int i = 1; i < 8; ++i) model.nodes[j * 9 + i] += Eigen::Vector2d(jitter(random), jitter(random));
  add_box_body(model, "block", elastic(1500, 1e6, 0.3), 0.25, 0.75, 0.25, 0.625);
  std::normal_distribution<double> speed(0, 1), stress(0, 1e3);
  for (auto& v : model.velocity) v = Eigen::Vector2d(speed(random), speed(random));
  for (auto& s : model.stress) s = Eigen::Vector4d(stress(random), stress(random), stress(random), stress(random));
  set_run(model, 1.0, Eigen::Vector2d(0, -9.81));
  model.run.transfer = transfer;
  model.run.xpic_order = xpic_order;
  return model;
}

// The phases of step() up to the particle velocity update.
void update_velocities(Simulation& sim, double dt) {
  const Config& c = sim.config;
  Scratch& s = sim.scratch;
  mark_active_nodes(s.stencil, sim.particles.size(), s.node_stamp, s.stamp, s.grids, c.threads);
  particles_to_grid({sim.particles, s.stencil, c.mesh.nodes, gravity_at(c, sim.time), {}, {}}, s.grids, s.buffers,
                    c.threads);
  update_grid_accelerations(c.constraints, c.body_fixed, c.damping, dt, s.grids, c.threads);
  if (c.transfer == Transfer::Xpic || c.transfer == Transfer::Apic) {
    lagrangian_grid_velocities(c.constraints, dt, s.grids, c.threads);
    if (c.xpic_order > 1) add_xpic_terms(sim.particles, s.stencil, c.constraints, c.xpic_order, s.grids, s.buffers, c.threads);
  }
  update_particle_velocities(sim.particles, s.stencil, c.mesh.nodes, c.transfer, dt, s.grids, s.buffers, c.threads);
  remap_grid_velocities(c.constraints, c.body_fixed, s.grids, s.buffers, c.threads);
}

Vec2 momentum(const Particles& P) {
  Vec2 sum = Vec2::Zero();
  for (std::size_t p = 0; p < P.moving_count; ++p) sum += P.m[p] * P.v[p];
  return sum;
}

}  // namespace

// Hammerquist and Nairn (2017): XPIC(m) is v_p <- v_p - (I - S S+)^m v_p + dt S a, with
// (S u)_p = sum_i N_ip u_i and (S+ w)_i = sum_p m_p N_ip w_p / m_i. The solver never forms
// these matrices (it applies powers of S+S on the grid); here they are built explicitly from
// the stencil and the powers taken in particle space.
TEST(Xpic, MatchesItsParticleSpaceDefinitionForEveryOrder) {
  for (int order : {1, 2, 5}) {
    SCOPED_TRACE(order);
    const Model model = random_block(Transfer::Xpic, order, 31);
    Simulation sim = make_simulation(model, 2);
    const Particles& P = sim.particles;
    const Eigen::Index n = static_cast<Eigen::Index>(P.moving_count);
    const Eigen::Index nodes = static_cast<Eigen::Index>(sim.config.mesh.node_count());
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, nodes);
    const Stencil& stencil = sim.scratch.stencil;
    for (Eigen::Index p = 0; p < n; ++p)
      for (int k = 0; k < stencil.width; ++k)
        S(p, stencil.nodes(p)[k]) += stencil.weights(p)[k];
    const Eigen::VectorXd m = Eigen::Map<const Eigen::VectorXd>(P.m.data(), n);
    const Eigen::VectorXd node_mass = S.transpose() * m;
    Eigen::MatrixXd S_plus = Eigen::MatrixXd::Zero(nodes, n);
    for (Eigen::Index i = 0; i < nodes; ++i)
      if (node_mass[i] > 0) S_plus.row(i) = (S.col(i).array() * m.array()).matrix().transpose() / node_mass[i];
    const Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(n, n) - S * S_plus;
    Eigen::MatrixXd v(n, 2);
    for (Eigen::Index p = 0; p < n; ++p) v.row(p) = P.v[p].transpose();

    const double dt = 1e-4;
    update_velocities(sim, dt);
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nodes, 2);
    for (int32_t i : sim.scratch.grids.active) a.row(i) = sim.scratch.grids.fields[0].a[i].transpose();
    Eigen::MatrixXd Qm = Eigen::MatrixXd::Identity(n, n);
    for (int k = 0; k < order; ++k) Qm = Qm * Q;
    const Eigen::MatrixXd expected = v - Qm * v + dt * S * a;
    double worst = 0;
    for (Eigen::Index p = 0; p < n; ++p) worst = std::max(worst, (P.v[p] - Vec2(expected.row(p).transpose())).norm());
    EXPECT_LT(worst, 1e-12 * v.cwiseAbs().maxCoeff());
    // And it is not FLIP: the m-th power of the noise is gone.
    EXPECT_GT((Qm * v).cwiseAbs().maxCoeff(), 1e-3);
  }
}

TEST(Transfer, EveryTransferKeepsMomentumUpToGravity) {
  const std::vector<std::pair<Transfer, int>> transfers{
      {Transfer::Flip, 1}, {Transfer::PicBlend, 1}, {Transfer::Xpic, 1}, {Transfer::Xpic, 4}, {Transfer::Apic, 1}};
  for (const auto& [transfer, order] : transfers) {
    SCOPED_TRACE(std::string(transfer_name(transfer)) + " " + std::to_string(order));
    Model model = random_block(transfer, order, 37);
    model.run.pic_fraction = transfer == Transfer::PicBlend ? 0.3 : 0.0;
    Simulation sim = make_simulation(model, 2);
    if (transfer == Transfer::Apic) {  // a random affine part too
      std::mt19937 random(41);
      std::normal_distribution<double> rate(0, 5);
      for (auto& C : sim.particles.C) C = Vec4(rate(random), rate(random), rate(random), rate(random));
    }
    double mass = 0;
    for (std::size_t p = 0; p < sim.particles.moving_count; ++p) mass += sim.particles.m[p];
    const Vec2 before = momentum(sim.particles);
    const double dt = 1e-4;
    ASSERT_TRUE(step(sim, dt));
    const Vec2 expected = before + dt * mass * sim.config.gravity;
    EXPECT_LT((momentum(sim.particles) - expected).norm(), 1e-12 * mass);
    // The remapped grid momentum agrees with the particles' (A.11).
    Vec2 grid = Vec2::Zero();
    for (int32_t i : sim.scratch.grids.active) grid += sim.scratch.grids.fields[0].m[i] * sim.scratch.grids.fields[0].v[i];
    EXPECT_LT((grid - momentum(sim.particles)).norm(), 1e-12 * mass);
  }
}

// An affine velocity field v(x) = v0 + G x with no stress and no gravity: APIC hands it to the
// grid and back exactly, velocity and gradient; PIC (XPIC(1)) smooths it near the block's edges.
TEST(Apic, CarriesAnAffineVelocityFieldExactly) {
  const Vec2 v0(0.3, -0.2);
  Eigen::Matrix2d G;
  G << 0.4, -1.1, 0.7, -0.25;
  auto run = [&](Transfer transfer, double& velocity_error, double& gradient_error) {
    Model model = random_block(transfer, 1, 43);
    model.run.gravity = Eigen::Vector2d::Zero();
    for (std::size_t p = 0; p < model.particle_count(); ++p) {
      model.velocity[p] = v0 + G * model.position[p];
      model.stress[p].setZero();
    }
    Simulation sim = make_simulation(model, 1);
    if (transfer == Transfer::Apic)
      for (auto& C : sim.particles.C) C = Vec4(G(0, 0), G(0, 1), G(1, 0), G(1, 1));
    const std::vector<Vec2> x = sim.particles.x;
    ASSERT_TRUE(step(sim, 1e-4));
    velocity_error = gradient_error = 0;
    for (std::size_t p = 0; p < sim.particles.moving_count; ++p) {
      velocity_error = std::max(velocity_error, (sim.particles.v[p] - (v0 + G * x[p])).norm());
      if (transfer == Transfer::Apic)
        gradient_error = std::max(gradient_error, (sim.particles.C[p] - Vec4(G(0, 0), G(0, 1), G(1, 0), G(1, 1))).norm());
    }
  };
  double apic_v = 0, apic_C = 0, pic_v = 0, unused = 0;
  run(Transfer::Apic, apic_v, apic_C);
  run(Transfer::Xpic, pic_v, unused);
  EXPECT_LT(apic_v, 1e-12);
  EXPECT_LT(apic_C, 1e-11);
  EXPECT_GT(pic_v, 1e-3);
}

// A particle alone in its element, well away from the block it shares nodes with, carries no
// stress and keeps its volume; the block's particles keep theirs.
TEST(IsolatedParticles, CarryNoStressAndKeepTheirVolume) {
  Model model = rectangle_mesh(0, 0, 8, 8, 0.125);
  add_box_body(model, "block", elastic(1500, 1e6, 0.3), 0.25, 0.5, 0.25, 0.5);
  // One particle at the centroid of a triangle next to the block's right edge.
  const Eigen::Vector2d lone(0.5 + 0.125 * 2 / 3, 0.25 + 0.125 / 3);
  model.position.push_back(lone);
  model.velocity.emplace_back(1.0, -1.0);
  model.volume.push_back(model.volume.back());
  model.mass.push_back(model.mass.back());
  model.stress.emplace_back(-2e4, -1e4, -1e4, 500);
  model.body.push_back(0);
  model.element.push_back(0);  // located by make_simulation
  for (auto& s : model.stress) s.x() = s.x() == -2e4 ? s.x() : -1e3;
  set_run(model, 1.0);
  Simulation sim = make_simulation(model, 1);
  ASSERT_TRUE(step(sim, 1e-5));
  const Particles& P = sim.particles;
  // The step's own count per element (the particles have not changed element in 1e-5 s).
  const auto alone = [&](std::size_t p) {
    const int32_t e = P.element[p];
    return is_isolated(sim.scratch.element_count.data(), nullptr, e, P.volume[p], sim.config.mesh.area[e]);
  };
  int isolated = 0;
  for (std::size_t p = 0; p < P.moving_count; ++p) {
    if (P.id[p] == static_cast<int32_t>(model.particle_count() - 1)) {
      EXPECT_TRUE(alone(p));
      EXPECT_EQ(P.sigma[p], Vec4::Zero());
      EXPECT_EQ(P.volume[p], model.volume.back());
    } else {
      EXPECT_NE(P.sigma[p], Vec4::Zero());
    }
    isolated += alone(p);
  }
  EXPECT_EQ(isolated, 1);
}

// A block pulled apart (v = 5 x, no gravity, a soft material that hardly resists): its
// particles grow to kMaxVolumeGrowth times their initial volume and no further.
TEST(VolumeGrowth, StopsAtItsCap) {
  Model model = rectangle_mesh(0, 0, 16, 16, 0.125);
  add_box_body(model, "block", elastic(1500, 1e2, 0.3), 0.75, 1.25, 0.75, 1.25);
  for (std::size_t p = 0; p < model.particle_count(); ++p) model.velocity[p] = 5.0 * (model.position[p] - Eigen::Vector2d(1, 1));
  set_run(model, 1.0);
  Simulation sim = make_simulation(model, 1);
  const double dt = 1e-3;
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(step(sim, dt));  // uncapped: (1 + 10 dt)^100, 2.7 times
  double largest = 0;
  for (std::size_t p = 0; p < sim.particles.moving_count; ++p)
    largest = std::max(largest, sim.particles.volume[p] / model.volume[sim.particles.id[p]]);
  EXPECT_NEAR(largest, kMaxVolumeGrowth, 1e-12);
}

// The transfer is a run setting of model.h5 (docs/model-format.md) and of the checkpoint's
// fingerprint: a restart with another transfer is refused.
TEST(Transfer, IsStoredInTheModelAndFingerprinted) {
  talus::testing::ScratchDir dir("transfer-model");
  Model model = random_block(Transfer::Xpic, 7, 47);
  write_model(dir.file("model.h5"), model);
  const Model read = read_model(dir.file("model.h5"));
  EXPECT_EQ(read.run.transfer, Transfer::Xpic);
  EXPECT_EQ(read.run.xpic_order, 7);
  auto run_settings = [](const Model& m) {
    for (const auto& [section, value] : model_fingerprints(m))
      if (section == "run settings") return value;
    return int64_t{0};
  };
  Model other = read;
  other.run.xpic_order = 6;
  EXPECT_NE(run_settings(other), run_settings(read));
  other = read;
  other.run.transfer = Transfer::Apic;
  EXPECT_NE(run_settings(other), run_settings(read));
  // Mixed integration too: stored, read back, and part of the fingerprint.
  other = read;
  other.run.full_cell_fill = 0.7;
  EXPECT_NE(run_settings(other), run_settings(read));
  write_model(dir.file("mixed.h5"), other);
  EXPECT_EQ(read_model(dir.file("mixed.h5")).run.full_cell_fill, 0.7);
  EXPECT_EQ(read.run.full_cell_fill, 0.0);
  // A file without xpic_order was written when the order's default was 2; it reads as 2, not as
  // today's default (5, since 2026-11-28).
  const hid_t file = H5Fopen(dir.file("mixed.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  EXPECT_GE(H5Adelete_by_name(file, "settings/run", "xpic_order", H5P_DEFAULT), 0);
  H5Fclose(file);
  EXPECT_EQ(read_model(dir.file("mixed.h5")).run.xpic_order, 2);
  EXPECT_NE(RunSettings{}.xpic_order, 2);
}
