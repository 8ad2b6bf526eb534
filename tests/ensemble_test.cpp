// `talus ensemble` (workflow/ensemble.hpp, docs/ensemble.md): the statistics against their
// definitions, the rows of realisations.csv read back as written, bad input refused with nothing
// written, an interrupted ensemble resumed to the same CSV as an uninterrupted one (and on another
// --jobs), and the fully correlated limit of a Tresca clay slope against its closed form
// P(c_u < mean / F), F from `talus fos` at the mean.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>
#include <thread>

#include "support/test_support.hpp"
#include "workflow/ensemble_report.hpp"
#include "workflow/ensemble_statistics.hpp"

using namespace talus;
using talus::testing::json_number;
using talus::testing::read_text;
using talus::testing::run_talus;
using talus::testing::ScratchDir;
using talus::testing::source_path;
namespace fs = std::filesystem;

namespace {

// The default slope's scene, coarse, with the geometry by its absolute path and `extra` appended.
std::string slope_scene(const ScratchDir& dir, const std::string& extra, const std::string& name = "scene.toml") {
  std::string text = read_text(source_path("geometries/slope.toml"));
  text = std::regex_replace(text, std::regex("geometry = \"slope.geo\""),
                            "geometry = \"" + source_path("geometries/slope.geo") + "\"");
  text = std::regex_replace(text, std::regex("size = 0.25"), "size = 1.0");
  const std::string path = dir.file(name);
  std::ofstream(path) << text << "\n" << extra;
  return path;
}

const char* kRandomCohesion = R"(
[random.cohesion]
material = "sand"
parameter = "cohesion"
distribution = "lognormal"
mean = 3000.0
cov = 0.5
correlation_length = [10.0, 2.0]
)";

// The rows of a realisations.csv, without its first (fingerprint) line.
std::string rows_of(const std::string& path) {
  const std::string text = read_text(path);
  return text.substr(text.find('\n') + 1);
}

long lines_of(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

}  // namespace

TEST(EnsembleStatistics, WilsonIntervalHasItsClosedFormsAndCoverage) {
  const double z = workflow::kZ95, z2 = z * z;
  for (std::size_t n : {1, 7, 40, 1000}) {
    // k = 0: [0, z^2 / (n + z^2)]; k = n: its mirror.
    const auto none = workflow::wilson_interval(0, n);
    EXPECT_NEAR(none.lower, 0, 1e-15);
    EXPECT_NEAR(none.upper, z2 / (n + z2), 1e-14);
    const auto all = workflow::wilson_interval(n, n);
    EXPECT_NEAR(all.lower, n / (n + z2), 1e-14);
    EXPECT_NEAR(all.upper, 1, 1e-15);
  }
  // Coverage: over many binomial samples the interval holds p about 95 % of the time (the Wilson
  // interval's coverage at n = 50 stays within 93-97 % for p in [0.1, 0.9]).
  std::mt19937_64 random(2024);
  for (double p : {0.1, 0.3, 0.5}) {
    std::binomial_distribution<int> draw(50, p);
    int covered = 0;
    const int samples = 4000;
    for (int s = 0; s < samples; ++s) {
      const auto band = workflow::wilson_interval(static_cast<std::size_t>(draw(random)), 50);
      covered += band.lower <= p && p <= band.upper;
    }
    EXPECT_NEAR(covered / static_cast<double>(samples), 0.95, 0.025) << "p = " << p;
  }
}

TEST(EnsembleStatistics, QuantilesExceedanceAndReach) {
  // Type 7: h = (n - 1) q between the order statistics.
  EXPECT_DOUBLE_EQ(workflow::quantile({5, 1, 4, 2, 3}, 0.5), 3);
  EXPECT_DOUBLE_EQ(workflow::quantile({5, 1, 4, 2, 3}, 0.9), 4.6);
  EXPECT_DOUBLE_EQ(workflow::quantile({2}, 0.95), 2);
  const auto curve = workflow::exceedance({0, 0, 1, 2, 3}, {-1, 0, 1.5, 3});
  EXPECT_EQ(curve.probability, (std::vector<double>{1.0, 0.6, 0.4, 0.0}));
  for (std::size_t i = 0; i < curve.at.size(); ++i) {
    EXPECT_LE(curve.lower[i], curve.probability[i]);
    EXPECT_GE(curve.upper[i], curve.probability[i]);
  }
  std::vector<workflow::RealisationRow> rows(4);
  rows[0].failed = true, rows[0].crown_x = 2, rows[0].tip_x = 8;
  rows[1].failed = true, rows[1].crown_x = 4, rows[1].tip_x = 6;
  rows[2].failed = false, rows[2].crown_x = 0, rows[2].tip_x = 10;  // not failed: reaches nothing
  rows[3].failed = true, rows[3].crown_x = -5, rows[3].tip_x = -7;  // a slope descending to -x
  const auto along = workflow::reach(rows, {-6, 3, 5, 7, 9});
  EXPECT_EQ(along.probability, (std::vector<double>{0.25, 0.25, 0.5, 0.25, 0.0}));
}

TEST(EnsembleReport, RowsReadBackAsWrittenAndCutLinesAreDropped) {
  const ScratchDir dir("ensemble_rows");
  workflow::RealisationRow a;
  a.index = 3, a.seed = 1234567890123ull, a.failed = true, a.runout = 1.0 / 3, a.crest_retreat = std::sqrt(2.0);
  a.failed_area = 12.5e-7, a.travel_angle = 31.25, a.crown_x = -0.1, a.tip_x = 17.0 / 7, a.steps = 4321;
  a.simulated_time = 4.75, a.field_means = {1234.5, 0.1};
  workflow::RealisationRow b;
  b.index = 0, b.seed = 1234567890120ull, b.solved = false, b.message = "blow-up, at t = 1\nsee";
  b.crown_x = b.tip_x = std::nan(""), b.field_means = {std::nan(""), 2.0 / 3};
  const std::vector<std::string> fields{"c", "phi"};
  const std::string path = dir.file("realisations.csv");
  workflow::write_rows(path, 42, fields, {a, b});
  long dropped = -1;
  auto rows = workflow::read_rows(path, 42, fields, dropped);
  EXPECT_EQ(dropped, 0);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(workflow::csv_line(rows.at(a.seed)), workflow::csv_line(a));
  EXPECT_EQ(rows.at(b.seed).message, "blow-up; at t = 1;see");
  EXPECT_FALSE(rows.at(b.seed).travel_angle.has_value());
  EXPECT_EQ(workflow::csv_line(rows.at(b.seed)), workflow::csv_line(b));
  // Other fields: the rows do not fit.
  EXPECT_TRUE(workflow::read_rows(path, 42, {"c"}, dropped).empty());
  // Other inputs: nothing of it is used.
  EXPECT_TRUE(workflow::read_rows(path, 43, fields, dropped).empty());
  // A line cut short by a kill is dropped, the finished ones kept.
  std::ofstream(path, std::ios::app) << workflow::csv_line(a).substr(0, 20);
  rows = workflow::read_rows(path, 42, fields, dropped);
  EXPECT_EQ(rows.size(), 2u);
  EXPECT_EQ(dropped, 1);
}

TEST(EnsembleCommand, BadInputIsRefusedWithNothingWritten) {
  const ScratchDir dir("ensemble_bad");
  const std::string with_field = slope_scene(dir, kRandomCohesion);
  const std::string without = slope_scene(dir, "", "plain.toml");
  const std::string out = dir.file("out");
  struct Case {
    std::string arguments, expected;
  };
  const std::vector<Case> cases = {
      {with_field + " --realisations 0", "--realisations: expected a positive integer, got '0'"},
      {with_field + " --realisations many", "--realisations: expected a positive integer"},
      {with_field + " --seed -3", "--seed: expected an integer from 0 to 9007199254740991, got '-3'"},
      {with_field + " --seed 1e3", "--seed: expected an integer"},
      {with_field + " --seed 9007199254740991 --realisations 2", "--seed: the seeds S to S + N - 1 must be at most"},
      {with_field + " --jobs 0", "--jobs: expected an integer from 1"},
      {with_field + " --threads 2", "--threads belongs to"},
      {with_field + " --fos", "ensemble: unknown option '--fos'"},
      {without, "random: the scene has no [random.NAME] table"},
      {with_field + " --set random.cohesion.cov=-1", "random.cohesion.cov"},
  };
  for (const Case& c : cases) {
    const auto run = run_talus("ensemble " + c.arguments + " --out " + out);
    EXPECT_EQ(run.status, 1) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.expected), std::string::npos) << c.arguments << "\n" << run.output;
    EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << run.output;  // one message
    EXPECT_FALSE(fs::exists(out)) << c.arguments;
  }
  const auto other = run_talus("fos " + with_field + " --seed 3");
  EXPECT_EQ(other.status, 1);
  EXPECT_NE(other.output.find("--realisations, --seed and --jobs belong to ensemble, not fos"), std::string::npos);
}

// An ensemble stopped by SIGINT keeps its finished rows; the same command again runs the rest, and
// the CSV is the one an uninterrupted ensemble writes, whatever --jobs.
TEST(EnsembleCommand, InterruptedThenResumedGivesTheSameCsvAsUninterrupted) {
  const ScratchDir dir("ensemble_resume");
  const std::string scene = slope_scene(dir, kRandomCohesion);
  const std::string common = "ensemble " + scene + " --realisations 6 --seed 11 -q";
  const auto whole = run_talus(common + " --jobs 2 --out " + dir.file("whole"));
  ASSERT_EQ(whole.status, 0) << whole.output;
  const std::string expected = rows_of(dir.file("whole/realisations.csv"));
  EXPECT_EQ(lines_of(expected), 7);  // header and six rows
  EXPECT_TRUE(fs::exists(dir.file("whole/ensemble.json")));

  // Stopped once two realisations are in its CSV (on one job the others follow one by one, each
  // taking seconds), by a shell that sends SIGINT to the talus it started.
  const std::string parts = dir.file("parts");
  std::ostringstream command;
  command << TALUS_BINARY << " " << common << " --jobs 1 --out " << parts << " > " << dir.file("stopped.log")
          << " 2>&1 & pid=$!; for i in $(seq 1200); do [ \"$(grep -c '' " << parts
          << "/realisations.csv 2>/dev/null)\" -ge 4 ] && break; sleep 0.1; done; kill -INT $pid; wait $pid; echo status $?";
  const auto stopped = talus::testing::run_shell(command.str());
  ASSERT_NE(stopped.output.find("status 130"), std::string::npos) << stopped.output;
  const std::string stopped_log = read_text(dir.file("stopped.log"));
  EXPECT_NE(stopped_log.find("interrupted by SIGINT"), std::string::npos) << stopped_log;
  EXPECT_FALSE(fs::exists(parts + "/ensemble.json"));
  const std::string kept = rows_of(parts + "/realisations.csv");
  EXPECT_GE(lines_of(kept), 3) << stopped_log;  // the header and the two rows it waited for
  EXPECT_LT(lines_of(kept), 7) << stopped_log;
  EXPECT_EQ(expected.compare(0, kept.size(), kept), 0) << "the rows kept are the first ones, as the whole wrote them";
  const auto resumed = run_talus(common + " --jobs 1 --out " + parts);
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_EQ(rows_of(parts + "/realisations.csv"), expected);
  EXPECT_EQ(json_number(read_text(parts + "/ensemble.json"), "probability_of_failure"),
            json_number(read_text(dir.file("whole/ensemble.json")), "probability_of_failure"));
}

// Correlation lengths of inf: each realisation is one value of c_u, so the slope fails exactly
// when c_u < mean / F, F the factor of safety at the mean. A Tresca clay (phi = 0) on Griffiths and
// Lane's 2:1 slope, loaded by a gravity ramp with damping so that the runs are quasi-static as in
// `talus fos`: P(c_u < mean / F) from the lognormal must lie in the ensemble's 95 % interval.
TEST(EnsembleValidation, FullyCorrelatedTrescaSlopeMatchesTheClosedForm) {
  const ScratchDir dir("ensemble_tresca");
  const double mean = 25e3, cov = 0.3;
  std::string text = read_text(source_path("geometries/griffiths_lane.toml"));
  text = std::regex_replace(text, std::regex("geometry = \"griffiths_lane.geo\""),
                            "geometry = \"" + source_path("geometries/griffiths_lane.geo") + "\"");
  std::ostringstream random;
  random << "\n[random.undrained]\nmaterial = \"soil\"\nparameter = \"cohesion\"\ndistribution = \"lognormal\"\n"
         << "mean = " << mean << "\ncov = " << cov << "\ncorrelation_length = [inf, inf]\n";
  const std::string scene = dir.file("tresca.toml");
  std::ofstream(scene) << text << random.str();
  const std::string sets = " --set materials.soil.friction_angle=0 --set materials.soil.cohesion=" +
                           std::to_string(mean) +
                           " --set materials.soil.youngs_modulus=2e7 --set run.gravity_ramp=3 --set run.damping=0.05"
                           " --set run.end_time=12 --set run.rest_ratio=0 --set mesh.size=2";
  const auto fos = run_talus("fos " + scene + sets + " -q --out " + dir.file("fos"));
  ASSERT_EQ(fos.status, 0) << fos.output;
  const std::string fos_json = read_text(dir.file("fos/fos.json"));
  const double F = json_number(fos_json, "factor_of_safety");
  ASSERT_TRUE(F > 0.9 && F < 1.5) << F;  // the scene is meant to be near failure
  // phi = 0: F = c_u / c_crit, so the bracket of F is one of c_crit; widened by the bracket's
  // tolerance (0.01), since the ensemble's ramped runs and fos's damped trials find c_crit each to
  // about that (docs/ensemble.md: 2 of 400 realisations failed 0.1 % above the bracket).
  const double c_low = mean / json_number(fos_json, "upper") / 1.01, c_high = mean / json_number(fos_json, "lower") * 1.01;

  const long n = 40;
  const auto run = run_talus("ensemble " + scene + sets + " --realisations " + std::to_string(n) +
                             " --seed 100 -q --out " + dir.file("ensemble"));
  ASSERT_EQ(run.status, 0) << run.output;
  const std::string json = read_text(dir.file("ensemble/ensemble.json"));
  const double sigma = std::sqrt(std::log1p(cov * cov)), mu = std::log(mean) - sigma * sigma / 2;
  const double exact = 0.5 * std::erfc(-(std::log(mean / F) - mu) / (sigma * std::numbers::sqrt2));
  const double estimate = json_number(json, "probability_of_failure");
  const std::regex band("\"probability_of_failure_95\": \\[([^,]+), ([^\\]]+)\\]");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(json, m, band)) << json;
  const double lower = std::stod(m[1]), upper = std::stod(m[2]);
  std::cout << "fully correlated Tresca slope: F = " << F << ", P(c_u < mean / F) = " << exact << ", ensemble "
            << estimate << " (95 % Wilson " << lower << " .. " << upper << ", " << n << " realisations)\n";
  EXPECT_GE(exact, lower);
  EXPECT_LE(exact, upper);

  // Realisation by realisation: each is one c_u (mean_undrained), and it fails exactly when c_u
  // is below c_crit, outside the (widened) bracket of `fos`.
  std::istringstream csv(read_text(dir.file("ensemble/realisations.csv")));
  std::string line;
  std::getline(csv, line);
  std::getline(csv, line);
  ASSERT_NE(line.find(",failed,"), std::string::npos);
  int rows = 0, outside = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    ASSERT_GE(f.size(), 14u) << line;
    const bool failed = f[3] == "1";
    const double c_u = std::stod(f[13]);
    ++rows;
    if (c_u > c_low && c_u < c_high) continue;
    ++outside;
    EXPECT_EQ(failed, c_u < c_low) << "c_u = " << c_u << ", c_crit in " << c_low << " .. " << c_high;
  }
  EXPECT_EQ(rows, n);
  EXPECT_GE(outside, n - 4);
}
