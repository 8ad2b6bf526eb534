// The preprocessor: the three scenes mesh and seed correctly (checked with geometry written
// here, independent of the CGAL code under test), holes, disjoint bodies and every seeding
// pattern behave, boundary conditions resolve per node, and bad input stops `talus mesh` with
// one message that names the file and the item, leaving no model.h5 behind.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <set>

#include "common/error.hpp"
#include "common/model.hpp"
#include "common/scene.hpp"
#include "preproc/boundary_conditions.hpp"
#include "preproc/polygon.hpp"
#include "preproc/preproc.hpp"
#include "preproc/seeding.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using testing::ScratchDir;
using Loops = std::vector<std::vector<Eigen::Vector2d>>;

// ---------------------------------------------------------------------------------------------
// Geometry written independently of preproc/polygon.cpp.

// Even-odd rule by ray casting along +x: a crossing of any loop edge flips the parity.
bool inside(const Loops& loops, const Eigen::Vector2d& p) {
  bool odd = false;
  for (const auto& loop : loops)
    for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
      const Eigen::Vector2d& a = loop[i];
      const Eigen::Vector2d& b = loop[j];
      if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()))
        odd = !odd;
    }
  return odd;
}

double twice_signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

Eigen::Vector3d barycentric(const Model& model, int32_t e, const Eigen::Vector2d& p) {
  const auto& t = model.triangles[e];
  const Eigen::Vector2d a = model.nodes[t[0]], b = model.nodes[t[1]], c = model.nodes[t[2]];
  const double whole = twice_signed_area(a, b, c);
  return {twice_signed_area(p, b, c) / whole, twice_signed_area(a, p, c) / whole, twice_signed_area(a, b, p) / whole};
}

double triangle_area(const Model& model, int32_t e) {
  const auto& t = model.triangles[e];
  return 0.5 * twice_signed_area(model.nodes[t[0]], model.nodes[t[1]], model.nodes[t[2]]);
}

int body_of(const Model& model, const std::string& name) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].name == name) return static_cast<int>(b);
  ADD_FAILURE() << "no body " << name;
  return -1;
}

// Mesh invariants that any Model written by `talus mesh` must satisfy.
void expect_valid_mesh(const Model& model) {
  std::vector<bool> used(model.nodes.size(), false);
  for (std::size_t e = 0; e < model.triangles.size(); ++e) {
    EXPECT_GT(triangle_area(model, static_cast<int32_t>(e)), 0) << "triangle " << e << " is not counter-clockwise";
    for (int32_t v : model.triangles[e]) used[v] = true;
    for (int k = 0; k < 3; ++k) {
      const int32_t n = model.neighbours[e][k];
      if (n < 0) continue;
      // The neighbour across the edge opposite vertex k lists e back, across the same edge.
      const auto& back = model.neighbours[n];
      const int kb = static_cast<int>(std::find(back.begin(), back.end(), static_cast<int32_t>(e)) - back.begin());
      ASSERT_LT(kb, 3) << "neighbours of " << e << " and " << n << " are not symmetric";
      const std::set<int32_t> edge{model.triangles[e][(k + 1) % 3], model.triangles[e][(k + 2) % 3]};
      const std::set<int32_t> edge_back{model.triangles[n][(kb + 1) % 3], model.triangles[n][(kb + 2) % 3]};
      EXPECT_EQ(edge, edge_back);
    }
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "node ids are not compact";
}

// Particle invariants: inside its body, inside its element, mass = density x volume, and
// volume = element area / particles per cell.
void expect_valid_particles(const Model& model, const Scene& scene) {
  ASSERT_EQ(model.bodies.size(), scene.bodies.size());
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const int b = model.body[p];
    const BodyInfo& body = model.bodies[b];
    ASSERT_TRUE(inside(body.loops, model.position[p])) << "particle " << p << " outside body " << body.name;
    const Eigen::Vector3d w = barycentric(model, model.element[p], model.position[p]);
    ASSERT_GT(w.minCoeff(), 0) << "particle " << p << " outside its element " << model.element[p];
    const double density = model.materials[body.material].density;
    ASSERT_NEAR(model.mass[p], density * model.volume[p], 1e-12 * model.mass[p]);
    const int ppc = scene.bodies[scene.body_index(body.name)].particles_per_cell;
    ASSERT_NEAR(model.volume[p], triangle_area(model, model.element[p]) / ppc, 1e-12 * model.volume[p]);
  }
}

std::map<std::string, double> volume_per_body(const Model& model) {
  std::map<std::string, double> volume;
  for (std::size_t p = 0; p < model.particle_count(); ++p) volume[model.bodies[model.body[p]].name] += model.volume[p];
  return volume;
}

struct Meshed {
  Scene scene;
  Model model;
  preproc::MeshReport report;
};

Meshed mesh_scene(const std::string& name, const std::vector<std::string>& overrides = {}) {
  Meshed m;
  m.scene = load_scene(testing::source_path("geometries/" + name + ".toml"), overrides);
  m.model = preproc::build_model(m.scene, &m.report);
  return m;
}

// gmsh sets OpenMP's thread count for the whole process when it starts and when it meshes; a
// solve after meshing in the same process (talus run, talus fos) must still get every core.
TEST(PreprocScenes, MeshingLeavesOpenMPsThreadCountAsItFoundIt) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  mesh_scene("spring_mass");
  EXPECT_EQ(omp_get_max_threads(), 3);
  omp_set_num_threads(before);
}

// ---------------------------------------------------------------------------------------------
// The three scenes at their own resolution. Their meshes follow every body edge, so the
// particles fill each body exactly: the seeded volume equals the area to rounding.

TEST(PreprocScenes, SpringMassFillsBothBodiesExactly) {
  const Meshed m = mesh_scene("spring_mass");
  expect_valid_mesh(m.model);
  expect_valid_particles(m.model, m.scene);
  const auto volume = volume_per_body(m.model);
  EXPECT_NEAR(volume.at("spring"), 0.1 * 1.0, 1e-9 * 0.1);
  EXPECT_NEAR(volume.at("mass"), 0.1 * 0.05, 1e-9 * 0.005);
  for (const auto& body : m.report.bodies) EXPECT_LT(std::abs(body.relative_difference), 1e-9) << body.name;
  // m = rho V: the validation's 5 kg block (per 0.1 m^2 cross-section, unit thickness).
  double block_mass = 0;
  for (std::size_t p = 0; p < m.model.particle_count(); ++p)
    if (m.model.body[p] == body_of(m.model, "mass")) block_mass += m.model.mass[p];
  EXPECT_NEAR(block_mass, 5.0, 1e-9);
  EXPECT_EQ(m.model.scene_name, "spring_mass");
  EXPECT_FALSE(m.model.contact.enabled);
}

TEST(PreprocScenes, BoxInclineFillsBothBodiesExactly) {
  const Meshed m = mesh_scene("box_incline");
  expect_valid_mesh(m.model);
  expect_valid_particles(m.model, m.scene);
  const auto volume = volume_per_body(m.model);
  EXPECT_NEAR(volume.at("box"), 0.15 * 0.10, 1e-9 * 0.015);
  EXPECT_NEAR(volume.at("surface"), 1.6 * 0.1 + 0.05 * 0.1, 1e-9 * 0.165);  // slab and wall
  EXPECT_TRUE(m.model.bodies[body_of(m.model, "surface")].fixed);
  EXPECT_FALSE(m.model.bodies[body_of(m.model, "box")].fixed);
  EXPECT_DOUBLE_EQ(m.model.contact.friction, 0.3);

  // The box's lower face lies on the surface line through the origin, inclined 30 degrees:
  // every box particle is above it, every surface particle below it (or in the wall).
  const Eigen::Vector2d up_slope_normal(std::sin(std::numbers::pi / 6), std::cos(std::numbers::pi / 6));
  for (std::size_t p = 0; p < m.model.particle_count(); ++p)
    if (m.model.body[p] == body_of(m.model, "box")) {
      EXPECT_GT(m.model.position[p].dot(up_slope_normal), 0);
    }
}

TEST(PreprocScenes, SlopeFillsTheSoilExactlyWithRollerSidesAndFixedBase) {
  const Meshed m = mesh_scene("slope");
  expect_valid_mesh(m.model);
  expect_valid_particles(m.model, m.scene);
  const double area = 6 * 5 + 0.5 * 5 * 5 / std::tan(50 * std::numbers::pi / 180);
  EXPECT_NEAR(volume_per_body(m.model).at("soil"), area, 1e-9 * area);
  EXPECT_NEAR(m.report.bodies.at(0).polygon_area, area, 1e-9 * area);
  EXPECT_EQ(m.report.particles, m.model.particle_count());
  EXPECT_TRUE(m.model.run.evs);

  // Every base node is fixed; every other side node is a roller with normal +-x.
  const std::set<int32_t> fixed(m.model.fixed_nodes.begin(), m.model.fixed_nodes.end());
  for (int32_t node : m.model.node_sets.at("base")) {
    EXPECT_EQ(m.model.nodes[node].y(), 0);
    EXPECT_TRUE(fixed.count(node));
  }
  std::set<int32_t> sides;
  for (const char* name : {"left", "right"})
    for (int32_t node : m.model.node_sets.at(name)) sides.insert(node);
  ASSERT_EQ(m.model.roller_nodes.size(), sides.size() - 2);  // the two base corners are fixed
  for (std::size_t r = 0; r < m.model.roller_nodes.size(); ++r) {
    EXPECT_TRUE(sides.count(m.model.roller_nodes[r]));
    EXPECT_NEAR(std::abs(m.model.roller_normals[r].x()), 1, 1e-12);
    EXPECT_NEAR(m.model.roller_normals[r].y(), 0, 1e-12);
  }
  EXPECT_TRUE(std::is_sorted(m.model.roller_nodes.begin(), m.model.roller_nodes.end()));
  EXPECT_TRUE(std::is_sorted(m.model.fixed_nodes.begin(), m.model.fixed_nodes.end()));
  EXPECT_TRUE(m.model.node_sets.count("top"));  // every named curve is a node set
}

// [mesh.parameters] reach the .geo's DefineConstant: the column is a L0 x a L0 rectangle.
TEST(PreprocScenes, ColumnCollapseTakesItsSizeFromMeshParameters) {
  const Meshed m = mesh_scene("column_collapse", {"mesh.parameters.a=2", "mesh.parameters.L0=0.05"});
  double x = 0, y = 0, volume = 0;
  for (std::size_t p = 0; p < m.model.particle_count(); ++p) {
    x = std::max(x, m.model.position[p].x());
    y = std::max(y, m.model.position[p].y());
    volume += m.model.volume[p];
  }
  EXPECT_NEAR(volume, 2 * 0.05 * 0.05, 1e-12);
  EXPECT_NEAR(x, 0.05, 0.005);
  EXPECT_NEAR(y, 0.1, 0.005);
}

TEST(PreprocScenes, MeshSizeOverridesTheGeo) {
  const Meshed coarse = mesh_scene("slope", {"mesh.size=0.5"});
  const Meshed fine = mesh_scene("slope", {"mesh.size=0.25"});
  // Halving the size quarters the element area.
  const double ratio = static_cast<double>(fine.model.triangles.size()) / coarse.model.triangles.size();
  EXPECT_GT(ratio, 3.5);
  EXPECT_LT(ratio, 4.5);
  double shortest = 1e9, longest = 0;
  for (const auto& t : coarse.model.triangles)
    for (int k = 0; k < 3; ++k) {
      const double length = (coarse.model.nodes[t[k]] - coarse.model.nodes[t[(k + 1) % 3]]).norm();
      shortest = std::min(shortest, length);
      longest = std::max(longest, length);
    }
  EXPECT_GT(shortest, 0.25);
  EXPECT_LT(longest, 0.9);
}

// ---------------------------------------------------------------------------------------------
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

Body make_body(const std::string& name, const std::string& group, int particles_per_cell) {
  Body body;
  body.name = name;
  body.group = group;
  body.material = "rock";
  body.particles_per_cell = particles_per_cell;
  return body;
}

Scene ring_scene(const std::string& geo, std::vector<Body> bodies, double size = 0.05) {
  Scene scene;
  scene.name = "ring";
  scene.path = "ring.toml";
  scene.geometry = geo;
  scene.mesh.size = size;
  Material rock;
  rock.name = "rock";
  rock.density = 2000;
  rock.youngs_modulus = 1e7;
  rock.poisson_ratio = 0.25;
  scene.materials = {rock};
  scene.bodies = std::move(bodies);
  scene.post.body = scene.bodies.front().name;
  return scene;
}

std::string write_file(const ScratchDir& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir.file(name)) << text;
  return dir.file(name);
}

TEST(PreprocSeeding, BodyWithAHoleHasNoParticlesInTheHole) {
  ScratchDir dir("preproc-hole");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  const Scene scene = ring_scene(geo, {make_body("ring", "ring", 4)});
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
  const Scene scene = ring_scene(geo, {make_body("ring", "ring", 3), make_body("core", "core", 6)});
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
    EXPECT_FALSE(inside(model.bodies[other].loops, model.position[p]));
    bodies_in_element[model.element[p]].insert(model.body[p]);
  }
  for (const auto& [element, bodies] : bodies_in_element) EXPECT_EQ(bodies.size(), 1u) << element;
}

TEST(PreprocSeeding, OverlappingBodiesAreAnError) {
  ScratchDir dir("preproc-overlap");
  const std::string geo = write_file(dir, "ring.geo", kRingGeo);
  const Scene scene = ring_scene(geo, {make_body("all", "domain", 4), make_body("core", "core", 4)});
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
    const Scene scene = ring_scene(geo, {make_body("all", "domain", ppc)}, 0.1);
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
  const Scene scene = ring_scene(geo, {make_body("wedge", "wedge", 6)}, 0.02);
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
  Body core = make_body("core", "core", 3);
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
  const Scene scene = ring_scene(geo, {make_body("granite", "granite", 4)});
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
  const Scene scene = ring_scene(geo, {make_body("speck", "speck", 1)}, 0.5);
  try {
    preproc::build_model(scene);
    FAIL() << "a body without particles was accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("bodies.speck"), std::string::npos) << message;
    EXPECT_NE(message.find("too coarse"), std::string::npos) << message;
  }
}

// ---------------------------------------------------------------------------------------------
// Loops and boundary conditions on hand-made input.

TEST(PreprocPolygon, ChainSplitsLoopsThatTouchAtAVertex) {
  // Two unit squares sharing the corner 2, listed in scrambled order and orientation.
  const std::vector<std::array<std::size_t, 2>> segments{{0, 1}, {2, 1}, {4, 5}, {3, 0}, {2, 3},
                                                         {5, 2}, {2, 6}, {6, 4}, {1, 2}};
  const auto loops = preproc::chain_loops(segments);
  ASSERT_TRUE(loops);
  ASSERT_EQ(loops->size(), 2u);
  for (const auto& loop : *loops) EXPECT_EQ(loop.size(), 4u);

  std::size_t open_end = 99;
  EXPECT_FALSE(preproc::chain_loops({{0, 1}, {1, 2}, {2, 3}}, &open_end));
  EXPECT_TRUE(open_end == 0 || open_end == 3);
}

TEST(PreprocPolygon, RegionAreaCountsHolesAndIslands) {
  auto square = [](double x0, double y0, double side) {
    return preproc::Loop{{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
  };
  // A 4x4 square, a 2x2 hole, a 1x1 island in the hole (given clockwise), and a separate piece.
  preproc::Loop island = square(1.5, 1.5, 1);
  std::reverse(island.begin(), island.end());
  const preproc::Region region({square(0, 0, 4), square(1, 1, 2), island, square(10, 0, 1)});
  EXPECT_DOUBLE_EQ(region.area(), 16 - 4 + 1 + 1);
  EXPECT_TRUE(region.contains({0.5, 0.5}));
  EXPECT_FALSE(region.contains({1.2, 1.2}));
  EXPECT_TRUE(region.contains({2, 2}));
  EXPECT_TRUE(region.contains({10.5, 0.5}));
  EXPECT_FALSE(region.contains({0, 2}));  // on the outline: not strictly inside
  EXPECT_TRUE(region.covers({0, 2}));
  EXPECT_NEAR(region.distance_to_boundary({5, 2}), 1, 1e-15);
}

TEST(PreprocBoundary, RollersAtACornerFixTheNodeAndFixedWins) {
  // Nodes: 0 (0,0), 1 (1,0), 2 (1,1), 3 (2,1) on a bent curve, 4 (0,1).
  const std::vector<Eigen::Vector2d> nodes{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {0, 1}};
  preproc::BoundaryCurve floor{"floor", BoundaryType::Roller, std::nullopt, {{0, 1}}};
  preproc::BoundaryCurve wall{"wall", BoundaryType::Roller, std::nullopt, {{2, 1}}};  // reversed on purpose
  preproc::BoundaryCurve ledge{"ledge", BoundaryType::Roller, Eigen::Vector2d(0, 2), {{2, 3}}};
  preproc::BoundaryCurve pin{"pin", BoundaryType::Fixed, std::nullopt, {{0, 4}}};
  const auto constraints = preproc::resolve_constraints(nodes, {floor, wall, ledge, pin});
  // 1: floor (normal y) meets wall (normal x) -> fixed. 2: wall (x) meets ledge (given y) -> fixed.
  // 0 and 4 are pinned. 3 is a roller with the given normal, normalised.
  EXPECT_EQ(constraints.fixed_nodes, (std::vector<int32_t>{0, 1, 2, 4}));
  ASSERT_EQ(constraints.roller_nodes, (std::vector<int32_t>{3}));
  EXPECT_EQ(constraints.roller_normals[0], Eigen::Vector2d(0, 1));
}

TEST(PreprocBoundary, CurveNormalIsTheAverageOfItsSegments) {
  // A roof: (0,0) -> (1,1) -> (2,0). At the ridge the two unit normals average to +-y.
  const std::vector<Eigen::Vector2d> nodes{{0, 0}, {1, 1}, {2, 0}};
  preproc::BoundaryCurve roof{"roof", BoundaryType::Roller, std::nullopt, {{0, 1}, {1, 2}}};
  const auto constraints = preproc::resolve_constraints(nodes, {roof});
  ASSERT_EQ(constraints.roller_nodes, (std::vector<int32_t>{0, 1, 2}));
  EXPECT_NEAR(std::abs(constraints.roller_normals[1].y()), 1, 1e-15);
  EXPECT_NEAR(constraints.roller_normals[1].x(), 0, 1e-15);
  EXPECT_NEAR(std::abs(constraints.roller_normals[0].dot(Eigen::Vector2d(1, -1).normalized())), 1, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Through the binary: one message naming the file and the item, status 1, no model left.

constexpr const char* kBlockGeo = R"(lc = 0.25;
Point(1) = {0, 0, 0, lc}; Point(2) = {2, 0, 0, lc}; Point(3) = {2, 1, 0, lc}; Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("domain") = {1};
Physical Surface("block") = {1};
Physical Curve("base") = {1};
// A closed curve that leaves the domain on the right.
Point(5) = {1.5, 0.2, 0, lc}; Point(6) = {2.5, 0.2, 0, lc}; Point(7) = {2.5, 0.6, 0, lc}; Point(8) = {1.5, 0.6, 0, lc};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Physical Curve("overhang") = {5, 6, 7, 8};
)";

struct BlockScene {
  std::string geometry = "block.geo";
  std::string body_group = "block";
  std::string model = "linear_elastic";
  std::string density = "2000.0";
  std::string youngs_modulus = "1.0e7";
  std::string size = "0.25";

  std::string text() const {
    return "[scene]\ngeometry = \"" + geometry + "\"\n[mesh]\nsize = " + size +
           "\n[run]\nend_time = 1.0\n[materials.rock]\nmodel = \"" + model + "\"\ndensity = " + density +
           "\nyoungs_modulus = " + youngs_modulus + "\npoisson_ratio = 0.25\n[bodies.block]\nmaterial = \"rock\"\n" +
           "group = \"" + body_group + "\"\n[boundaries.base]\ntype = \"fixed\"\n";
  }
};

struct Rejection {
  int status;
  std::string output;
  bool left_model;
};

Rejection run_mesh(const BlockScene& scene, const std::string& extra = "") {
  ScratchDir dir("preproc-cli");
  write_file(dir, "block.geo", kBlockGeo);
  write_file(dir, "bad.geo", "Point(1) = {0, 0, 0};\nLine(1) = {1, 2\nPhysical Surface(\"domain\") = {1};\n");
  const std::string toml = write_file(dir, "block.toml", scene.text());
  const std::string out = dir.file("out");
  const auto result = testing::run_talus("mesh " + toml + " --out " + out + " " + extra);
  namespace fs = std::filesystem;
  const bool left = fs::exists(out + "/model.h5") || fs::exists(out + "/model.h5.tmp");
  return {result.status, result.output, left};
}

void expect_rejected(const Rejection& r, const std::vector<const char*>& parts) {
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_FALSE(r.left_model) << "a model was left behind";
  for (const char* part : parts) EXPECT_NE(r.output.find(part), std::string::npos) << part << " not in: " << r.output;
  EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
}

TEST(PreprocCli, ValidSceneWritesAModelThatReadsBack) {
  ScratchDir dir("preproc-ok");
  const auto result =
      testing::run_talus("mesh " + testing::source_path("geometries/spring_mass.toml") + " --out " + dir.file("out"));
  ASSERT_EQ(result.status, 0) << result.output;
  const Model read = read_model(dir.file("out/model.h5"));
  const Meshed direct = mesh_scene("spring_mass");
  EXPECT_EQ(read.particle_count(), direct.model.particle_count());
  EXPECT_EQ(read.triangles, direct.model.triangles);
  EXPECT_EQ(read.fixed_nodes, direct.model.fixed_nodes);
  EXPECT_EQ(read.roller_nodes, direct.model.roller_nodes);
  EXPECT_NE(result.output.find("particles"), std::string::npos);
}

// Each case changes one thing in a valid scene and names what the message must contain.
struct BadInput {
  const char* what;
  std::function<void(BlockScene&)> change;
  std::string extra_arguments;
  std::vector<const char*> message_parts;
};

TEST(PreprocCli, EveryBadInputNamesItsFileAndItem) {
  const std::vector<BadInput> cases{
      {"missing .geo", [](BlockScene& s) { s.geometry = "nowhere.geo"; }, "",
       {"nowhere.geo", "no such geometry file", "block.toml"}},
      {"unparsable .geo", [](BlockScene& s) { s.geometry = "bad.geo"; }, "",
       {"bad.geo", "syntax error"}},  // gmsh's own words
      {"group absent from the .geo", [](BlockScene& s) { s.body_group = "granite"; }, "",
       {"block.geo", "granite", "bodies.block", "overhang"}},
      {"body outside the domain", [](BlockScene& s) { s.body_group = "overhang"; }, "",
       {"block.toml", "bodies.block", "outside the domain"}},
      {"unknown material model", [](BlockScene& s) { s.model = "plasticine"; }, "",
       {"block.toml", "materials.rock.model", "plasticine"}},
      {"zero density", [](BlockScene& s) { s.density = "0.0"; }, "", {"block.toml", "materials.rock.density"}},
      {"negative density", [](BlockScene& s) { s.density = "-1.0"; }, "", {"block.toml", "materials.rock.density"}},
      {"NaN density", [](BlockScene& s) { s.density = "nan"; }, "", {"block.toml", "materials.rock.density"}},
      {"zero modulus", [](BlockScene& s) { s.youngs_modulus = "0.0"; }, "",
       {"block.toml", "materials.rock.youngs_modulus"}},
      {"negative mesh size", [](BlockScene& s) { s.size = "-0.1"; }, "", {"block.toml", "mesh.size"}},
      {"zero mesh size by --set", [](BlockScene&) {}, "--set mesh.size=0", {"block.toml", "mesh.size"}},
      {"--set of a key that does not exist", [](BlockScene&) {}, "--set run.end_tme=2",
       {"block.toml", "run.end_tme", "end_time"}},
      {"unknown transfer", [](BlockScene&) {}, "--set run.transfer=flop",
       {"block.toml", "run.transfer", "flop", "xpic"}},
      {"pic_fraction without the PIC blend", [](BlockScene&) {}, "--set run.transfer=xpic --set run.pic_fraction=0.1",
       {"block.toml", "run.pic_fraction", "pic_blend"}},
      {"xpic_order without XPIC", [](BlockScene&) {}, "--set run.transfer=apic --set run.xpic_order=3",
       {"block.toml", "run.xpic_order", "xpic"}},
      {"XPIC of order 0", [](BlockScene&) {}, "--set run.transfer=xpic --set run.xpic_order=0",
       {"block.toml", "run.xpic_order", "[1, 100]"}},
      {"a .geo parameter the .geo does not declare", [](BlockScene&) {}, "--set mesh.parameters.width=2",
       {"block.geo", "mesh.parameters.width", "DefineConstant"}},
  };
  // The unchanged scene is valid, so each rejection below comes from its one change.
  const Rejection valid = run_mesh(BlockScene{});
  ASSERT_EQ(valid.status, 0) << valid.output;
  ASSERT_TRUE(valid.left_model);
  for (const auto& bad : cases) {
    SCOPED_TRACE(bad.what);
    BlockScene scene;
    bad.change(scene);
    expect_rejected(run_mesh(scene, bad.extra_arguments), bad.message_parts);
  }
}

}  // namespace
}  // namespace talus
