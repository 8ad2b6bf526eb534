// Surface loads ([loads.NAME], docs/scenes.md): meshed from a .geo and a scene, carried by the
// particles along the loaded curve. An oedometric elastic column under a pressure settles
// q H / M; a free block under a pressure on a slanted edge and a shear traction on a vertical
// one takes, at every step, exactly the requested total force, and gains its momentum.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/scene/scene.hpp"
#include "preproc/preproc.hpp"
#include "solver/io/io.hpp"
#include "solver/step/step.hpp"
#include "support/oedometer_column.hpp"
#include "support/test_support.hpp"

using namespace talus;
using namespace talus::solver;
using talus::testing::ScratchDir;

namespace {

Model mesh_scene(const ScratchDir& dir, const std::string& geo, const std::string& toml) {
  std::ofstream(dir.file("scene.geo")) << geo;
  std::ofstream(dir.file("scene.toml")) << toml;
  return preproc::build_model(load_scene(dir.file("scene.toml")));
}

// The sum of this step's nodal forces over every field (the internal forces sum to zero).
Vec2 total_nodal_force(const Simulation& sim) {
  Vec2 total = Vec2::Zero();
  for (const Grid& grid : sim.scratch.grids.fields)
    for (int32_t i : sim.scratch.grids.active) total += grid.f[i];
  return total;
}

double smooth_ramp(double t, double T) { return t >= T ? 1.0 : 0.5 * (1 - std::cos(M_PI * t / T)); }

// The oedometric column (support/oedometer_column.hpp): 0.5 m wide, H = 2 m, q on its top.
constexpr double kWidth = talus::testing::kColumnWidth, kHeight = talus::testing::kColumnHeight,
                 kQ = talus::testing::kColumnLoad, kE = talus::testing::kColumnE, kNu = talus::testing::kColumnNu;

TEST(SurfaceLoads, OedometricColumnSettlesQHOverM) {
  ScratchDir dir("surface_loads_oedometer");
  const Model model =
      mesh_scene(dir, talus::testing::kOedometerColumnGeo, talus::testing::oedometer_column_scene());
  ASSERT_EQ(model.loads.size(), 1u);
  // The shares of the curve's length sum to the loaded length, along the outward normal (0, 1).
  double length = 0;
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  for (std::size_t p = 0; p < model.particle_count(); ++p)
    if (model.load[p] == 0) length += model.load_length[p], normal += model.load_normal[p];
  EXPECT_NEAR(length, kWidth, 1e-12);
  EXPECT_NEAR(normal.x(), 0, 1e-12);
  EXPECT_NEAR(normal.y(), kWidth, 1e-12);

  omp_set_num_threads(1);
  Simulation sim = make_simulation(model, 1);
  const double M = kE * (1 - kNu) / ((1 + kNu) * (1 - 2 * kNu));
  while (sim.time < model.run.end_time) {
    const double t = sim.time;
    ASSERT_TRUE(step(sim, stable_time_step(sim, 0.5)));
    const Vec2 force = total_nodal_force(sim);  // the load alone: no gravity
    ASSERT_NEAR(force.x(), 0, 1e-9 * kQ * kWidth);
    ASSERT_NEAR(force.y(), -kQ * kWidth * smooth_ramp(t, 0.3), 1e-9 * kQ * kWidth) << "t = " << t;
  }
  // Uniaxial strain: u_y = -(q / M) y, sigma_yy = -q. The settlement of the top is the slope
  // of u_y(y0) (least squares through the fixed base) times H; the loaded particles sit a
  // fraction of an element below the crest and settle q y0 / M each. The stress is checked
  // below one column width from the crest, where the load's spread over the crest's uneven
  // triangles has evened out (Saint-Venant).
  double uy = 0, yy = 0, worst_stress = 0, loaded_ratio = 0;
  int loaded = 0;
  for (std::size_t p = 0; p < sim.particles.size(); ++p) {
    const Eigen::Vector2d& x0 = model.position[sim.particles.id[p]];
    const double u = sim.particles.x[p].y() - x0.y();
    uy += u * x0.y();
    yy += x0.y() * x0.y();
    if (x0.y() < kHeight - kWidth)
      worst_stress = std::max(worst_stress, std::abs(sim.particles.sigma[p][1] + kQ) / kQ);
    if (model.load[sim.particles.id[p]] == 0) loaded_ratio += -u / (kQ * x0.y() / M), ++loaded;
  }
  const double settlement = -uy / yy * kHeight, expected = kQ * kHeight / M;
  loaded_ratio /= loaded;
  std::printf("oedometer: settlement %.6e m (q H / M = %.6e m, %+.3f %%), loaded particles' settlement / (q y0 / M) "
              "%.4f, worst sigma_yy below y = H - W %.3f %% off -q\n",
              settlement, expected, 100 * (settlement / expected - 1), loaded_ratio, 100 * worst_stress);
  EXPECT_NEAR(settlement, expected, 0.01 * expected);
  EXPECT_NEAR(loaded_ratio, 1.0, 0.01);
  EXPECT_LT(worst_stress, 0.01);
}

// A free elastic block in a larger domain, no gravity, no supports: a pressure on its slanted
// top edge (0, 0.4)-(1, 0.6) and an upward shear traction on its right edge x = 1, meeting at
// the corner (1, 0.6), each with its own ramp.
const char* const kBlockGeo = R"(lc = 0.1;
Point(1) = {-0.5, -0.5, 0, 0.3}; Point(2) = {2, -0.5, 0, 0.3}; Point(3) = {2, 1.5, 0, 0.3}; Point(4) = {-0.5, 1.5, 0, 0.3};
Point(5) = {0, 0, 0, lc}; Point(6) = {1, 0, 0, lc}; Point(7) = {1, 0.6, 0, lc}; Point(8) = {0, 0.4, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2}; Plane Surface(2) = {2};
Physical Surface("domain") = {1, 2};
Physical Surface("block") = {2};
Physical Curve("crest") = {7};
Physical Curve("face") = {6};
Physical Curve("outer") = {1};
)";

const char* const kBlockScene = R"([scene]
geometry = "scene.geo"

[run]
end_time = 0.05
gravity = [0.0, 0.0]

[materials.rock]
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.25

[bodies.block]
material = "rock"

[loads.surcharge]
group = "crest"
pressure = 2000.0
ramp = 0.02

[loads.shear]
group = "face"
traction = [0.0, 1500.0]
)";

TEST(SurfaceLoads, FreeBlockTakesTheRequestedForceAtEveryStep) {
  ScratchDir dir("surface_loads_block");
  const Model model = mesh_scene(dir, kBlockGeo, kBlockScene);
  ASSERT_EQ(model.loads.size(), 2u);
  // Full loads: the pressure along the inward normal of the slanted edge, whose length times
  // its unit normal is (0.2, -1) m; the traction times the face's 0.6 m.
  const Vec2 pressure_force = 2000.0 * Vec2(0.2, -1.0), traction_force = Vec2(0, 1500.0 * 0.6);

  omp_set_num_threads(1);
  Simulation sim = make_simulation(model, 1);
  Vec2 impulse = Vec2::Zero();
  long steps = 0;
  while (sim.time < model.run.end_time) {
    const double t = sim.time, dt = stable_time_step(sim, 0.5);
    ASSERT_TRUE(step(sim, dt));
    const Vec2 requested = smooth_ramp(t, 0.02) * pressure_force + traction_force;
    const Vec2 force = total_nodal_force(sim);
    ASSERT_NEAR(force.x(), requested.x(), 1e-9 * pressure_force.norm()) << "t = " << t;
    ASSERT_NEAR(force.y(), requested.y(), 1e-9 * pressure_force.norm()) << "t = " << t;
    impulse += dt * requested;
    ++steps;
  }
  // FLIP without supports or damping conserves momentum: it gains exactly the impulse.
  Vec2 momentum = Vec2::Zero();
  for (std::size_t p = 0; p < sim.particles.size(); ++p) momentum += sim.particles.m[p] * sim.particles.v[p];
  std::printf("free block: %ld steps, momentum (%.6f, %.6f) vs impulse (%.6f, %.6f) N s/m\n", steps,
              momentum.x(), momentum.y(), impulse.x(), impulse.y());
  EXPECT_NEAR(momentum.x(), impulse.x(), 1e-9 * impulse.norm());
  EXPECT_NEAR(momentum.y(), impulse.y(), 1e-9 * impulse.norm());
  EXPECT_GT(impulse.norm(), 10.0);  // the loads did act
}

// The loads are particle fields: re-ordered with the particles, checkpointed and restored. A
// run re-sorted, checkpointed, restored into a fresh simulation and continued matches the
// uninterrupted run bit for bit; a model whose load changed is refused, naming the loads.
TEST(SurfaceLoads, CheckpointRestoresTheLoadsBitForBit) {
  ScratchDir dir("surface_loads_restart");
  const Model model = mesh_scene(dir, kBlockGeo, kBlockScene);
  omp_set_num_threads(1);
  Simulation sim = make_simulation(model, 1);
  const double dt = 0.5 * stable_time_step(sim, 0.5);
  for (int n = 0; n < 40; ++n) ASSERT_TRUE(step(sim, dt));
  sort_particles(sim);
  LoopState loop;
  loop.next_output = loop.next_checkpoint = 1.0;
  write_checkpoint(dir.path().string(), model, sim, loop, ResultsPosition{});

  Simulation restored = make_simulation(model, 1);
  LoopState read_loop;
  ResultsPosition position;
  read_checkpoint(dir.path().string(), model, restored, read_loop, position);
  ASSERT_EQ(restored.particles.load, sim.particles.load);
  for (int n = 0; n < 40; ++n) {
    ASSERT_TRUE(step(sim, dt));
    ASSERT_TRUE(step(restored, dt));
  }
  ASSERT_EQ(restored.particles.size(), sim.particles.size());
  for (std::size_t p = 0; p < sim.particles.size(); ++p) {
    ASSERT_EQ(restored.particles.x[p], sim.particles.x[p]) << "particle " << p;
    ASSERT_EQ(restored.particles.v[p], sim.particles.v[p]) << "particle " << p;
  }

  Model changed = model;
  for (auto& load : changed.loads)
    if (load.traction) *load.traction *= 2;
  Simulation other = make_simulation(changed, 1);
  try {
    read_checkpoint(dir.path().string(), changed, other, read_loop, position);
    FAIL() << "a checkpoint of another load was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("loads"), std::string::npos) << e.what();
  }
}

}  // namespace

// The same column through the command line: `talus run` hands the model's particle columns to
// the solver (solve(Model&&)), and the loads must survive the hand-over.
TEST(SurfaceLoads, TheCommandLineRunSettlesTheColumnAsTheLibraryDoes) {
  ScratchDir dir("surface_loads_cli");
  std::ofstream(dir.file("scene.geo")) << talus::testing::kOedometerColumnGeo;
  std::ofstream(dir.file("scene.toml")) << talus::testing::oedometer_column_scene();
  const auto run = talus::testing::run_talus("run " + dir.file("scene.toml") + " --out " + dir.file("out") +
                                             " -q --threads 1 --set post.metrics=[]");
  ASSERT_EQ(run.status, 0) << run.output;
  const h5::File file = h5::File::open_read(dir.file("out/results.h5"));
  h5::Dims dims;
  const auto position = h5::read_doubles(file, "frames/position", &dims);
  const std::size_t frames = dims[0], n = dims[1];
  ASSERT_GE(frames, 2u);
  double uy = 0, yy = 0;
  for (std::size_t p = 0; p < n; ++p) {
    const double y0 = position[p * 2 + 1], y = position[((frames - 1) * n + p) * 2 + 1];
    uy += (y - y0) * y0;
    yy += y0 * y0;
  }
  const double M = kE * (1 - kNu) / ((1 + kNu) * (1 - 2 * kNu));
  const double settlement = -uy / yy * kHeight, expected = kQ * kHeight / M;
  EXPECT_NEAR(settlement, expected, 0.01 * expected);
}
