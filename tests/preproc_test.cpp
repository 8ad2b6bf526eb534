// The preprocessor: the three scenes mesh and seed correctly (checked with geometry written
// independently of the CGAL code under test, support/preproc_checks.hpp), loops and boundary
// conditions resolve on hand-made input, and bad input stops `talus mesh` with one message that
// names the file and the item, leaving no model.h5 behind. Seeding on scenes written here:
// preproc_seeding_test.cpp.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <set>

#include "common/error.hpp"
#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "preproc/boundary_conditions.hpp"
#include "preproc/polygon.hpp"
#include "preproc/preproc.hpp"
#include "support/preproc_checks.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using testing::body_of;
using testing::expect_valid_mesh;
using testing::expect_valid_particles;
using testing::mesh_scene;
using testing::Meshed;
using testing::ScratchDir;
using testing::volume_per_body;
using testing::write_file;

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
  EXPECT_FALSE(m.model.run.evs);  // crossed triangles: no locking to relieve

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

TEST(PreprocScenes, TrianglesFollowACurveAndNodesAreNumberedAsTheTrianglesNameThem) {
  // The solver's particles follow the element order and its grid phases the node order: the
  // mesh is ordered so that neighbours in space are neighbours in memory.
  const Meshed m = mesh_scene("slope");
  const auto& triangles = m.model.triangles;
  const int32_t nodes = static_cast<int32_t>(m.model.nodes.size());
  int32_t next = 0;  // node ids appear for the first time in increasing order
  for (const auto& t : triangles)
    for (int32_t i : t) {
      ASSERT_LE(i, next);
      if (i == next) ++next;
    }
  EXPECT_EQ(next, nodes);
  // A triangle's nodes are close in memory: their id spread averages 2.4 % of the node count on
  // the slope (gmsh's own numbering: 24 %).
  double spread = 0;
  for (const auto& t : triangles) spread += *std::max_element(t.begin(), t.end()) - *std::min_element(t.begin(), t.end());
  EXPECT_LT(spread / static_cast<double>(triangles.size()), 0.05 * nodes);
  // Consecutive triangles are near each other: the mean distance between consecutive centroids
  // is 0.38 m with 0.25 m elements (gmsh's order: 5.9 m).
  const auto centroid = [&](std::size_t e) {
    const auto& t = triangles[e];
    return Eigen::Vector2d((m.model.nodes[t[0]] + m.model.nodes[t[1]] + m.model.nodes[t[2]]) / 3.0);
  };
  double step = 0;
  for (std::size_t e = 1; e < triangles.size(); ++e) step += (centroid(e) - centroid(e - 1)).norm();
  EXPECT_LT(step / static_cast<double>(triangles.size() - 1), 2 * 0.25);
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

// A value outside its DefineConstant's Min and Max is refused before gmsh meshes it (gmsh
// itself would take a = 1e9 and mesh a domain that fills the memory).
TEST(PreprocScenes, MeshParameterOutsideItsDeclaredRangeIsRefused) {
  ScratchDir dir("mesh-parameter-range");
  const std::filesystem::path out = dir.path() / "out";
  const auto result = testing::run_talus("mesh " + testing::source_path("geometries/column_collapse.toml") +
                                         " --set mesh.parameters.a=1e9 --out " + out.string());
  EXPECT_NE(result.status, 0);
  EXPECT_NE(result.output.find("column_collapse.geo"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("mesh.parameters.a: got 1e+09, expected a value in [0.1, 20]"), std::string::npos)
      << result.output;
  EXPECT_FALSE(std::filesystem::exists(out / "model.h5"));
}

TEST(PreprocScenes, MeshSizeOverridesTheGeo) {
  const Meshed coarse = mesh_scene("slope", {"mesh.size=0.5", "mesh.pattern=delaunay"});
  const Meshed fine = mesh_scene("slope", {"mesh.size=0.25", "mesh.pattern=delaunay"});
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
      {"APIC on linear triangles", [](BlockScene&) {}, "--set run.transfer=apic",
       {"block.toml", "run.transfer", "apic", "bspline", "cpdi"}},
      {"XPIC of order 0", [](BlockScene&) {}, "--set run.transfer=xpic --set run.xpic_order=0",
       {"block.toml", "run.xpic_order", "[1, 100]"}},
      {"unknown integration", [](BlockScene&) {}, "--set run.integration=gauss",
       {"block.toml", "run.integration", "gauss", "mixed"}},
      {"full_cell_fill without mixed integration", [](BlockScene&) {}, "--set run.full_cell_fill=0.5",
       {"block.toml", "run.full_cell_fill", "mixed"}},
      {"a full-cell fill of 0", [](BlockScene&) {}, "--set run.integration=mixed --set run.full_cell_fill=0",
       {"block.toml", "run.full_cell_fill"}},
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
