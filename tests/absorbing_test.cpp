// Absorbing boundaries and the compliant base (docs/seismic.md): Lysmer and Kuhlemeyer's
// dashpots let a plane wave out of an elastic column, and a shear wave put in through a compliant
// base doubles at the free surface.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "preproc/absorbing.hpp"
#include "solver/step/simulation.hpp"
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

}  // namespace
}  // namespace talus
