// The slope scene end to end through the binary (validation.md, case 3): geometries/slope.toml
// at a coarse mesh (0.5 m) must fail from the toe, come to rest before its end time with every
// particle still in the domain, and report a runout. Reads results.h5 and metrics.json.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <sstream>
#include <vector>

#include "common/h5.hpp"
#include "support/test_support.hpp"

using namespace talus;
using talus::testing::run_talus;
using talus::testing::ScratchDir;
using talus::testing::json_number;
using talus::testing::read_text;
using talus::testing::source_path;

namespace {

// The slope of geometries/slope.geo: crest plateau at y = 5 m up to x = 6 m, a 50 degree face
// down to the toe on the base y = 0.
constexpr double kHeight = 5.0, kCrestX = 6.0;
const double kToeX = kCrestX + kHeight / std::tan(50.0 * M_PI / 180.0);

// Frame `frame` of a [frames, N, 2] dataset as N points.
std::vector<Eigen::Vector2d> points(const std::vector<double>& flat, std::size_t frame, std::size_t n) {
  std::vector<Eigen::Vector2d> result(n);
  for (std::size_t p = 0; p < n; ++p) result[p] = {flat[(frame * n + p) * 2], flat[(frame * n + p) * 2 + 1]};
  return result;
}

}  // namespace

TEST(SlopeScene, FailsFromTheToeComesToRestAndReportsTheRunout) {
  ScratchDir dir("slope");
  const auto run = run_talus("run " + source_path("geometries/slope.toml") + " --out " + dir.path().string() +
                             " -q --set mesh.size=0.5");
  // A particle leaving the domain is an error exit, so exit 0 also says none left.
  ASSERT_EQ(run.status, 0) << run.output;

  const h5::File results = h5::File::open_read(dir.file("results.h5"));
  EXPECT_EQ(h5::get_int(results, "/", "complete"), 1);
  const double end_time = h5::get_double(results, "settings/run", "end_time");
  const std::vector<double> time = h5::read_doubles(results, "frames/time");
  ASSERT_GE(time.size(), 3u);
  h5::Dims dims;
  const std::vector<double> position = h5::read_doubles(results, "frames/position", &dims);
  ASSERT_EQ(dims.size(), 3u);
  const std::size_t frames = dims[0], n = dims[1];
  ASSERT_EQ(frames, time.size());
  const std::vector<Eigen::Vector2d> initial = points(h5::read_doubles(results, "particles/initial_position"), 0, n);

  // At rest: the run stopped on its rest rule (kinetic energy below 1 % of its peak for
  // rest_window), before end_time, and the last recorded kinetic energy agrees.
  EXPECT_LT(time.back(), end_time - 1.0) << "the run did not stop at rest";
  const std::vector<double> kinetic = h5::read_doubles(results, "history/kinetic_energy");
  ASSERT_FALSE(kinetic.empty());
  const double peak = *std::max_element(kinetic.begin(), kinetic.end());
  EXPECT_GT(peak, 0);
  EXPECT_LT(kinetic.back(), 0.01 * peak);

  // It failed: some material moved by more than 0.5 m.
  const std::vector<Eigen::Vector2d> last = points(position, frames - 1, n);
  double largest = 0;
  for (std::size_t p = 0; p < n; ++p) largest = std::max(largest, (last[p] - initial[p]).norm());
  EXPECT_GT(largest, 0.5);

  // It failed from the toe. The slid mass moves almost as a block (the crest corner, which also
  // settles, moves most), so displacement does not show where failure starts; plastic shear
  // strain does. Rule: at the first frame in which some particle has moved by more than 0.1 m,
  // the 10 particles with the largest equivalent plastic shear strain all started in the lower
  // half of the slope (y < H / 2) and within one slope height H of the toe (x > x_toe - H).
  std::size_t onset = frames;
  for (std::size_t f = 1; f < frames && onset == frames; ++f) {
    const std::vector<Eigen::Vector2d> x = points(position, f, n);
    for (std::size_t p = 0; p < n && onset == frames; ++p)
      if ((x[p] - initial[p]).norm() > 0.1) onset = f;
  }
  ASSERT_LT(onset, frames) << "nothing moved by 0.1 m";
  const std::vector<double> plastic_strain = h5::read_doubles(results, "frames/plastic_strain");
  const double* strain = plastic_strain.data() + onset * n;
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::partial_sort(order.begin(), order.begin() + 10, order.end(),
                    [&](std::size_t a, std::size_t b) { return strain[a] > strain[b]; });
  EXPECT_GT(strain[order[9]], 0.01) << "no plastic strain at the onset";
  for (int k = 0; k < 10; ++k) {
    const Eigen::Vector2d& X = initial[order[k]];
    EXPECT_LT(X.y(), 0.5 * kHeight) << "particle from (" << X.x() << ", " << X.y() << ")";
    EXPECT_GT(X.x(), kToeX - kHeight) << "particle from (" << X.x() << ", " << X.y() << ")";
  }
  std::printf("onset at t = %.2f s; most strained particle from (%.2f, %.2f), plastic strain %.3f\n", time[onset],
              initial[order[0]].x(), initial[order[0]].y(), strain[order[0]]);

  // The postprocessor found the deposit beyond the toe.
  const std::string metrics = read_text(dir.file("metrics.json"));
  ASSERT_FALSE(metrics.empty()) << "no metrics.json";
  const double runout = json_number(metrics, "runout_distance_m");
  std::printf("runout %.2f m, last frame %.2f s of %.1f s, %zu particles\n", runout, time.back(), end_time, n);
  EXPECT_GT(runout, 0);

  // metrics.json is complete: every value the postprocessor promises, finite.
  for (const char* key : {"runout_distance_m", "crest_retreat_m", "travel_angle_deg", "failed_area_m2",
                          "bishop_fos", "time_to_rest_s"})
    EXPECT_TRUE(std::isfinite(json_number(metrics, key))) << key << " in " << metrics;
  for (const char* key : {"\"slip_circle\"", "\"bishop_circle\"", "\"failure_surface\": [["})
    EXPECT_NE(metrics.find(key), std::string::npos) << key;
  const std::string slip = metrics.substr(metrics.find("\"slip_circle\""));
  const Eigen::Vector2d centre(json_number(slip, "xc_m"), json_number(slip, "yc_m"));
  const double radius = json_number(slip, "r_m");
  ASSERT_TRUE(std::isfinite(centre.norm() + radius)) << slip.substr(0, 120);
  // The fitted slip circle passes near the toe (within two cells of 0.5 m) ...
  EXPECT_LT(std::abs((centre - Eigen::Vector2d(kToeX, 0)).norm() - radius), 1.0);
  // ... and comes out on the crest plateau (y = H) behind the crest, within two slope heights.
  ASSERT_GT(radius, std::abs(kHeight - centre.y()));
  const double exit_x = centre.x() - std::sqrt(radius * radius - (kHeight - centre.y()) * (kHeight - centre.y()));
  EXPECT_GT(exit_x, kCrestX - 2 * kHeight);
  EXPECT_LT(exit_x, kCrestX + 0.5);
  std::printf("slip circle centre (%.2f, %.2f) m, r %.2f m, exits the crest plateau at x = %.2f m\n", centre.x(),
              centre.y(), radius, exit_x);

  // The figures a report needs exist and are not empty.
  for (const char* figure : {"deformed.png", "front.png", "energy.png"}) {
    std::ifstream png(dir.file(figure), std::ios::binary);
    char magic[4] = {};
    png.read(magic, 4);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG") << figure;
  }
}
