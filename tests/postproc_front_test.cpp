// Runout from any body's initial front: the foot of a slope face, of a vertical cliff, or of a
// collapsing column's free side. Synthetic particle sets whose answers are known by
// construction, and `talus post` on a column whose results are written in code.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "postproc/analysed_slope.hpp"
#include "postproc/postproc.hpp"
#include "postproc/results.hpp"
#include "postproc/runout.hpp"
#include "support/test_support.hpp"

namespace talus::postproc {
namespace {

constexpr double kSpacing = 0.1;  // particle spacing (m)

// Particles at cell centres of the region below `top(x)` for x0 < x < x1, y > 0.
template <class Top>
std::vector<Eigen::Vector2d> fill(double x0, double x1, Top top) {
  std::vector<Eigen::Vector2d> points;
  for (double x = x0 + kSpacing / 2; x < x1; x += kSpacing)
    for (double y = kSpacing / 2; y < top(x); y += kSpacing) points.emplace_back(x, y);
  return points;
}

// A column 2 m wide and 1 m high (a = 0.5) against a wall at x = 0.
const Polyline kColumn = {{0, 0}, {2, 0}, {2, 1}, {0, 1}};

TEST(Front, AColumnThatRanOutHasItsFreeSideAsTheFace) {
  const SlopeProfile profile = slope_profile(kColumn, true);
  EXPECT_EQ(profile.crest, Eigen::Vector2d(2, 1));
  EXPECT_EQ(profile.toe, Eigen::Vector2d(2, 0));
  EXPECT_DOUBLE_EQ(profile.height, 1);
  EXPECT_DOUBLE_EQ(surface_height(profile.surface, 1.9), 1);
  EXPECT_DOUBLE_EQ(surface_height(profile.surface, 2.1), 0);  // the base beyond the column
  // Without having moved, a level top has no face: the slope metrics refuse it.
  EXPECT_DOUBLE_EQ(slope_profile(kColumn).height, 0);
  // The side it moved to decides.
  EXPECT_FALSE(descends_to_left(kColumn, 0.3));
  EXPECT_TRUE(descends_to_left(kColumn, -0.3));
}

TEST(Front, CollapsedColumnRunoutAndFinalHeight) {
  // The column's top stays at H0 = 1 near the wall (a = 0.5: Lube's undisturbed top), and the
  // collapse leaves a wedge from x = 1 down to a blunt front 0.5 m thick at x = 3.2 on the base:
  // the tip is the last particle column's centre, 3.15, a runout of 1.15 m.
  const SlopeProfile profile = slope_profile(kColumn, true);
  const auto initial = fill(0, 2, [](double) { return 1.0; });
  const auto final = fill(0, 3.2, [](double x) { return x < 1 ? 1.0 : 1.0 - 0.5 * (x - 1) / 2.2; });
  const ColumnRule rule = column_rule_for(std::vector<double>(10, kSpacing * kSpacing));
  const RunoutMetrics m = runout_metrics(profile, initial, final, 0.05, rule);
  ASSERT_TRUE(m.deposit_found);
  EXPECT_NEAR(m.tip.x(), 3.2 - kSpacing / 2, 1e-9);
  EXPECT_NEAR(m.runout_distance, 1.2 - kSpacing / 2, 1e-9);
  EXPECT_NEAR(m.final_height, 1 - kSpacing / 2, 1e-12);  // the highest particle centre
  EXPECT_GT(m.crest_retreat, 0.5);  // the top dropped from x of about 1 to the face
}

TEST(Front, AVerticalCliffsToeIsTheFootOfItsFace) {
  // Plateau at 8 m to x = 4, a vertical face down to a bench at 2 m that runs to x = 10.
  const Polyline cliff = {{0, 0}, {10, 0}, {10, 2}, {4, 2}, {4, 8}, {0, 8}};
  const SlopeProfile profile = slope_profile(cliff);
  EXPECT_EQ(profile.crest, Eigen::Vector2d(4, 8));
  EXPECT_EQ(profile.toe, Eigen::Vector2d(4, 2));
  EXPECT_DOUBLE_EQ(profile.height, 6);
  EXPECT_TRUE(has_vertical_face(profile.surface));
  EXPECT_DOUBLE_EQ(surface_height(profile.surface, 3.999), 8);
  EXPECT_DOUBLE_EQ(surface_height(profile.surface, 4.001), 2);
  // Bishop's method of slices needs the ground as a function of x: no circle, not a wrong one.
  BodyInfo body;
  body.name = "cliff";
  body.loops = {cliff};
  EXPECT_FALSE(critical_circle(analysed_slope(body, {"results.h5"}), {1e4, 30, 2e4}));
  // An overhang is refused.
  EXPECT_THROW(slope_profile({{0, 0}, {10, 0}, {10, 2}, {3, 2}, {4, 8}, {0, 8}}), Error);
}

// `talus post` on a column against a wall at x = 4 that collapses towards -x: the runout is
// measured from its free side's foot at x = 2, in the mirrored frame, with the final height.
TEST(Front, TalusPostReportsAColumnsRunout) {
  Results r;
  r.metadata.scene_name = "synthetic_column";
  BodyInfo body;
  body.name = "column";
  body.loops = {{{2, 0}, {4, 0}, {4, 1}, {2, 1}}};
  r.metadata.bodies = {body};
  Material sand = testing::mohr_coulomb(1800, 1e7, 0.3, 30, 0);
  sand.name = "sand";
  r.metadata.materials = {sand};
  r.metadata.post.metrics = {"runout"};
  // In the column's own frame (wall at 0, free side at 2): each particle spreads away from the
  // wall the more the lower it sits, x' = x (1 + 0.6 (1 - y)); the top row stays nearly put.
  const auto column = fill(0, 2, [](double) { return 1.0; });
  std::vector<Eigen::Vector2d> spread;
  for (const auto& p : column) spread.emplace_back(p.x() * (1 + 0.6 * (1 - p.y())), p.y());
  auto to_scene = [](std::vector<Eigen::Vector2d> points) {  // x -> 4 - x: the wall at x = 4
    for (auto& p : points) p.x() = 4 - p.x();
    return points;
  };
  r.initial_position = to_scene(column);
  const std::size_t n = column.size();
  r.body.assign(n, 0);
  r.volume.assign(n, kSpacing * kSpacing);
  r.mass.assign(n, 1800 * kSpacing * kSpacing);
  r.frame_time = {0, 1};
  r.position = {r.initial_position, to_scene(spread)};
  r.velocity.assign(2, std::vector<Eigen::Vector2d>(n, Eigen::Vector2d::Zero()));
  r.history_time = {0, 1};
  r.kinetic_energy = {0, 0};
  r.potential_energy = {0, 0};
  r.strain_energy = {0, 0};

  testing::ScratchDir dir("postproc-front");
  write_results(dir.file("results.h5"), r);
  std::ostringstream log;
  PostOptions options;
  options.figures_script = testing::source_path("postproc/figures.py");  // the figures draw a column too
  ASSERT_EQ(run_post(dir.file("results.h5"), dir.path().string(), log, options), 0) << log.str();
  EXPECT_TRUE(std::filesystem::exists(dir.file("deformed.png")));
  const std::string json = testing::read_text(dir.file("metrics.json"));
  // The library's runout on the column's own frame, where its free side's foot is at (2, 0).
  const RunoutMetrics expected = runout_metrics(slope_profile(kColumn, true), column, spread, 0.05,
                                                column_rule_for(r.volume));
  ASSERT_TRUE(expected.deposit_found);
  EXPECT_GT(expected.runout_distance, 0.5);
  EXPECT_NEAR(testing::json_number(json, "runout_distance_m"), expected.runout_distance, 1e-9);
  EXPECT_NEAR(testing::json_number(json, "final_height_m"), 1 - kSpacing / 2, 1e-9);
  EXPECT_DOUBLE_EQ(testing::json_number(json, "slope_height_m"), 1);
  EXPECT_NE(json.find("\"toe_m\": [2, 0]"), std::string::npos) << json;
}

}  // namespace
}  // namespace talus::postproc
