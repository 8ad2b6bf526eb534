// The layered analysis (docs/layered.md): the ground of several bodies (upper_envelope), the
// LayeredGround slice model against hand-computed slices and against one soil, and Bishop's
// critical circle on the published two-layer clay slope (geometries/two_layer_clay.*).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/error.hpp"
#include "postproc/analysed_slope.hpp"
#include "postproc/bishop.hpp"
#include "postproc/slice_model.hpp"
#include "postproc/slope_geometry.hpp"
#include "solver/stress/material_state.hpp"
#include "solver/strength_reduction.hpp"

namespace talus::postproc {
namespace {

// A slope layer (crest y = 20, a 2:1 face from (20, 20) to the toe (40, 10)) on a foundation
// layer [0, 70] x [0, 10]: geometries/two_layer_clay.geo.
const Polyline kSlopeLayer{{0, 10}, {40, 10}, {20, 20}, {0, 20}};
const Polyline kFoundation{{0, 0}, {70, 0}, {70, 10}, {40, 10}, {0, 10}};

TEST(Layered, TheGroundOfTwoBodiesIsTheUpperEnvelopeOfTheirOutlines) {
  const Polyline ground = upper_envelope({kSlopeLayer, kFoundation});
  const Polyline expected{{0, 20}, {20, 20}, {40, 10}, {70, 10}};
  ASSERT_EQ(ground.size(), expected.size());
  for (std::size_t i = 0; i < ground.size(); ++i) EXPECT_EQ(ground[i], expected[i]) << i;
  const SlopeProfile profile = slope_profile(std::vector<Polyline>{kSlopeLayer, kFoundation});
  EXPECT_EQ(profile.crest, Eigen::Vector2d(20, 20));
  EXPECT_EQ(profile.toe, Eigen::Vector2d(40, 10));
  EXPECT_EQ(profile.base_y, 0);
  EXPECT_EQ(profile.height, 10);
  // A block standing on the foundation beyond the toe: a step up and down in the ground.
  const Polyline block{{50, 10}, {54, 10}, {54, 13}, {50, 13}};
  const Polyline stepped = upper_envelope({kSlopeLayer, kFoundation, block});
  const Polyline with_block{{0, 20}, {20, 20}, {40, 10}, {50, 10}, {50, 13}, {54, 13}, {54, 10}, {70, 10}};
  ASSERT_EQ(stepped.size(), with_block.size());
  for (std::size_t i = 0; i < stepped.size(); ++i) EXPECT_EQ(stepped[i], with_block[i]) << i;
  // Bodies that leave a gap in x do not make a ground.
  EXPECT_THROW(upper_envelope({kSlopeLayer, Polyline{{45, 0}, {50, 0}, {50, 5}, {45, 5}}}), Error);
}

// One slice worked by hand: x = 30 (the face is at y = 15 there), base at y = 6 in the
// foundation, the table at y = 12, surface forces of 1000 N each every 0.5 m.
TEST(Layered, ASliceWeighsEachLayerAboveItsBaseAndTakesTheStrengthUnderIt) {
  GroundLayer slope{{kSlopeLayer}, {10e3, 20, 18e3}, 21e3};
  GroundLayer foundation{{kFoundation}, {30e3, 0, 19e3}, 22e3};
  std::vector<SurfaceForce> loads;
  for (int k = 0; k < 200; ++k) loads.push_back({25.025 + 0.05 * k, 100.0});  // 2000 N/m over [25, 35]
  const LayeredGround dry({slope, foundation});
  const Slice slice{30, 2, 15, 6};
  const SliceForces f = dry.forces(slice);
  // Slope layer from y = 10 to 15 at 18 kN/m3, foundation from 6 to 10 at 19 kN/m3, 2 m wide.
  EXPECT_NEAR(f.weight, 2 * (5 * 18e3 + 4 * 19e3), 1e-6);
  EXPECT_EQ(f.cohesion, 30e3);
  EXPECT_EQ(f.tan_phi, 0);
  EXPECT_EQ(f.pore_pressure, 0);
  // With a table at y = 12: saturated below it (21 and 22 kN/m3), u = 9810 (12 - 6).
  const LayeredGround wet({slope, foundation}, {}, 0, 9810, [](double) { return 12.0; });
  const SliceForces w = wet.forces(slice);
  EXPECT_NEAR(w.weight, 2 * (3 * 18e3 + 2 * 21e3 + 4 * 22e3), 1e-6);
  EXPECT_NEAR(w.pore_pressure, 9810 * 6, 1e-9);
  // A base on the line between the layers takes the upper layer's strength; in the slope layer too.
  const SliceForces on_line = dry.forces({30, 2, 15, 10});
  EXPECT_EQ(on_line.cohesion, 10e3);
  EXPECT_NEAR(on_line.tan_phi, std::tan(20 * M_PI / 180), 1e-15);
  EXPECT_NEAR(on_line.weight, 2 * 5 * 18e3, 1e-6);
  // Surface forces: 100 N every 0.05 m spread over 0.05 m each is 2000 N/m; the slice takes 2 m.
  const LayeredGround loaded({slope, foundation}, loads, 0.05);
  EXPECT_NEAR(loaded.forces(slice).weight, f.weight + 2 * 2000, 1e-6);
  // A slice half beyond the loaded stretch carries half.
  EXPECT_NEAR(loaded.forces({35, 2, 10, 6}).weight, 2 * 4 * 19e3 + 1 * 2000, 1e-6);
}

// Two layers of one soil are one soil: the same factor of safety as UniformSoil, for one circle
// and for the search.
TEST(Layered, TwoLayersOfOneSoilGiveTheSingleSoilsFactor) {
  const SoilStrength soil{10e3, 20, 20e3};
  const SlopeProfile profile = slope_profile(std::vector<Polyline>{kSlopeLayer, kFoundation});
  const LayeredGround layered({GroundLayer{{kSlopeLayer}, soil, 0}, GroundLayer{{kFoundation}, soil, 0}});
  const UniformSoil uniform(soil);
  const Circle circle{{35, 30}, 22};
  const auto one = bishop_factor_of_safety(profile, uniform, circle);
  const auto two = bishop_factor_of_safety(profile, layered, circle);
  ASSERT_TRUE(one && two);
  EXPECT_NEAR(two->factor_of_safety, one->factor_of_safety, 1e-12 * one->factor_of_safety);
  const auto searched_one = bishop_search(profile, uniform);
  const auto searched_two = bishop_search(profile, layered);
  ASSERT_TRUE(searched_one && searched_two);
  EXPECT_NEAR(searched_two->factor_of_safety, searched_one->factor_of_safety, 1e-9 * searched_one->factor_of_safety);
  std::printf("one soil in two layers: F = %.6f, one layer: %.6f\n", searched_two->factor_of_safety,
              searched_one->factor_of_safety);
}

// The model of geometries/two_layer_clay: c_u1 = 0.25 gamma H = 50 kPa in the slope layer,
// c_u2 = lambda c_u1 in the foundation, phi_u = 0, gamma = 20 kN/m3.
Model two_layer_clay(double lambda) {
  Model model;
  model.run.gravity = {0, -9.81};
  const double density = 20e3 / 9.81;
  Material clay, foundation;
  clay.name = "clay", foundation.name = "foundation";
  for (Material* m : {&clay, &foundation}) {
    m->model = MohrCoulomb::Parameters{}, m->density = density;
    m->youngs_modulus = 1e8, m->poisson_ratio = 0.3;
  }
  parameters_of<MohrCoulomb>(clay).cohesion = 50e3;
  parameters_of<MohrCoulomb>(foundation).cohesion = lambda * 50e3;
  model.materials = {clay, foundation};
  model.bodies = {BodyInfo{"slope", 0, false, {kSlopeLayer}}, BodyInfo{"foundation", 1, false, {kFoundation}}};
  model.post.bodies = {"slope", "foundation"};
  return model;
}

// Griffiths and Lane (1999), Geotechnique 49(3):387-403: the undrained clay slope on a
// foundation layer (2:1, H = 10 m, D = 2). Published factors of safety (code_aster validation
// manual V6.03.507, ssnp507, Table 2, the reference of Griffiths and Lane's example): 1.448 at
// lambda = c_u2 / c_u1 = 1, 2.032 at lambda = 1.5 and 4. Within 5 %; at lambda = 4 the one-soil
// answer (1.47, the deep circle) would be 28 % off: the layers must be honoured.
TEST(Layered, BishopOnTheTwoLayerClaySlopeWithinFivePercentOfGriffithsAndLane) {
  const Source source{"two_layer_clay.toml", true};
  for (const auto& [lambda, published] : {std::pair{1.0, 1.448}, {1.5, 2.032}, {4.0, 2.032}}) {
    const Model model = two_layer_clay(lambda);
    const AnalysedBodies bodies{{0, 1}, {}};
    const AnalysedSlope slope = analysed_slope(model, bodies, source);
    const auto bishop = critical_circle(slope, model, bodies, GroundLoads{}, source);
    ASSERT_TRUE(bishop);
    std::printf("two-layer clay, lambda %.1f: Bishop F = %.4f (published %.3f, %+.1f %%), %s circle, centre "
                "(%.2f, %.2f) m, R = %.2f m\n",
                lambda, bishop->factor_of_safety, published, 100 * (bishop->factor_of_safety / published - 1),
                to_string(bishop->kind), bishop->circle.centre.x(), bishop->circle.centre.y(), bishop->circle.radius);
    EXPECT_NEAR(bishop->factor_of_safety, published, 0.05 * published) << lambda;
    if (lambda == 4.0) {  // the slope fails above the strong foundation, at its toe, tangent to it
      EXPECT_NE(bishop->kind, CircleKind::Base);
      EXPECT_GT(bishop->x_exit, 35);
      EXPECT_LE(bishop->x_exit, 40 + 1e-6);
      EXPECT_GE(bishop->circle.centre.y() - bishop->circle.radius, 10 - 1e-6);
    } else if (lambda == 1.0) {  // a deep circle through the foundation, leaving beyond the toe
      EXPECT_EQ(bishop->kind, CircleKind::Base);
    }
  }
}

TEST(Layered, BishopRefusesABodyThatIsNotMohrCoulomb) {
  Model model = two_layer_clay(4);
  model.materials[1].model = LinearElastic::Parameters{};
  const AnalysedBodies bodies{{0, 1}, {}};
  const Source source{"two_layer_clay.toml", true};
  const AnalysedSlope slope = analysed_slope(model, bodies, source);
  try {
    critical_circle(slope, model, bodies, GroundLoads{}, source);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("two_layer_clay.toml: materials.foundation"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("body 'foundation'"), std::string::npos) << e.what();
  }
}

TEST(Layered, AnalysedBodiesFollowPostBodiesAndRefuseUnknownNames) {
  Model model = two_layer_clay(1);
  const std::vector<int32_t> body_of{1, 0, 1, 0};
  const AnalysedBodies both = analysed_bodies(model, body_of, {"results.h5"});
  EXPECT_EQ(both.indices, (std::vector<int>{0, 1}));
  EXPECT_EQ(both.particles, (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_EQ(body_names(model, both), "slope and foundation");
  model.post.bodies = {"slope", "dam"};
  try {
    analysed_bodies(model, body_of, {"results.h5"});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("results.h5: settings/post/bodies: no body named 'dam'"), std::string::npos)
        << e.what();
  }
  model.post.bodies.clear();  // post.body alone (the first body when empty)
  EXPECT_EQ(analysed_bodies(model, body_of, {"results.h5"}).indices, (std::vector<int>{0}));
}

// Strength reduction divides every soil (Mohr-Coulomb) material, each its own c and tan phi, and
// leaves a linear-elastic body's material alone.
TEST(Layered, StrengthReductionDividesEveryMohrCoulombMaterial) {
  Model model = two_layer_clay(1.5);
  parameters_of<MohrCoulomb>(model.materials[1]).friction_angle = 30;
  Material block;  // linear elastic: no strength, left alone
  block.name = "block";
  block.density = 2400, block.youngs_modulus = 3e10, block.poisson_ratio = 0.2;
  model.materials.push_back(block);
  solver::Simulation sim;
  for (const Material& m : model.materials) sim.config.materials.push_back(solver::make_material(m));
  const auto untouched = std::get<LinearElastic::Prepared>(sim.config.materials[2].prepared);
  solver::reduce_strength(sim, model, 2.0);
  auto peak = [&](int i) { return std::get<MohrCoulomb::Prepared>(sim.config.materials[i].prepared).peak_strength; };
  EXPECT_DOUBLE_EQ(peak(0).cohesion, 25e3);
  EXPECT_DOUBLE_EQ(peak(0).friction_angle, 0);
  EXPECT_DOUBLE_EQ(peak(1).cohesion, 37.5e3);
  EXPECT_NEAR(std::tan(peak(1).friction_angle * M_PI / 180), std::tan(M_PI / 6) / 2, 1e-12);
  const auto& block_state = std::get<LinearElastic::Prepared>(sim.config.materials[2].prepared);
  EXPECT_EQ(block_state.shear_modulus, untouched.shear_modulus);
  EXPECT_FALSE(sim.config.materials[2].reduction);
  EXPECT_EQ(sim.config.materials[1].reduction, 2.0);
}

}  // namespace
}  // namespace talus::postproc
