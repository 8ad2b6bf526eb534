// Absorbing boundaries and the compliant base (docs/seismic.md): Lysmer and Kuhlemeyer's
// dashpots let a plane wave out of an elastic column, and a shear wave put in through a compliant
// base doubles at the free surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/error.hpp"
#include "preproc/absorbing.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/step/simulation.hpp"
#include "solver/step/step.hpp"
#include "solver/step/time_loop.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

constexpr double kRho = 2000, kE = 1e7, kNu = 0.25;
const double kG = kE / (2 * (1 + kNu)), kK = kE / (3 * (1 - 2 * kNu)), kM = kK + 4 * kG / 3, kLambda = kK - 2 * kG / 3;

// A column [0, 2h] x [0, H] of one elastic soil, with the dashpots of an absorbing "bottom" resolved
// as talus mesh resolves them (preproc::absorbing_nodes); `compliant`: the bottom inputs the motion.
Model column(int cells, double h, bool absorbing, bool compliant) {
  Model model = testing::rectangle_mesh(0, 0, 2, cells, h);
  const Material soil = testing::elastic(kRho, kE, kNu);
  testing::add_box_body(model, "soil", soil, 0, 2 * h, 0, cells * h);
  testing::set_run(model, 1);
  if (!absorbing) return model;
  Scene scene;
  scene.materials.push_back(model.materials.front());
  Boundary bottom;
  bottom.name = "bottom";
  bottom.type = BoundaryType::Absorbing;
  bottom.material = model.materials.front().name;
  scene.boundaries.push_back(bottom);
  scene.base_motion.compliant = compliant;
  scene.base_motion.boundaries = {"bottom"};
  preproc::BoundaryCurve curve{"bottom", BoundaryType::Absorbing, std::nullopt, {}, 0};
  const auto& nodes = model.node_sets.at("bottom");
  for (std::size_t k = 0; k + 1 < nodes.size(); ++k) curve.segments.push_back({nodes[k], nodes[k + 1]});
  model.absorbing = preproc::absorbing_nodes(model.nodes, {curve}, model.triangles, scene);
  return model;
}

double wave_energy(const solver::Simulation& sim) {
  const solver::Energies e = solver::energies(sim);
  return e.kinetic + e.strain;
}

// A compressive pulse travelling down a laterally confined column (rollers on its sides), a
// cos^2 bell 0.8 m long centred 3 m up: v_y = -V f(y), sigma_yy = rho c_p v_y, sigma_xx = sigma_zz =
// lambda / M sigma_yy. After it has reached the base (0.1 s; c_p = 77.5 m/s), the energy left in
// the column is what the base reflected: below 5 % of the pulse's on the absorbing base, nearly
// all of it on a fixed one.
double reflected_share(bool absorbing) {
  const double h = 0.05;
  Model model = column(80, h, absorbing, false);
  model.fixed_nodes.clear();
  if (!absorbing) model.fixed_nodes = model.node_sets.at("bottom");
  for (int32_t i : model.node_sets.at("left")) model.roller_nodes.push_back(i), model.roller_normals.emplace_back(1, 0);
  for (int32_t i : model.node_sets.at("right")) model.roller_nodes.push_back(i), model.roller_normals.emplace_back(1, 0);
  const double c_p = std::sqrt(kM / kRho), V = 0.01, centre = 3.0, width = 0.8;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const double s = (model.position[p].y() - centre) / width;
    const double f = std::abs(s) < 0.5 ? std::pow(std::cos(M_PI * s), 2) : 0.0;
    model.velocity[p] = {0, -V * f};
    const double syy = kRho * c_p * (-V * f);
    model.stress[p] = {kLambda / kM * syy, syy, kLambda / kM * syy, 0};
  }
  solver::Simulation sim = solver::make_simulation(model, 1);
  const double start = wave_energy(sim);
  solver::run_time_loop(sim, 0.5, 0.1, {});
  const double share = wave_energy(sim) / start;
  std::printf("%s base: %.4f of the pulse's energy (%.4g J/m) left after 0.1 s\n", absorbing ? "absorbing" : "fixed",
              share, start);
  return share;
}

TEST(Absorbing, PlaneWaveLeavesTheColumn) {
  EXPECT_LT(reflected_share(true), 0.05);
  EXPECT_GT(reflected_share(false), 0.9);  // the check can fail: a fixed base sends it back
}

// A vertically propagating shear wave: an elastic layer 4 m deep (c_s = 44.7 m/s) on a compliant
// base whose outcrop motion is one cycle of a sine in velocity, v_g = U sin(2 pi f t) for
// t < 1/f (f = 10 Hz, a wavelength of 4.5 m). The base puts in the incident wave v_g / 2; at the
// free surface it doubles, so the surface moves with v_g delayed by H / c_s; its reflection leaves
// through the base's dashpots, so up to 3 H / c_s nothing else reaches the surface.
TEST(Absorbing, ShearWaveDoublesAtTheFreeSurfaceOfACompliantBase) {
  const double h = 0.05, H = 4.0, U = 0.01, f = 10;
  Model model = column(static_cast<int>(H / h), h, true, true);
  model.fixed_nodes.clear();
  // Sides: no vertical motion (a shear column).
  for (const char* side : {"left", "right"})
    for (int32_t i : model.node_sets.at(side)) model.roller_nodes.push_back(i), model.roller_normals.emplace_back(0, 1);
  // The record: the ground velocity U sin(2 pi f t), as the acceleration 2 pi f U cos(2 pi f t), sampled finely.
  BaseMotion& m = model.base_motion;
  m.type = MotionType::Record;
  m.compliant = true;
  m.boundaries = {"bottom"};
  for (int k = 0; k <= 400; ++k) {
    const double t = k / (400 * f);
    m.time.push_back(t);
    m.acceleration.emplace_back(2 * M_PI * f * U * std::cos(2 * M_PI * f * t), 0);
  }
  solver::Simulation sim = solver::make_simulation(model, 1);
  const double c_s = std::sqrt(kG / kRho), arrival = H / c_s;
  // The surface particles' mean horizontal velocity, over the time the pulse is at the surface.
  std::vector<std::size_t> surface;
  for (std::size_t p = 0; p < sim.particles.size(); ++p)
    if (sim.particles.x[p].y() > H - 0.5 * h) surface.push_back(p);
  ASSERT_FALSE(surface.empty());
  double peak = 0, trough = 0;
  struct Watch : solver::Observer {
    const std::vector<std::size_t>& surface;
    double &peak, &trough;
    Watch(const std::vector<std::size_t>& s, double& p, double& t) : surface(s), peak(p), trough(t) {}
    solver::Verdict after_step(solver::Simulation& sim, const solver::StepEvent&) override {
      double v = 0;
      for (std::size_t p : surface) v += sim.particles.v[p].x();
      v /= surface.size();
      peak = std::max(peak, v), trough = std::min(trough, v);
      return solver::Verdict::go_on();
    }
  } watch(surface, peak, trough);
  solver::run_time_loop(sim, 0.5, arrival + 1 / f + 0.02, {&watch});
  std::printf("surface velocity: peak %.5f, trough %.5f m/s; outcrop motion +-%.5f, incident +-%.5f\n", peak, trough, U,
              U / 2);
  EXPECT_NEAR(peak, U, 0.05 * U);
  EXPECT_NEAR(trough, -U, 0.05 * U);
}

// A laterally confined elastic column 4 m high under gravity settles by
// u(y) = rho g (H y - y^2 / 2) / M (M = K + 4 G / 3, the constrained modulus), u_top = rho g H^2 / (2 M)
// = 13.08 mm. On an absorbing base the base is held fixed while gravity rises (run.gravity_ramp,
// 1 s, about five elastic periods 4 H / c_p = 0.21 s); then the dashpots come on with the base's
// reactions as constant nodal forces (docs/seismic.md). The column must stay at its static
// settlement to the end, 5 s later, within 2 %, and at rest. Without the reactions it sank (at
// up to g H / c_p = 0.5 m/s, the speed at which the dashpots carry its weight) and the run ended
// early, at t = 0.37 s, 15 mm down; with the reactions as recorded but without taking the
// ramp's oscillation out of their resultant (absorbing.hpp), it rose by 2 mm/s, to 0.13 of the
// settlement at 6 s.
struct Settlement {
  double final_top = 0, low = 0, high = 0;  // mean top displacement / closed form: at the end, least, most after 2 s
  double exact_top = 0;                     // m
  double end_time = 0;                      // s, when the run ended
};

Settlement settle(bool absorbing) {
  const double h = 0.05, H = 4.0, g = 9.81;
  Model model = column(static_cast<int>(H / h), h, absorbing, false);
  model.fixed_nodes.clear();
  if (!absorbing) model.fixed_nodes = model.node_sets.at("bottom");
  for (const char* side : {"left", "right"})
    for (int32_t i : model.node_sets.at(side)) model.roller_nodes.push_back(i), model.roller_normals.emplace_back(1, 0);
  testing::set_run(model, 6, {0, -g});
  model.run.gravity_ramp = 1.0;
  solver::Simulation sim = solver::make_simulation(model, 1);
  // By particle id (the solver re-orders the particles): the initial height, and the top row's.
  std::vector<double> start(sim.particles.size());
  std::vector<bool> top(sim.particles.size(), false);
  double exact = 0;
  int count = 0;
  for (std::size_t p = 0; p < sim.particles.size(); ++p) {
    const double y = sim.particles.x[p].y();
    start[sim.particles.id[p]] = y;
    if (y > H - h) top[sim.particles.id[p]] = true, exact += kRho * g * (H * y - 0.5 * y * y) / kM, ++count;
  }
  exact /= count;
  Settlement s;
  s.exact_top = exact;
  s.low = 1e9, s.high = -1e9;
  struct Watch : solver::Observer {
    const std::vector<double>& start;
    const std::vector<bool>& top;
    int count;
    Settlement& s;
    Watch(const std::vector<double>& y0, const std::vector<bool>& t, int n, Settlement& out)
        : start(y0), top(t), count(n), s(out) {}
    solver::Verdict after_step(solver::Simulation& sim, const solver::StepEvent&) override {
      double u = 0;
      for (std::size_t p = 0; p < sim.particles.size(); ++p)
        if (top[sim.particles.id[p]]) u += start[sim.particles.id[p]] - sim.particles.x[p].y();
      u /= count * s.exact_top;
      s.final_top = u;
      if (sim.time > 2) s.low = std::min(s.low, u), s.high = std::max(s.high, u);
      return solver::Verdict::go_on();
    }
  } watch(start, top, count, s);
  const solver::LoopEnd end = solver::run_time_loop(sim, 0.5, 6, {&watch});
  s.end_time = sim.time;
  std::printf("%s base: top settlement %.4f of rho g (H y - y^2/2) / M = %.5f m at t = %.3f s%s%s; %.4f to %.4f "
              "from 2 s on\n",
              absorbing ? "absorbing" : "fixed", s.final_top, exact, sim.time, end.reason.empty() ? "" : ", ",
              end.reason.c_str(), s.low, s.high);
  return s;
}

TEST(Absorbing, ElasticColumnStaysAtItsStaticSettlementUnderGravity) {
  const Settlement fixed = settle(false), absorbing = settle(true);
  EXPECT_NEAR(fixed.final_top, 1, 0.03);
  EXPECT_GE(absorbing.end_time, 6);  // it did not sink out of the mesh
  EXPECT_NEAR(absorbing.final_top, 1, 0.02);
  EXPECT_GT(absorbing.low, 0.98);
  EXPECT_LT(absorbing.high, 1.02);
  // At rest: the ramp's oscillation has left through the base, and nothing drifts.
  EXPECT_LT(absorbing.high - absorbing.low, 0.002);
}

// The reactions' resultant is the column's weight, sum m_p g, to round-off (the ramp's
// oscillation at the switch taken out of it, absorbing.hpp); and the reactions are part of a
// checkpoint: a run checkpointed after the switch, restored into a fresh simulation and
// continued matches the uninterrupted one bit for bit, and reactions that do not fit the model
// are refused.
TEST(Absorbing, ReactionsCarryTheWeightAndComeBackFromACheckpointBitForBit) {
  testing::ScratchDir dir("absorbing_restart");
  const double h = 0.05, g = 9.81;
  Model model = column(40, h, true, false);
  model.fixed_nodes.clear();
  for (const char* side : {"left", "right"})
    for (int32_t i : model.node_sets.at(side)) model.roller_nodes.push_back(i), model.roller_normals.emplace_back(1, 0);
  testing::set_run(model, 1, {0, -g});
  model.run.gravity_ramp = 0.05;
  solver::Simulation sim = solver::make_simulation(model, 1);
  const double dt = 0.5 * solver::stable_time_step(sim, 0.5);
  while (sim.time < 0.1) ASSERT_TRUE(solver::step(sim, dt));
  ASSERT_EQ(sim.absorbing_reaction.size(), model.absorbing.node.size());
  double weight = 0;
  for (std::size_t p = 0; p < sim.particles.size(); ++p) weight += sim.particles.m[p] * g;
  Eigen::Vector2d resultant = Eigen::Vector2d::Zero();
  for (const auto& r : sim.absorbing_reaction) resultant += r;
  std::printf("reactions' resultant (%.6g, %.9g) N/m, the column's weight %.9g N/m\n", resultant.x(), resultant.y(),
              weight);
  EXPECT_NEAR(resultant.y(), weight, 1e-9 * weight);

  solver::LoopState loop;
  loop.next_output = loop.next_checkpoint = 1.0;
  solver::write_checkpoint(dir.path().string(), model, sim, loop, solver::ResultsPosition{});
  solver::Simulation restored = solver::make_simulation(model, 1);
  solver::LoopState read_loop;
  solver::ResultsPosition position;
  solver::read_checkpoint(dir.path().string(), model, restored, read_loop, position);
  ASSERT_EQ(restored.absorbing_reaction, sim.absorbing_reaction);
  for (int n = 0; n < 100; ++n) {
    ASSERT_TRUE(solver::step(sim, dt));
    ASSERT_TRUE(solver::step(restored, dt));
  }
  for (std::size_t p = 0; p < sim.particles.size(); ++p) {
    ASSERT_EQ(restored.particles.x[p], sim.particles.x[p]) << "particle " << p;
    ASSERT_EQ(restored.particles.v[p], sim.particles.v[p]) << "particle " << p;
  }
  // A checkpoint whose reactions do not fit the model is refused, naming them.
  sim.absorbing_reaction.pop_back();
  solver::write_checkpoint(dir.path().string(), model, sim, loop, solver::ResultsPosition{});
  solver::Simulation other = solver::make_simulation(model, 1);
  try {
    solver::read_checkpoint(dir.path().string(), model, other, read_loop, position);
    FAIL() << "a checkpoint with reactions of another size was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("absorbing_reaction: expected " +
                                         std::to_string(2 * model.absorbing.node.size()) + " finite values"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace talus
