// The preprocessor's seeding on scenes written here: holes, disjoint and overlapping bodies,
// every seeding pattern, a body drawn off the mesh, initial stress and velocity, and the errors
// of a missing group or a body too small for the mesh. Checked with the independent geometry of
// support/preproc_checks.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "common/error.hpp"
#include "common/geometry.hpp"
#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "preproc/preproc.hpp"
#include "preproc/seeding.hpp"
#include "support/preproc_checks.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using testing::expect_valid_mesh;
using testing::rock_body;
using testing::expect_valid_particles;
using testing::ScratchDir;
using testing::twice_signed_area;
using testing::volume_per_body;
using testing::write_file;

// Scenes written here: a unit square domain split into a ring (surface 1) around a core
// (surface 2, the square [0.3, 0.7]^2), plus a free-standing closed curve.

constexpr const char* kRingGeo = R"(lc = 0.1;
Point(1) = {0, 0, 0, lc}; Point(2) = {1, 0, 0, lc}; Point(3) = {1, 1, 0, lc}; Point(4) = {0, 1, 0, lc};
Point(5) = {0.3, 0.3, 0, lc}; Point(6) = {0.7, 0.3, 0, lc}; Point(7) = {0.7, 0.7, 0, lc}; Point(8) = {0.3, 0.7, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2}; Plane Surface(2) = {2};
Physical Surface("domain") = {1, 2};
Physical Surface("ring") = {1};
Physical Surface("core") = {2};
Physical Curve("bottom") = {1};
Physical Curve("left") = {4};
Physical Curve("right") = {2};
// A triangle drawn apart from the surfaces: gmsh meshes it as curves only.
Point(9) = {0.12, 0.11, 0, lc}; Point(10) = {0.93, 0.2, 0, lc}; Point(11) = {0.41, 0.87, 0, lc};
Line(9) = {9, 10}; Line(10) = {10, 11}; Line(11) = {11, 9};
Physical Curve("wedge") = {9, 10, 11};
)";

Scene ring_scene(const std::string& geo, std::vector<Body> bodies, double size = 0.05) {
  return testing::rock_scene("ring", "ring.toml", geo, size, std::move(bodies));
}

TEST(PreprocSeeding, BodyWithAHoleHasNoParticlesInTheHole) {
  ScratchDir dir("preproc-hole");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  const Scene scene = ring_scene(geo, {rock_body("ring", "ring", 4)});
  preproc::MeshReport report;
  const Model model = preproc::build_model(scene, &report);
  expect_valid_mesh(model);
  expect_valid_particles(model, scene);
  ASSERT_EQ(model.bodies[0].loops.size(), 2u);  // the outer square and the hole
  for (const auto& x : model.position)
    EXPECT_FALSE(x.x() > 0.3 && x.x() < 0.7 && x.y() > 0.3 && x.y() < 0.7) << x.transpose();
  EXPECT_NEAR(volume_per_body(model).at("ring"), 1 - 0.16, 1e-12);
  EXPECT_NEAR(report.bodies[0].polygon_area, 1 - 0.16, 1e-12);
}

TEST(PreprocSeeding, TwoBodiesGetDisjointParticles) {
  ScratchDir dir("preproc-two");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  const Scene scene = ring_scene(geo, {rock_body("ring", "ring", 3), rock_body("core", "core", 6)});
  const Model model = preproc::build_model(scene);
  expect_valid_particles(model, scene);
  const auto volume = volume_per_body(model);
  EXPECT_NEAR(volume.at("ring"), 0.84, 1e-12);
  EXPECT_NEAR(volume.at("core"), 0.16, 1e-12);
  // No particle of one lies in the other, and no element holds particles of both (the mesh
  // follows the shared edge).
  std::map<int32_t, std::set<int32_t>> bodies_in_element;
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const int other = 1 - model.body[p];
    EXPECT_FALSE(inside_loops(model.bodies[other].loops, model.position[p]));
    bodies_in_element[model.element[p]].insert(model.body[p]);
  }
  for (const auto& [element, bodies] : bodies_in_element) EXPECT_EQ(bodies.size(), 1u) << element;
}

TEST(PreprocSeeding, OverlappingBodiesAreAnError) {
  ScratchDir dir("preproc-overlap");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  const Scene scene = ring_scene(geo, {rock_body("all", "domain", 4), rock_body("core", "core", 4)});
  try {
    preproc::build_model(scene);
    FAIL() << "overlapping bodies were accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bodies.all"), std::string::npos) << message;
    EXPECT_NE(message.find("bodies.core"), std::string::npos) << message;
    EXPECT_NE(message.find("overlap"), std::string::npos) << message;
  }
}

TEST(PreprocSeeding, EveryPatternFillsEveryTriangleOfTheDomain) {
  ScratchDir dir("preproc-ppc");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  for (int ppc : preproc::kSupportedParticlesPerCell) {
    const Scene scene = ring_scene(geo, {rock_body("all", "domain", ppc)}, 0.1);
    const Model model = preproc::build_model(scene);
    EXPECT_EQ(model.particle_count(), ppc * model.triangles.size()) << ppc;
    EXPECT_NEAR(volume_per_body(model).at("all"), 1.0, 1e-12) << ppc;
    std::vector<int> per_element(model.triangles.size(), 0);
    for (int32_t e : model.element) ++per_element[e];
    EXPECT_EQ(*std::min_element(per_element.begin(), per_element.end()), ppc);
    EXPECT_EQ(*std::max_element(per_element.begin(), per_element.end()), ppc);
  }
}

TEST(PreprocSeeding, PatternsAreInteriorAndCentredOnTheCentroid) {
  for (int ppc : preproc::kSupportedParticlesPerCell) {
    const auto pattern = preproc::seed_pattern(ppc);
    ASSERT_EQ(static_cast<int>(pattern.size()), ppc);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::set<std::tuple<double, double, double>> distinct;
    for (const auto& w : pattern) {
      EXPECT_NEAR(w.sum(), 1, 1e-15);
      EXPECT_GT(w.minCoeff(), 0.05) << ppc;  // well inside, never on an edge
      mean += w / ppc;
      distinct.insert({w[0], w[1], w[2]});
    }
    // Equal weights and the centroid as mean: the rule integrates linear fields exactly, so
    // the particles' first moment is the triangle's.
    EXPECT_NEAR((mean - Eigen::Vector3d::Constant(1.0 / 3)).norm(), 0, 1e-15) << ppc;
    EXPECT_EQ(static_cast<int>(distinct.size()), ppc);
  }
  EXPECT_TRUE(preproc::seed_pattern(2).empty());
  EXPECT_TRUE(preproc::seed_pattern(5).empty());
}

TEST(PreprocSeeding, ClosedCurveBodyOffTheMeshIsSeededToWithinTwoPercent) {
  ScratchDir dir("preproc-curve");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  const Scene scene = ring_scene(geo, {rock_body("wedge", "wedge", 6)}, 0.02);
  preproc::MeshReport report;
  const Model model = preproc::build_model(scene, &report);
  expect_valid_particles(model, scene);
  const Eigen::Vector2d a(0.12, 0.11), b(0.93, 0.2), c(0.41, 0.87);
  const double area = 0.5 * twice_signed_area(a, b, c);
  EXPECT_NEAR(report.bodies[0].polygon_area, area, 1e-12);
  EXPECT_LT(std::abs(volume_per_body(model).at("wedge") - area), 0.02 * area);
  EXPECT_GT(std::abs(report.bodies[0].relative_difference), 0);  // the mesh does not follow this outline
}

TEST(PreprocSeeding, GeostaticStressAndInitialVelocity) {
  ScratchDir dir("preproc-stress");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  Body core = rock_body("core", "core", 3);
  core.initial_stress = InitialStress{0.5, std::nullopt};
  core.initial_velocity = {1.5, -2};
  Scene scene = ring_scene(geo, {core});
  scene.run.gravity = {0, -10};
  const Model model = preproc::build_model(scene);
  ASSERT_GT(model.particle_count(), 0u);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const double sigma_yy = -2000 * 10 * (0.7 - model.position[p].y());  // surface: the core's top
    EXPECT_NEAR(model.stress[p][1], sigma_yy, 1e-9 * std::abs(sigma_yy));
    EXPECT_NEAR(model.stress[p][0], 0.5 * sigma_yy, 1e-9 * std::abs(sigma_yy));
    EXPECT_NEAR(model.stress[p][2], 0.5 * sigma_yy, 1e-9 * std::abs(sigma_yy));
    EXPECT_EQ(model.stress[p][3], 0);
    EXPECT_EQ(model.velocity[p], Eigen::Vector2d(1.5, -2));
  }
}

TEST(PreprocSeeding, MissingGroupErrorListsTheGroupsOfTheGeo) {
  ScratchDir dir("preproc-missing");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  const Scene scene = ring_scene(geo, {rock_body("granite", "granite", 4)});
  try {
    preproc::build_model(scene);
    FAIL() << "a missing group was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    for (const char* part : {"granite", "ring.geo", "bodies.granite", "core", "wedge"})
      EXPECT_NE(message.find(part), std::string::npos) << part << " not in: " << message;
  }
}

TEST(PreprocSeeding, BodyTooSmallForTheMeshIsAnError) {
  ScratchDir dir("preproc-small");
  const std::string geo = write_file(dir, "tiny.geo", R"(
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("domain") = {1};
Point(5) = {0.001, 0.001, 0}; Point(6) = {0.002, 0.001, 0}; Point(7) = {0.002, 0.002, 0};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 5};
Physical Curve("speck") = {5, 6, 7};
)");
  const Scene scene = ring_scene(geo, {rock_body("speck", "speck", 1)}, 0.5);
  try {
    preproc::build_model(scene);
    FAIL() << "a body without particles was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bodies.speck"), std::string::npos) << message;
    EXPECT_NE(message.find("too coarse"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace talus
