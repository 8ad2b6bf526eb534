// The undrained water mode (solver/pore_pressure.*, docs/water.md) against closed forms: an
// oedometric column under a surface pressure shares the load between the water and the skeleton
// as their stiffnesses say; isotropic compression and pure shear of one particle, step by step.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "common/scene/scene.hpp"
#include "preproc/preproc.hpp"
#include "solver/step/step.hpp"
#include "solver/stress/stress.hpp"
#include "solver/stress/water.hpp"
#include "support/oedometer_column.hpp"
#include "support/test_support.hpp"

using namespace talus;
using namespace talus::solver;
using talus::testing::ScratchDir;

namespace {

// The oedometric column (support/oedometer_column.hpp): 0.5 m wide, H = 2 m, q on its top. The
// water table lies a micrometre above the base (it must lie in the domain), so that all of u is
// excess.
using namespace talus::testing;
constexpr double kWidth = kColumnWidth, kHeight = kColumnHeight, kQ = kColumnLoad, kE = kColumnE, kNu = kColumnNu;
constexpr double kWaterBulk = 4e6, kPorosity = 0.4;  // K_w / n = 1e7 Pa, of the skeleton's M

std::string column_scene(const std::string& mode) {
  return oedometer_column_scene("porosity = 0.4\n", "\n[water]\ntable = [[0.0, 1.0e-6], [0.5, 1.0e-6]]\n"
                                                   "bulk_modulus = 4.0e6\nmode = \"" + mode + "\"\n");
}

struct ColumnAtRest {
  double settlement = 0;     // of the top, from the least-squares slope of u_y(y0)
  double u = 0;              // mean pore pressure below one column width from the crest
  double total_yy = 0;       // mean total sigma_yy there
  double effective_yy = 0;   // mean effective sigma_yy there
  double effective_xx = 0;   // mean effective sigma_xx there
  double worst_u = 0;        // largest |u - mean u| there
};

ColumnAtRest run_column(const std::string& mode) {
  ScratchDir dir("undrained_column_" + mode);
  std::ofstream(dir.file("scene.geo")) << kOedometerColumnGeo;
  std::ofstream(dir.file("scene.toml")) << column_scene(mode);
  const Model model = preproc::build_model(load_scene(dir.file("scene.toml")));
  omp_set_num_threads(1);
  Simulation sim = make_simulation(model, 1);
  while (sim.time < model.run.end_time) {
    if (!step(sim, stable_time_step(sim, 0.5))) {
      ADD_FAILURE() << "step failed at t = " << sim.time;
      return {};
    }
  }
  const Particles& P = sim.particles;
  ColumnAtRest r;
  double uy = 0, yy = 0;
  int count = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Eigen::Vector2d& x0 = model.position[P.id[p]];
    uy += (P.x[p].y() - x0.y()) * x0.y();
    yy += x0.y() * x0.y();
    if (x0.y() < kHeight - kWidth) {  // Saint-Venant: below the crest's uneven load spread
      const Vec4 effective = effective_stress(P, p);
      r.u += P.pore_pressure[p], r.total_yy += P.sigma[p][1];
      r.effective_yy += effective[1], r.effective_xx += effective[0];
      ++count;
    }
  }
  r.settlement = -uy / yy * kHeight;
  r.u /= count, r.total_yy /= count, r.effective_yy /= count, r.effective_xx /= count;
  for (std::size_t p = 0; p < P.size(); ++p)
    if (model.position[P.id[p]].y() < kHeight - kWidth) r.worst_u = std::max(r.worst_u, std::abs(P.pore_pressure[p] - r.u));
  return r;
}

}  // namespace

// Undrained and confined (uniaxial strain, no flow): the total vertical stress carries q, the
// water's stiffness K_w / n and the skeleton's constrained modulus M = E (1 - nu) / ((1 + nu)
// (1 - 2 nu)) act in parallel on the same strain eps = -q / (M + K_w / n), so
//   u = q (K_w / n) / (K_w / n + M),   sigma'_yy = -q M / (K_w / n + M),
//   sigma'_xx = nu / (1 - nu) sigma'_yy,   settlement = q H / (K_w / n + M).
// Drained, the skeleton alone carries q (u = 0, settlement q H / M).
TEST(Undrained, OedometricColumnSharesTheLoadBetweenWaterAndSkeleton) {
  const double M = kE * (1 - kNu) / ((1 + kNu) * (1 - 2 * kNu)), Kw = kWaterBulk / kPorosity;
  const double u = kQ * Kw / (Kw + M), effective = -kQ * M / (Kw + M);
  const ColumnAtRest undrained = run_column("undrained");
  std::printf("undrained oedometer: u %.1f Pa (expected %.1f, spread %.1f), sigma'_yy %.1f (%.1f), sigma'_xx %.1f "
              "(%.1f), sigma_yy %.1f (%.1f), settlement %.4e m (%.4e)\n",
              undrained.u, u, undrained.worst_u, undrained.effective_yy, effective, undrained.effective_xx,
              kNu / (1 - kNu) * effective, undrained.total_yy, -kQ, undrained.settlement, kQ * kHeight / (Kw + M));
  EXPECT_NEAR(undrained.u, u, 0.01 * u);
  EXPECT_LT(undrained.worst_u, 0.02 * u);
  EXPECT_NEAR(undrained.effective_yy, effective, 0.01 * kQ);
  EXPECT_NEAR(undrained.effective_xx, kNu / (1 - kNu) * effective, 0.01 * kQ);
  EXPECT_NEAR(undrained.total_yy, -kQ, 0.01 * kQ);
  EXPECT_NEAR(undrained.settlement, kQ * kHeight / (Kw + M), 0.01 * kQ * kHeight / (Kw + M));

  const ColumnAtRest drained = run_column("drained");
  EXPECT_EQ(drained.u, 0.0);
  EXPECT_NEAR(drained.effective_yy, -kQ, 0.01 * kQ);
  EXPECT_NEAR(drained.settlement, kQ * kHeight / M, 0.01 * kQ * kHeight / M);
}

namespace {

// One particle of an elastic material, undrained, 5 m below a level table.
struct OneParticle {
  Config config;
  Particles P;
  // The cell pass's view for update_stresses: one element that the particle fills
  // (so it is not isolated), no EVS.
  Stencil stencil;
  std::vector<int32_t> element_count{1};
  CellSums cells() const { return CellSums{config.mesh, stencil, element_count, nullptr}; }
};

OneParticle one_particle(double porosity) {
  Material m;
  m.name = "soil";
  m.density = 2000;
  m.youngs_modulus = 5e7;
  m.poisson_ratio = 0.3;
  m.porosity = porosity;
  OneParticle o;
  o.config.water.table = {{-10, 10}, {10, 10}};
  o.config.water.mode = WaterMode::Undrained;
  o.config.materials = {make_material(m)};
  o.config.material_of_body = {0};
  o.config.initial_volume = {1};
  Model model;
  model.materials = {m};
  prepare_materials(o.config, model);
  Particles& P = o.P;
  P.x = {{0, 5}};
  P.v = {{0, 0}};
  P.m = {2000};
  P.volume = {1};
  P.body = {0};
  P.element = {0};
  o.config.mesh.area = {1};
  P.id = {0};
  P.eps_p = {0};
  P.moving_count = 1;
  initial_pore_pressures(P, o.config, 0);
  P.sigma = {Vec4(-100e3, -100e3, -100e3, 0) - P.pore_pressure[0] * Vec4(1, 1, 1, 0)};  // effective -100 kPa
  return o;
}

}  // namespace

// Isotropic compression in 100 steps of d(eps_v) = -1e-5 each, then back: the excess pore
// pressure is (K_w / n) times the accumulated compression at every step, the effective mean
// stress moves by K d(eps_v) alone, and unloading returns both to the start. With n = 0 there is
// no excess at all.
TEST(Undrained, IsotropicCompressionRaisesThePorePressureByKwOverNTimesTheStrain) {
  OneParticle o = one_particle(0.25);
  Particles& P = o.P;
  const double u0 = P.pore_pressure[0], Kw_n = 2.2e9 / 0.25, K = o.config.materials[0].bulk_modulus;
  const std::vector<Vec4> compress = {Vec4(-1e-5 / 3, -1e-5 / 3, -1e-5 / 3, 0)};
  const std::vector<Vec4> expand = {-compress[0]};
  double worst = 0;
  for (int k = 1; k <= 200; ++k) {
    ASSERT_EQ(update_stresses(P, k <= 100 ? compress : expand, o.cells(), o.config, 0, 1e-3, 1), -1);
    const double strain = 1e-5 * (k <= 100 ? k : 200 - k);  // accumulated compression
    worst = std::max(worst, std::abs(P.excess_pore_pressure[0] - Kw_n * strain) / (Kw_n * 1e-3));
    const Vec4 effective = effective_stress(P, 0);
    ASSERT_NEAR((effective[0] + effective[1] + effective[2]) / 3, -100e3 - K * strain, 1e-6 * 100e3) << k;
    ASSERT_NEAR(P.pore_pressure[0], u0 + P.excess_pore_pressure[0], 1e-9 * u0);
  }
  std::printf("isotropic compression: K_w / n = %.3e Pa, worst excess error %.2e of its peak\n", Kw_n, worst);
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(P.excess_pore_pressure[0], 0, 1e-6);

  // The time step follows the stiffer mixture: c = sqrt((K + K_w / n + 4G/3) / rho).
  const MaterialState& m = o.config.materials[0];
  EXPECT_NEAR(m.wave_speed, std::sqrt((K + Kw_n + 4 * m.shear_modulus / 3) / 2000), 1e-9 * m.wave_speed);

  OneParticle dry = one_particle(0);
  ASSERT_EQ(update_stresses(dry.P, compress, dry.cells(), dry.config, 0, 1e-3, 1), -1);
  EXPECT_EQ(dry.P.excess_pore_pressure[0], 0.0);
  EXPECT_NEAR(dry.P.pore_pressure[0], 9810 * 5, 1e-9);
}

// Pure shear changes no volume, so no excess pore pressure: the deviatoric stress goes to the
// skeleton, 2 G times the tensor shear strain.
TEST(Undrained, PureShearLeavesThePorePressure) {
  OneParticle o = one_particle(0.4);
  Particles& P = o.P;
  const double u0 = P.pore_pressure[0], G = o.config.materials[0].shear_modulus;
  const std::vector<Vec4> shear = {Vec4(1e-5, -1e-5, 0, 1e-5)};
  for (int k = 0; k < 50; ++k) ASSERT_EQ(update_stresses(P, shear, o.cells(), o.config, 0, 1e-3, 1), -1);
  EXPECT_EQ(P.excess_pore_pressure[0], 0.0);
  EXPECT_EQ(P.pore_pressure[0], u0);
  const Vec4 effective = effective_stress(P, 0);
  EXPECT_NEAR(effective[0] - effective[1], 2 * G * 2 * 50e-5, 1e-9 * G);
  EXPECT_NEAR(effective[2], -100e3, 1e-6);
}
