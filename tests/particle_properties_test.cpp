// Per-particle material properties (Model::properties, docs/model-format.md): a column of sand
// whose right half has its own cohesion, given either as a second material or as a per-particle
// cohesion of one material. The two must give the same stresses, particle by particle and bit for
// bit, through the steps, strength reduction, a checkpoint and restart, a re-ordering, and a solve
// on two MPI ranks (particles migrate with their values); model.h5 and results.h5 carry them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/solver.hpp"
#include "solver/step/step.hpp"
#include "solver/strength_reduction.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using testing::ScratchDir;

constexpr double kWeak = 500, kStrong = 2000;  // Pa: the left and the right half's cohesion

// A 0.6 m column of sand against the left wall of a 2 m x 0.8 m box, in two bodies (left and
// right half), collapsing under gravity. Two materials that differ only in cohesion.
Model two_materials() {
  Model model = testing::rectangle_mesh(0, 0, 40, 16, 0.05);
  testing::add_box_body(model, "left", testing::mohr_coulomb(1800, 1e7, 0.3, 30, kWeak), 0, 0.3, 0, 0.6);
  testing::add_box_body(model, "right", testing::mohr_coulomb(1800, 1e7, 0.3, 30, kStrong), 0.3, 0.6, 0, 0.6);
  testing::fix_base_roll_sides(model);
  model.contact.enabled = false;  // one velocity field, as one body
  testing::set_run(model, 0.15, Eigen::Vector2d(0, -9.81));
  model.run.output_interval = 0.05;
  model.scene_name = "properties";
  model.post.body = "left";
  return model;
}

// The same column with one material, the weak one, and the right half's cohesion per particle;
// also the friction angle per particle, the material's everywhere, so that each particle carries
// two values (a field two wide through sorting, checkpoints and migration).
Model one_material_with_properties() {
  Model model = two_materials();
  model.materials.pop_back();
  model.bodies[1].material = 0;
  ParticleProperty cohesion{model.materials[0].name, "cohesion", {}};
  for (int32_t body : model.body) cohesion.values.push_back(body == 1 ? kStrong : kWeak);
  const ParticleProperty friction{model.materials[0].name, "friction_angle",
                                  std::vector<double>(model.particle_count(), 30.0)};
  model.properties = {cohesion, friction};
  return model;
}

// Steps `sim` n times with its CFL step.
void advance(solver::Simulation& sim, int n) {
  for (int k = 0; k < n; ++k) ASSERT_TRUE(solver::step(sim, solver::stable_time_step(sim, 0.5)));
}

// The particles' stresses and plastic strains in model order.
std::vector<double> state_by_id(const solver::Simulation& sim) {
  const solver::Particles& P = sim.particles;
  std::vector<double> out(5 * P.size());
  for (std::size_t p = 0; p < P.size(); ++p) {
    for (int k = 0; k < 4; ++k) out[5 * P.id[p] + k] = P.sigma[p][k];
    out[5 * P.id[p] + 4] = P.eps_p[p];
  }
  return out;
}

TEST(ParticleProperties, AnOverriddenCohesionActsAsASecondMaterialBitForBit) {
  for (int threads : {1, 2}) {
    solver::Simulation split = solver::make_simulation(two_materials(), threads);
    solver::Simulation with = solver::make_simulation(one_material_with_properties(), threads);
    ASSERT_EQ(with.particles.properties.size(), 2 * with.particles.size());  // two values per particle
    ASSERT_TRUE(split.particles.properties.empty());
    advance(split, 150);
    advance(with, 150);
    EXPECT_EQ(state_by_id(split), state_by_id(with)) << threads << " threads";
    // The right half yields, so its cohesion matters: the weak material everywhere differs.
    Model weak = two_materials();
    parameters_of<MohrCoulomb>(weak.materials[1]).cohesion = kWeak;
    solver::Simulation all_weak = solver::make_simulation(weak, threads);
    advance(all_weak, 150);
    EXPECT_NE(state_by_id(all_weak), state_by_id(with));
    int plastic_right = 0;
    for (std::size_t p = 0; p < with.particles.size(); ++p)
      plastic_right += with.particles.body[p] == 1 && with.particles.eps_p[p] > 0;
    EXPECT_GT(plastic_right, 10);
  }
}

TEST(ParticleProperties, StrengthReductionDividesAnOverriddenCohesionAsTheMaterials) {
  const Model split_model = two_materials(), with_model = one_material_with_properties();
  solver::Simulation split = solver::make_simulation(split_model, 1);
  solver::Simulation with = solver::make_simulation(with_model, 1);
  solver::reduce_strength(split, split_model, 1.7);
  solver::reduce_strength(with, with_model, 1.7);
  advance(split, 100);
  advance(with, 100);
  EXPECT_EQ(state_by_id(split), state_by_id(with));
}

TEST(ParticleProperties, ValuesFollowTheParticlesThroughSortingAndACheckpoint) {
  const ScratchDir dir("properties-checkpoint");
  const Model model = one_material_with_properties();
  solver::Simulation sim = solver::make_simulation(model, 2);
  advance(sim, 60);
  solver::sort_particles(sim);  // the particles have moved: a new order
  const solver::Particles& P = sim.particles;
  for (std::size_t p = 0; p < P.size(); ++p) ASSERT_EQ(P.properties[2 * p], model.properties[0].values[P.id[p]]);
  solver::write_checkpoint(dir.path().string(), model, sim, solver::LoopState{0.5, 0.5}, solver::ResultsPosition{1, 0});

  solver::Simulation restarted = solver::make_simulation(model, 2);
  solver::LoopState loop;
  solver::ResultsPosition position;
  solver::read_checkpoint(dir.path().string(), model, restarted, loop, position);
  EXPECT_EQ(restarted.particles.properties, P.properties);
  advance(sim, 60);
  advance(restarted, 60);
  EXPECT_EQ(state_by_id(sim), state_by_id(restarted));

  // Another value is another model: the checkpoint is refused, naming the properties.
  Model changed = model;
  changed.properties[0].values[0] = 1000;
  solver::Simulation other = solver::make_simulation(changed, 1);
  try {
    solver::read_checkpoint(dir.path().string(), changed, other, loop, position);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("particle properties changed"), std::string::npos) << e.what();
  }
}

TEST(ParticleProperties, ModelAndResultsFilesCarryThemAndOnlyThem) {
  const ScratchDir dir("properties-files");
  Model model = one_material_with_properties();
  write_model(dir.file("with.h5"), model);
  const Model read = read_model(dir.file("with.h5"));
  ASSERT_EQ(read.properties.size(), 2u);
  EXPECT_EQ(read.properties[0].material, model.materials[0].name);
  EXPECT_EQ(read.properties[0].parameter, "cohesion");
  EXPECT_EQ(read.properties[0].values, model.properties[0].values);  // every particle is of that material
  EXPECT_EQ(read.properties[1].parameter, "friction_angle");

  solver::SolveOptions options;
  options.out_dir = dir.path().string();
  options.progress = false;
  options.threads = 1;
  std::ostringstream log;
  solver::solve(model, options, log);
  const h5::File results = h5::File::open_read(dir.file("results.h5"));
  EXPECT_EQ(h5::read_doubles(results, "particles/cohesion"), model.properties[0].values);
  EXPECT_EQ(h5::get_string(results, "particles/cohesion", "unit"), "Pa");
  EXPECT_EQ(h5::get_string(results, "particles/friction_angle", "unit"), "deg");

  // Without properties: no group in model.h5, no dataset in results.h5.
  const Model plain = two_materials();
  write_model(dir.file("plain.h5"), plain);
  EXPECT_FALSE(h5::exists(h5::File::open_read(dir.file("plain.h5")), "particles/properties"));
  const ScratchDir out("properties-plain");
  options.out_dir = out.path().string();
  solver::solve(plain, options, log);
  EXPECT_FALSE(h5::exists(h5::File::open_read(out.file("results.h5")), "particles/cohesion"));
}

TEST(ParticleProperties, BadValuesAreRefusedNamingTheDatasetAndTheParticle) {
  const ScratchDir dir("properties-bad");
  auto problem_of = [&](const std::function<void(Model&)>& change) {
    Model model = one_material_with_properties();
    change(model);
    write_model(dir.file("bad.h5"), model);
    try {
      read_model(dir.file("bad.h5"));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string item = "particles/properties/left_material.";
  EXPECT_NE(problem_of([](Model& m) { m.properties[0].values[3] = -1; })
                .find(item + "cohesion: particle 3: cohesion: got -1, expected a finite number in [0, inf]"),
            std::string::npos);
  // A per-particle friction angle bounds that particle's dilation angle.
  EXPECT_NE(problem_of([](Model& m) {
              parameters_of<MohrCoulomb>(m.materials[0]).dilation_angle = 20;
              m.properties[1].values[7] = 10;
            }).find("particle 7: dilation_angle: got 20, expected a finite number in [0, 10]"),
            std::string::npos);
  EXPECT_NE(problem_of([](Model& m) { m.properties[0].parameter = "density"; }).find("not a per-particle property"),
            std::string::npos);
  EXPECT_NE(problem_of([](Model& m) { m.properties[0].parameter = "stiffness"; })
                .find("has no parameter 'stiffness'"),
            std::string::npos);
}

TEST(ParticleProperties, TwoRanksMigrateTheValuesWithTheParticles) {
  if (testing::talus_version().find("(with MPI") == std::string::npos) GTEST_SKIP() << "talus was built without MPI";
  const ScratchDir dir("properties-mpi");
  write_model(dir.file("with.h5"), one_material_with_properties());
  write_model(dir.file("split.h5"), two_materials());
  for (const char* name : {"with", "split"}) {
    const auto solved = testing::run_talus("solve " + dir.file(std::string(name) + ".h5") +
                                           " --threads 1 --ranks 2 --quiet --out " + dir.file(name));
    ASSERT_EQ(solved.status, 0) << solved.output;
  }
  std::string worst;
  EXPECT_EQ(testing::frame_difference(dir.file("with/results.h5"), dir.file("split/results.h5"), worst), 0) << worst;
}

}  // namespace
}  // namespace talus
