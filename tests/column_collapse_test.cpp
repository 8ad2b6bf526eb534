// Validation case 4 (docs/column.md): the granular column collapse of
// geometries/column_collapse.toml at its own aspect ratio a = 0.5, through the binary, against
// Lube et al. (2005), 2D: (L_inf - L0) / L0 = 1.2 a, and the top of the deposit stays at H0.
// The other aspect ratios (1, 3, 6) are the runout benchmark's (talus bench runout).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>

#include "common/h5.hpp"
#include "support/test_support.hpp"

using namespace talus;
using talus::testing::run_talus;
using talus::testing::ScratchDir;
using talus::testing::source_path;

TEST(ColumnCollapse, RunsToRestWithinFifteenPercentOfLubesLawAndKeepsItsTop) {
  ScratchDir dir("column");
  const auto run = run_talus("run " + source_path("geometries/column_collapse.toml") + " --out " + dir.path().string() +
                             " -q --threads 1");
  // A particle leaving the domain is an error exit, so exit 0 also says none left.
  ASSERT_EQ(run.status, 0) << run.output;

  const h5::File results = h5::File::open_read(dir.file("results.h5"));
  EXPECT_EQ(h5::get_int(results, "/", "complete"), 1);
  const std::vector<double> time = h5::read_doubles(results, "frames/time");
  EXPECT_LT(time.back(), h5::get_double(results, "settings/run", "end_time") - 1.0) << "the run did not stop at rest";

  h5::Dims dims;
  const std::vector<double> flat = h5::read_doubles(results, "frames/position", &dims);
  const std::size_t frames = dims[0], n = dims[1];
  auto frame = [&](std::size_t f) {
    std::vector<Eigen::Vector2d> x(n);
    for (std::size_t p = 0; p < n; ++p) x[p] = {flat[(f * n + p) * 2], flat[(f * n + p) * 2 + 1]};
    return x;
  };
  const auto start = frame(0), end = frame(frames - 1);
  // The scene's column: L0 = 0.2 m, H0 = 0.1 m (a = 0.5); the particles fill it exactly.
  const double L0 = 0.2, H0 = 0.1, a = H0 / L0;
  double top = 0, right = 0;
  for (const auto& x : start) top = std::max(top, x.y()), right = std::max(right, x.x());
  ASSERT_NEAR(top, H0, 0.005);
  ASSERT_NEAR(right, L0, 0.005);

  const auto deposit = talus::testing::column_deposit(end, 0.005);
  const double runout = (deposit.tip - L0) / L0;
  const double law = *talus::testing::lube_runout(a);  // 0.6
  EXPECT_NEAR(runout / law, 1.0, 0.15) << "runout " << runout << " against " << law;
  // Below a = 1.15 the top of the column does not move: the deposit's height is the column's,
  // measured on the same particle rows (the highest particle sits h/6 below H0).
  EXPECT_NEAR(deposit.height / top, 1.0, 0.01);
  EXPECT_LE(deposit.detached, 5) << "grains thrown clear of the deposit";

  // What a user reads: talus post's runout from the released face's foot (x = L0), and the
  // final height, against the same law and the same top.
  const std::string metrics = talus::testing::read_text(dir.file("metrics.json"));
  const double post_runout = talus::testing::json_number(metrics, "runout_distance_m") / L0;
  EXPECT_NEAR(post_runout / law, 1.0, 0.15) << metrics;
  EXPECT_NEAR(talus::testing::json_number(metrics, "final_height_m") / top, 1.0, 0.01) << metrics;
  EXPECT_NE(metrics.find("\"toe_m\": [0.2, 0]"), std::string::npos) << metrics;
}
