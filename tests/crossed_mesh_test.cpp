// mesh.pattern = "crossed": quadrilaterals cut by their diagonals into four triangles
// (preproc/gmsh_geometry.cpp, docs/slope.md "Crossed triangles"). Checked here: the cut is at
// the diagonals' crossing and the quadrilaterals have the size asked for, the particles still
// fill the bodies exactly, and the property the pattern exists for, counted on the discrete
// divergence of linear triangles: with every boundary node fixed, a Delaunay mesh admits no
// velocity field (but zero) whose divergence vanishes in every triangle, so plastic flow at
// constant volume locks; a crossed mesh admits one per interior corner and a half, less half a
// quadrilateral (2 N_corner - N_quad + 1 in all: the four triangles of a quadrilateral constrain
// its volume change three times, not four; Nagtegaal, Parks and Rice 1974).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "preproc/preproc.hpp"
#include "support/preproc_checks.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using testing::expect_valid_mesh;
using testing::expect_valid_particles;
using testing::mesh_scene;
using testing::Meshed;
using testing::ScratchDir;
using testing::twice_signed_area;
using testing::volume_per_body;
using testing::write_file;

constexpr const char* kSquareGeo = R"(lc = 0.2;
Point(1) = {0, 0, 0, lc}; Point(2) = {1, 0, 0, lc}; Point(3) = {1, 1, 0, lc}; Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("domain") = {1};
Physical Curve("sides") = {1, 2, 3, 4};
)";

// The unit square filled by one elastic body, one particle per cell.
Scene square_scene(const ScratchDir& dir, std::optional<double> size) {
  return testing::rock_scene("square", dir.file("square.toml"), write_file(dir, "square.geo", kSquareGeo), size,
                             {testing::rock_body("block", "domain", 1)});
}

Model mesh_square(const ScratchDir& dir, MeshPattern pattern, std::optional<double> size,
                  preproc::MeshReport* report) {
  Scene scene = square_scene(dir, size);
  scene.mesh.pattern = pattern;
  return preproc::build_model(scene, report);
}

// The interior nodes' velocity components (2 per node) that leave every triangle's divergence
// zero: the dimension of the null space of the triangles' divergence rows.
struct DivergenceCount {
  long unknowns = 0;
  long free_fields = 0;  // dimension of the divergence-free space
};

DivergenceCount divergence_free_fields(const Model& model) {
  std::vector<int> column(model.nodes.size(), -1);
  long unknowns = 0;
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    const Eigen::Vector2d& x = model.nodes[i];
    const bool boundary = std::min({x.x(), x.y(), 1 - x.x(), 1 - x.y()}) < 1e-9;
    if (!boundary) column[i] = static_cast<int>(unknowns), unknowns += 2;
  }
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(static_cast<long>(model.triangles.size()), unknowns);
  for (std::size_t e = 0; e < model.triangles.size(); ++e) {
    const auto& t = model.triangles[e];
    const Eigen::Vector2d a = model.nodes[t[0]], b = model.nodes[t[1]], c = model.nodes[t[2]];
    const double twice_area = twice_signed_area(a, b, c);
    // grad N_k of the linear triangle, times twice its area: the opposite edge turned a right angle.
    const Eigen::Vector2d corner[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const int col = column[t[k]];
      if (col < 0) continue;
      const Eigen::Vector2d edge = corner[(k + 2) % 3] - corner[(k + 1) % 3];
      const Eigen::Vector2d grad(-edge.y() / twice_area, edge.x() / twice_area);
      B(static_cast<long>(e), col) += grad.x();
      B(static_cast<long>(e), col + 1) += grad.y();
    }
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(B);
  lu.setThreshold(1e-9);
  return {unknowns, unknowns - lu.rank()};
}

TEST(CrossedMesh, QuadrilateralsOfTheSizeAreCutWhereTheirDiagonalsCross) {
  const Meshed crossed = mesh_scene("slope", {"mesh.size=0.5", "mesh.pattern=crossed"});
  const Meshed delaunay = mesh_scene("slope", {"mesh.size=0.5"});
  expect_valid_mesh(crossed.model);
  expect_valid_particles(crossed.model, crossed.scene);
  // The particles fill the soil exactly, as on the Delaunay mesh.
  EXPECT_NEAR(volume_per_body(crossed.model).at("soil"), volume_per_body(delaunay.model).at("soil"), 1e-9);
  const std::size_t quadrilaterals = crossed.report.quadrilaterals;
  const std::size_t halves = crossed.report.quadrilaterals_cut_in_two;
  ASSERT_GT(quadrilaterals, 0u);
  EXPECT_EQ(crossed.model.triangles.size(), 4 * quadrilaterals - 2 * halves);
  EXPECT_LT(halves, quadrilaterals / 100 + 1);

  // Each crossing point: a node in exactly four triangles, on both diagonals of the four outer
  // corners (each triangle's other two nodes, in turn around it).
  std::vector<std::vector<int32_t>> around(crossed.model.nodes.size());
  for (std::size_t e = 0; e < crossed.model.triangles.size(); ++e)
    for (int32_t n : crossed.model.triangles[e]) around[n].push_back(static_cast<int32_t>(e));
  std::size_t crossings = 0;
  double edge_sum = 0;
  std::size_t edges = 0;
  for (std::size_t n = 0; n < around.size(); ++n) {
    if (around[n].size() != 4) continue;
    // The outer edge of each triangle, ordered so that the corners chain around the centre.
    std::map<int32_t, int32_t> next;
    for (int32_t e : around[n]) {
      const auto& t = crossed.model.triangles[e];
      int k = 0;
      while (t[k] != static_cast<int32_t>(n)) ++k;
      next[t[(k + 1) % 3]] = t[(k + 2) % 3];
    }
    if (next.size() != 4) continue;
    std::vector<int32_t> corners{next.begin()->first};
    for (int k = 0; k < 4; ++k) {
      const auto link = next.find(corners.back());
      if (link == next.end()) break;  // a fan on the boundary: not a closed ring
      corners.push_back(link->second);
    }
    if (corners.size() != 5 || corners.back() != corners.front()) continue;
    corners.pop_back();
    const Eigen::Vector2d centre = crossed.model.nodes[n];
    auto on_segment = [&](int32_t p, int32_t q) {
      const Eigen::Vector2d a = crossed.model.nodes[p], b = crossed.model.nodes[q];
      return std::abs(twice_signed_area(a, b, centre)) < 1e-9 * (b - a).squaredNorm() &&
             (centre - a).dot(b - a) > 0 && (centre - b).dot(a - b) > 0;
    };
    if (!on_segment(corners[0], corners[2]) || !on_segment(corners[1], corners[3])) continue;
    ++crossings;
    for (int k = 0; k < 4; ++k, ++edges)
      edge_sum += (crossed.model.nodes[corners[k]] - crossed.model.nodes[corners[(k + 1) % 4]]).norm();
  }
  EXPECT_EQ(crossings, quadrilaterals - halves);
  // mesh.size is the quadrilateral's edge.
  const double mean_edge = edge_sum / static_cast<double>(edges);
  EXPECT_GT(mean_edge, 0.4);
  EXPECT_LT(mean_edge, 0.6);
}

TEST(CrossedMesh, AdmitsFlowAtConstantVolumeWhereDelaunayTrianglesLock) {
  ScratchDir dir("crossed-divergence");
  preproc::MeshReport crossed_report, delaunay_report;
  const Model crossed = mesh_square(dir, MeshPattern::Crossed, 0.125, &crossed_report);
  const Model delaunay = mesh_square(dir, MeshPattern::Delaunay, 0.125, &delaunay_report);
  ASSERT_EQ(crossed_report.quadrilaterals_cut_in_two, 0u);

  const DivergenceCount on_delaunay = divergence_free_fields(delaunay);
  EXPECT_GT(on_delaunay.unknowns, 20);
  EXPECT_EQ(on_delaunay.free_fields, 0);  // locked: more triangles than velocity unknowns

  const DivergenceCount on_crossed = divergence_free_fields(crossed);
  const long quads = static_cast<long>(crossed_report.quadrilaterals);
  const long interior_corners = (on_crossed.unknowns / 2) - quads;  // every crossing point is interior
  EXPECT_GT(interior_corners, 5);
  // 2 unknowns per interior corner and per crossing point, 3 independent constraints per
  // quadrilateral, and one fewer in all (the total volume change is zero with the boundary fixed).
  EXPECT_EQ(on_crossed.free_fields, 2 * interior_corners - quads + 1);
  EXPECT_GT(on_crossed.free_fields, 0);
}

TEST(CrossedMesh, WithoutMeshSizeTheGeosSizeIsTheQuadrilaterals) {
  // The square's .geo asks for lc = 0.2: without mesh.size its sizes are doubled for gmsh as
  // mesh.size would be, so the mesh is the one of mesh.size = 0.2 (a size left undoubled would
  // give about four times the quadrilaterals).
  ScratchDir dir("crossed-geo-size");
  preproc::MeshReport from_geo, from_size;
  const Model by_geo = mesh_square(dir, MeshPattern::Crossed, std::nullopt, &from_geo);
  const Model by_size = mesh_square(dir, MeshPattern::Crossed, 0.2, &from_size);
  ASSERT_GT(from_size.quadrilaterals, 0u);
  EXPECT_EQ(from_geo.quadrilaterals, from_size.quadrilaterals);
  EXPECT_EQ(by_geo.triangles.size(), by_size.triangles.size());
}

// The mesh report's note: a moving Mohr-Coulomb body on Delaunay triangles without EVS locks
// (the count above), so `talus mesh` says how to avoid it; crossed triangles, EVS, an elastic
// material or a fixed body need no note.
TEST(CrossedMesh, ReportNotesAPlasticBodyOnLockingDelaunayTriangles) {
  ScratchDir dir("crossed-locking-note");
  auto note_for = [&](MeshPattern pattern, bool evs, bool elastic, bool fixed) {
    Scene scene = square_scene(dir, 0.25);
    scene.mesh.pattern = pattern;
    scene.run.evs = evs;
    scene.materials[0].model = elastic ? MaterialParameters(LinearElastic::Parameters{})
                                       : MaterialParameters(MohrCoulomb::Parameters{.friction_angle = 30, .cohesion = 1e3});
    scene.bodies[0].fixed = fixed;
    preproc::MeshReport report;
    preproc::build_model(scene, &report);
    std::ostringstream printed;
    preproc::print_report(report, printed);
    EXPECT_EQ(report.locking_material.empty(), printed.str().find("note:") == std::string::npos) << printed.str();
    return report.locking_material;
  };
  EXPECT_EQ(note_for(MeshPattern::Delaunay, false, false, false), "rock");
  EXPECT_EQ(note_for(MeshPattern::Crossed, false, false, false), "");
  EXPECT_EQ(note_for(MeshPattern::Delaunay, true, false, false), "");
  EXPECT_EQ(note_for(MeshPattern::Delaunay, false, true, false), "");
  EXPECT_EQ(note_for(MeshPattern::Delaunay, false, false, true), "");
}

}  // namespace
}  // namespace talus
