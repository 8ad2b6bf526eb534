// Factor of safety by shear strength reduction (solver/strength_reduction.hpp, `talus fos`):
// the bracket search on a mocked trial function, Griffiths and Lane's (1999) example 1 against
// its published factor, and a long shallow cohesionless slope against the infinite-slope value
// tan(phi) / tan(beta).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "common/error.hpp"
#include "solver/strength_reduction.hpp"
#include "support/test_support.hpp"

using namespace talus;
using solver::SearchSettings;
using solver::TrialOutcome;

namespace {

// A slope that fails exactly above `critical`; counts the trials it is asked for.
struct MockSlope {
  explicit MockSlope(double critical_factor) : critical(critical_factor) {}
  double critical;
  int trials = 0;
  std::vector<int> batch_sizes;
  std::vector<TrialOutcome> operator()(const std::vector<double>& factors) {
    batch_sizes.push_back(static_cast<int>(factors.size()));
    std::vector<TrialOutcome> out;
    for (double f : factors) {
      ++trials;
      TrialOutcome o;
      o.factor = f;
      o.failed = f > critical;
      o.reason = o.failed ? "displacement limit" : "equilibrium";
      out.push_back(o);
    }
    return out;
  }
};

solver::SearchResult search(MockSlope& slope, SearchSettings settings) {
  return solver::search_factor_of_safety([&](const std::vector<double>& f) { return slope(f); }, settings);
}

using talus::testing::json_number;
using talus::testing::read_text;

}  // namespace

TEST(FosSearch, TrisectionBracketsTheCriticalFactorAboveOne) {
  MockSlope slope(1.2345);
  SearchSettings settings;
  settings.workers = 2;
  const auto r = search(slope, settings);
  EXPECT_LE(r.lower, 1.2345);
  EXPECT_GT(r.upper, 1.2345);
  EXPECT_LE(r.upper - r.lower, 0.01 + 1e-12);
  EXPECT_NEAR(r.factor, 1.2345, 0.005 + 1e-12);
  // Expansion 1.5, 2.25 (one round), then trisection of [1, 1.5]: 0.5 / 3^k <= 0.01 needs k = 4.
  EXPECT_EQ(r.rounds, 5);
  EXPECT_EQ(slope.trials, 10);
  for (int size : slope.batch_sizes) EXPECT_EQ(size, 2);
  ASSERT_GE(r.upper_trial, 0);
  EXPECT_TRUE(r.trials[r.upper_trial].failed);
  EXPECT_DOUBLE_EQ(r.trials[r.upper_trial].factor, r.upper);
}

TEST(FosSearch, OneWorkerIsBisection) {
  MockSlope slope(1.2345);
  SearchSettings settings;
  settings.workers = 1;
  settings.failed_factor = 2.0;
  const auto r = search(slope, settings);
  // [1, 2] halved until its width is <= 0.01: 2^-7 = 0.0078, seven trials.
  EXPECT_EQ(slope.trials, 7);
  EXPECT_NEAR(r.upper - r.lower, 1.0 / 128, 1e-12);
  EXPECT_LE(r.lower, 1.2345);
  EXPECT_GT(r.upper, 1.2345);
}

TEST(FosSearch, SlopeThatFailsAsBuiltIsSearchedBelowOne) {
  MockSlope slope(0.7312);
  SearchSettings settings;
  settings.stable_factor = 0.5;  // the equilibrium was reached with the strength doubled
  settings.failed_factor = 1.0;  // and not at F = 1
  settings.tolerance = 0.001;
  const auto r = search(slope, settings);
  EXPECT_LT(r.factor, 1.0);
  EXPECT_LE(r.lower, 0.7312);
  EXPECT_GT(r.upper, 0.7312);
  EXPECT_LE(r.upper - r.lower, 0.001 + 1e-12);
  for (const auto& t : r.trials) EXPECT_TRUE(t.factor > 0.5 && t.factor < 1.0);
}

TEST(FosSearch, ExpandsUntilAFailureAndRejectsBadInput) {
  MockSlope strong(7.0);
  SearchSettings settings;
  const auto r = search(strong, settings);
  EXPECT_NEAR(r.factor, 7.0, 0.005 + 1e-12);

  MockSlope never(1e9);
  EXPECT_THROW(search(never, settings), Error);
  settings.failed_factor = 0.9;  // at or below the stable factor
  MockSlope any(1.0);
  EXPECT_THROW(search(any, settings), Error);
}

// Griffiths, D. V. and Lane, P. A. (1999), "Slope stability analysis by finite elements",
// Geotechnique 49(3):387-403, example 1 (geometries/griffiths_lane.toml): strength reduction
// gives F = 1.4 (their first non-converged trial; 1.35 converged), the charts of Bishop and
// Morgenstern (1960) 1.380. Default (coarse) resolution, within 5%.
TEST(FosTextbook, GriffithsLaneExample1WithinFivePercent) {
  talus::testing::ScratchDir dir("fos_griffiths_lane");
  const auto run = talus::testing::run_talus("fos " + talus::testing::source_path("geometries/griffiths_lane.toml") + " --out " +
                                      dir.path().string() + " --threads 2 --quiet");
  ASSERT_EQ(run.status, 0) << run.output;
  const std::string json = read_text(dir.file("fos.json"));
  const double factor = json_number(json, "factor_of_safety");
  std::cout << "Griffiths and Lane example 1: F = " << factor << " (published 1.4, charts 1.380), Bishop "
            << json_number(json, "bishop_fos") << "\n";
  EXPECT_NEAR(factor, 1.4, 0.05 * 1.4) << json;
  // The postproc's Bishop search on the same slope agrees with the charts.
  EXPECT_NEAR(json_number(json, "bishop_fos"), 1.38, 0.05 * 1.38);
  EXPECT_LE(json_number(json, "upper") - json_number(json, "lower"), 0.01 + 1e-9);
  // A slip surface came out of the first failing trial, and the figure was drawn.
  EXPECT_NE(json.find("\"slip_surface\": ["), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir.file("fos.png")));
  EXPECT_EQ(json.find("\"fails_as_built\": true"), std::string::npos);
}

// A long shallow slope of beta = 20 deg and height H = 4 m, 4 m of crest and 6 m of toe over a
// 1 m foundation: the .geo, and the scene with `material` and `extra` tables appended.
void write_infinite_slope(const talus::testing::ScratchDir& dir, double beta, const std::string& material,
                          const std::string& extra) {
  const double H = 4.0;
  const double run = H / std::tan(beta * M_PI / 180);
  {
    std::ofstream geo(dir.file("infinite.geo"));
    geo << "H = " << H << "; crest = 4; toe = crest + " << run << "; W = toe + 6; F = 1; D = F + H + 1.5;\n"
        << "lc = 0.4;\n"
           "Point(1) = {0, 0, 0, lc}; Point(2) = {W, 0, 0, lc}; Point(3) = {W, F, 0, lc};\n"
           "Point(4) = {toe, F, 0, lc}; Point(5) = {crest, F + H, 0, lc}; Point(6) = {0, F + H, 0, lc};\n"
           "Point(7) = {W, D, 0, lc}; Point(8) = {0, D, 0, lc};\n"
           "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6};\n"
           "Line(6) = {6, 1}; Line(7) = {3, 7}; Line(8) = {7, 8}; Line(9) = {8, 6};\n"
           "Curve Loop(1) = {1, 2, 3, 4, 5, 6}; Plane Surface(1) = {1};\n"
           "Curve Loop(2) = {-3, 7, 8, 9, -5, -4}; Plane Surface(2) = {2};\n"
           "Physical Surface(\"domain\") = {1, 2}; Physical Surface(\"soil\") = {1};\n"
           "Physical Curve(\"base\") = {1}; Physical Curve(\"left\") = {6, 9}; Physical Curve(\"right\") = {2, 7};\n";
  }
  std::ofstream toml(dir.file("infinite.toml"));
  toml << "[scene]\nname = \"infinite\"\ngeometry = \"infinite.geo\"\n"
          "[mesh]\nsize = 0.4\n"
          "[run]\nend_time = 10.0\ncfl = 0.5\nevs = true\n"
          "[materials.sand]\nmodel = \"mohr_coulomb\"\ndensity = 2000.0\nyoungs_modulus = 2.0e7\n"
          "poisson_ratio = 0.3\ncohesion = 50.0\ndilation_angle = 0.0\n"
       << material
       << "[bodies.soil]\nmaterial = \"sand\"\n"
          "[boundaries.base]\ntype = \"fixed\"\n[boundaries.left]\ntype = \"roller\"\n"
          "[boundaries.right]\ntype = \"roller\"\n"
          "[post]\nmetrics = [\"bishop\"]\n"
       << extra;
}

std::string run_fos(const talus::testing::ScratchDir& dir) {
  const auto result = talus::testing::run_talus("fos " + dir.file("infinite.toml") + " --out " + dir.path().string() +
                                                " --threads 2 --quiet --tolerance=0.02");
  EXPECT_EQ(result.status, 0) << result.output;
  return read_text(dir.file("fos.json"));
}

// phi = 30 deg with a token cohesion (c / (gamma H) = 0.0006, against the apex's zero stiffness
// at a stress-free surface): the critical slip is shallow and parallel to the face,
// F -> tan(phi) / tan(beta) = 1.586.
TEST(FosInfiniteSlope, ShallowCohesionlessSlopeApproachesTanPhiOverTanBeta) {
  talus::testing::ScratchDir dir("fos_infinite_slope");
  const double beta = 20.0;
  write_infinite_slope(dir, beta, "friction_angle = 30.0\n", "");
  const std::string json = run_fos(dir);
  const double expected = std::tan(30 * M_PI / 180) / std::tan(beta * M_PI / 180);
  std::cout << "infinite slope: F = " << json_number(json, "factor_of_safety") << ", tan(phi)/tan(beta) = " << expected
            << ", Bishop " << json_number(json, "bishop_fos") << "\n";
  EXPECT_NEAR(json_number(json, "factor_of_safety"), expected, 0.10 * expected) << json;
}

// The same slope of a cohesionless mu(I) sand with mu_s = sin 30 deg (docs/column.md, "The mu(I)
// material"): strength reduction takes tan(phi) / F of sin(phi) = mu, so F -> tan 30 deg /
// tan(beta) = 1.586 as for the Mohr-Coulomb sand above; Bishop's method takes tan(phi) = mu_s on
// the slip surface, F = mu_s / tan(beta) = 1.374. Measured: 1.625 and 1.3737.
TEST(FosInfiniteSlope, MuOfISandIsReducedAsTheMohrCoulombSandOfSinPhiEqualToMuStatic) {
  talus::testing::ScratchDir dir("fos_infinite_slope_mu_i");
  const double beta = 20.0, mu_s = 0.5;
  write_infinite_slope(dir, beta, "friction_angle = 30.0\n", "");
  std::string scene = read_text(dir.file("infinite.toml"));
  const std::size_t begin = scene.find("[materials.sand]"), end = scene.find("[bodies.soil]");
  ASSERT_NE(begin, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  scene.replace(begin, end - begin,
                "[materials.sand]\nmodel = \"mu_i\"\ndensity = 2000.0\nyoungs_modulus = 2.0e7\npoisson_ratio = 0.3\n"
                "mu_static = 0.5\nmu_limit = 0.7\ninertial_number_scale = 0.279\ngrain_diameter = 1.0e-3\n");
  std::ofstream(dir.file("infinite.toml")) << scene;
  const std::string json = run_fos(dir);
  const double tan_beta = std::tan(beta * M_PI / 180);
  const double expected = std::tan(std::asin(mu_s)) / tan_beta;
  EXPECT_NEAR(json_number(json, "factor_of_safety"), expected, 0.10 * expected) << json;
  EXPECT_NEAR(json_number(json, "bishop_fos"), mu_s / tan_beta, 0.02 * mu_s / tan_beta) << json;
}

// The same slope with phi = 40 deg, saturated below a water table at the ground surface
// (rho_sat = 2400 kg/m3). With u = gamma_w z at the vertical depth z below the table
// (docs/water.md), an infinite slope has
//   F = (1 - gamma_w / (gamma_sat cos^2 beta)) tan(phi) / tan(beta) = 1.2176.
// Measured: talus fos 1.258 (+3.3 %), Bishop on this finite slope 1.2575 (the long-slope check
// of Bishop, within 2 %, is postproc_bishop_test's).
TEST(FosInfiniteSlope, WaterTableAtTheSurfaceWithinFivePercent) {
  talus::testing::ScratchDir dir("fos_infinite_slope_water");
  const double beta = 20.0, H = 4.0;
  const double toe = 4 + H / std::tan(beta * M_PI / 180);
  std::ostringstream water;
  water << "[water]\ntable = [[0.0, 5.0], [4.0, 5.0], [" << toe << ", 1.0], [" << toe + 6 << ", 1.0]]\n";
  write_infinite_slope(dir, beta, "friction_angle = 40.0\nsaturated_density = 2400.0\n", water.str());
  const std::string json = run_fos(dir);
  const double b = beta * M_PI / 180;
  const double expected =
      (1 - 9810 / (2400 * 9.81 * std::cos(b) * std::cos(b))) * std::tan(40 * M_PI / 180) / std::tan(b);
  std::cout << "infinite slope under water: F = " << json_number(json, "factor_of_safety") << ", closed form "
            << expected << ", Bishop " << json_number(json, "bishop_fos") << "\n";
  EXPECT_NEAR(json_number(json, "factor_of_safety"), expected, 0.05 * expected) << json;
  EXPECT_NE(json.find("\"unit_weight_N_m3\": 9810"), std::string::npos) << json;  // fos.json names the table
}
