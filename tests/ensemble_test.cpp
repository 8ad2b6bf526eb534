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

// `talus ARGUMENTS --out OUT` started by a shell, which sends it SIGINT once OUT/realisations.csv
// has `lines` lines (each realisation takes seconds, so few more follow), waits for it and says
// "status S"; then runs `after`. The talus's own output goes to LOG.
talus::testing::CommandResult stopped_once_rows_are_in(const std::string& arguments, const std::string& out,
                                                       const std::string& log, int lines,
                                                       const std::string& after = "") {
  std::ostringstream command;
  command << TALUS_BINARY << " " << arguments << " --out " << out << " > " << log
          << " 2>&1 & pid=$!; for i in $(seq 1200); do [ \"$(cat " << out
          << "/realisations.csv 2>/dev/null | grep -c '')\" -ge " << lines
          << " ] && break; sleep 0.1; done; kill -INT $pid; wait $pid; echo status $?; " << after;
  return talus::testing::run_shell(command.str());
}

// The rows of `talus ensemble ARGUMENTS --out OUT`, which must succeed.
std::string rows_of_run(const std::string& arguments, const std::string& out) {
  const auto run = run_talus(arguments + " --out " + out);
  EXPECT_EQ(run.status, 0) << run.output;
  return rows_of(out + "/realisations.csv");
}

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

  // --fos: a column fos, empty when the search found none; a CSV of the other kind is not read.
  a.fos = 1.0 / 7, b.fos.reset();
  workflow::write_rows(path, 42, fields, {a, b}, true);
  rows = workflow::read_rows(path, 42, fields, dropped, true);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows.at(a.seed).fos, a.fos);
  EXPECT_FALSE(rows.at(b.seed).fos.has_value());
  EXPECT_EQ(workflow::csv_line(rows.at(a.seed), true), workflow::csv_line(a, true));
  EXPECT_NE(read_text(path).find(",mean_c,mean_phi,fos,message\n"), std::string::npos);
  EXPECT_TRUE(workflow::read_rows(path, 42, fields, dropped, false).empty());
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
      {with_field + " --frobnicate", "ensemble: unknown option '--frobnicate'"},
      {with_field + " --tolerance 0.02", "--tolerance: the bracket width of --fos's search; give --fos with it"},
      {with_field + " --fos --tolerance 1e-300", "--tolerance: got 1e-300, below"},
      {with_field + " --ranks 0", "--ranks: expected an integer from 1 to 256, got '0'"},
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
  const auto fos_flag = run_talus("run " + with_field + " --fos");
  EXPECT_EQ(fos_flag.status, 1);
  EXPECT_NE(fos_flag.output.find("--fos belongs to ensemble"), std::string::npos) << fos_flag.output;
}

// An ensemble stopped by SIGINT keeps its finished rows; the same command again runs the rest, and
// the CSV is the one an uninterrupted ensemble writes, whatever --jobs.
TEST(EnsembleCommand, InterruptedThenResumedGivesTheSameCsvAsUninterrupted) {
  const ScratchDir dir("ensemble_resume");
  const std::string scene = slope_scene(dir, kRandomCohesion);
  const std::string common = "ensemble " + scene + " --realisations 6 --seed 11 -q";
  const std::string expected = rows_of_run(common + " --jobs 2", dir.file("whole"));
  EXPECT_EQ(lines_of(expected), 7);  // header and six rows
  EXPECT_TRUE(fs::exists(dir.file("whole/ensemble.json")));

  // Stopped once two realisations are in its CSV (on one job the others follow one by one, each
  // taking seconds), by a shell that sends SIGINT to the talus it started.
  const std::string parts = dir.file("parts");
  const auto stopped = stopped_once_rows_are_in(common + " --jobs 1", parts, dir.file("stopped.log"), 4);
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

// The Tresca clay of Griffiths and Lane's 2:1 slope with c_u lognormal (mean 25 kPa, cov 0.3) and
// fully correlated, written into `dir` (tresca.toml), and the settings that make its runs
// quasi-static (docs/ensemble.md, "The fully correlated limit").
std::string tresca_scene(const ScratchDir& dir, double mean, double cov, std::string& sets) {
  std::string text = read_text(source_path("geometries/griffiths_lane.toml"));
  text = std::regex_replace(text, std::regex("geometry = \"griffiths_lane.geo\""),
                            "geometry = \"" + source_path("geometries/griffiths_lane.geo") + "\"");
  std::ostringstream random;
  random << "\n[random.undrained]\nmaterial = \"soil\"\nparameter = \"cohesion\"\ndistribution = \"lognormal\"\n"
         << "mean = " << mean << "\ncov = " << cov << "\ncorrelation_length = [inf, inf]\n";
  const std::string scene = dir.file("tresca.toml");
  std::ofstream(scene) << text << random.str();
  sets = " --set materials.soil.friction_angle=0 --set materials.soil.cohesion=" + std::to_string(mean) +
         " --set materials.soil.youngs_modulus=2e7 --set run.gravity_ramp=3 --set run.damping=0.05"
         " --set run.end_time=12 --set run.rest_ratio=0 --set mesh.size=2";
  return scene;
}

// The cells of the data rows of a realisations.csv (after its fingerprint and header).
std::vector<std::vector<std::string>> csv_cells(const std::string& path, std::string* header = nullptr) {
  std::istringstream csv(read_text(path));
  std::string line;
  std::getline(csv, line);
  std::getline(csv, line);
  if (header) *header = line;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) f.push_back(cell);
    if (!line.empty() && line.back() == ',') f.emplace_back();
    rows.push_back(f);
  }
  return rows;
}

// Correlation lengths of inf: each realisation is one value of c_u, so the slope fails exactly
// when c_u < mean / F, F the factor of safety at the mean. A Tresca clay (phi = 0) on Griffiths and
// Lane's 2:1 slope, loaded by a gravity ramp with damping so that the runs are quasi-static as in
// `talus fos`: P(c_u < mean / F) from the lognormal must lie in the ensemble's 95 % interval.
TEST(EnsembleValidation, FullyCorrelatedTrescaSlopeMatchesTheClosedForm) {
  const ScratchDir dir("ensemble_tresca");
  const double mean = 25e3, cov = 0.3;
  std::string sets;
  const std::string scene = tresca_scene(dir, mean, cov, sets);
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

// --fos in the fully correlated limit: a Tresca slope of uniform c_u has F = c_u / c_crit, so each
// realisation's factor of safety is F_mean x c_u / mean, F_mean that of `talus fos` at the mean.
// Both are the middles of brackets no wider than the tolerance, each holding its true value, so
// they differ by at most tolerance / 2 x (1 + c_u / mean).
TEST(EnsembleValidation, FullyCorrelatedTrescaFosScalesWithTheUndrainedStrength) {
  const ScratchDir dir("ensemble_tresca_fos");
  const double mean = 25e3, cov = 0.3, tolerance = 0.02;
  std::string sets;
  const std::string scene = tresca_scene(dir, mean, cov, sets);
  const std::string search = " --tolerance " + std::to_string(tolerance);
  const auto fos = run_talus("fos " + scene + sets + search + " -q --out " + dir.file("fos"));
  ASSERT_EQ(fos.status, 0) << fos.output;
  const double F = json_number(read_text(dir.file("fos/fos.json")), "factor_of_safety");
  ASSERT_TRUE(F > 0.9 && F < 1.5) << F;

  const long n = 4;
  const auto run = run_talus("ensemble " + scene + sets + search + " --fos --realisations " + std::to_string(n) +
                             " --seed 100 --jobs 2 -q --out " + dir.file("ensemble"));
  ASSERT_EQ(run.status, 0) << run.output;
  std::string header;
  const auto rows = csv_cells(dir.file("ensemble/realisations.csv"), &header);
  ASSERT_NE(header.find(",mean_undrained,fos,message"), std::string::npos) << header;
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(n));
  int below = 0;
  for (const auto& f : rows) {
    ASSERT_EQ(f.size(), 16u);
    const double c_u = std::stod(f[13]);
    ASSERT_FALSE(f[14].empty()) << "no factor of safety: " << f[15];
    const double F_k = std::stod(f[14]), expected = F * c_u / mean;
    std::cout << "c_u = " << c_u << " Pa: F = " << F_k << ", F_mean c_u / mean = " << expected << "\n";
    EXPECT_NEAR(F_k, expected, 0.5 * tolerance * (1 + c_u / mean)) << "c_u = " << c_u;
    below += F_k < 1;
  }
  const std::string json = read_text(dir.file("ensemble/ensemble.json"));
  EXPECT_EQ(json_number(json, "count"), n);
  EXPECT_DOUBLE_EQ(json_number(json, "probability_below_1"), below / static_cast<double>(n));
}

// --ranks: the realisations shared over MPI ranks give the rows of one process, byte for byte; a
// Ctrl-C at the driver stops every rank (none left running) and the same command resumes.
// Skipped without MPI.
TEST(EnsembleRanks, TwoRanksGiveTheRowsOfOneJobAndResumeAfterCtrlC) {
  if (talus::testing::talus_version().find("(with MPI") == std::string::npos) GTEST_SKIP() << "talus was built without MPI";
  const ScratchDir dir("ensemble_ranks");
  const std::string scene = slope_scene(dir, kRandomCohesion);
  const std::string common = "ensemble " + scene + " --realisations 5 --seed 21 -q";
  const std::string expected = rows_of_run(common + " --jobs 1", dir.file("one"));
  EXPECT_EQ(lines_of(expected), 6);

  const auto two = run_talus("ensemble " + scene + " --realisations 5 --seed 21 --ranks 2 --jobs 1 --out " + dir.file("two"));
  ASSERT_EQ(two.status, 0) << two.output;
  EXPECT_NE(two.output.find("on 2 MPI ranks"), std::string::npos) << two.output;
  EXPECT_NE(two.output.find("2 ranks x 1 job"), std::string::npos) << two.output;
  EXPECT_EQ(rows_of(dir.file("two/realisations.csv")), expected);
  EXPECT_EQ(json_number(read_text(dir.file("two/ensemble.json")), "probability_of_failure"),
            json_number(read_text(dir.file("one/ensemble.json")), "probability_of_failure"));
  EXPECT_TRUE(fs::exists(dir.file("two/ensemble_exceedance.png")));

  // Stopped by SIGINT at the driver once a row is in: every rank stops, the driver exits 130.
  const std::string parts = dir.file("parts");
  // Then the ranks and mpirun still running, found by the options the driver gives them (this
  // shell's own text does not match the pattern).
  const auto stopped = stopped_once_rows_are_in(common + " --ranks 2 --jobs 1", parts, dir.file("stopped.log"), 3,
                                                "sleep 1; echo left $(pgrep -f -c -- '[-]-seed 21 --jobs 1 --out " +
                                                    parts + "')");
  const std::string stopped_log = read_text(dir.file("stopped.log"));
  ASSERT_NE(stopped.output.find("status 130"), std::string::npos) << stopped.output << stopped_log;
  EXPECT_NE(stopped.output.find("left 0"), std::string::npos) << stopped.output;
  EXPECT_NE(stopped_log.find("interrupted by SIGINT"), std::string::npos) << stopped_log;
  EXPECT_FALSE(fs::exists(parts + "/ensemble.json"));
  const std::string kept = rows_of(parts + "/realisations.csv");
  EXPECT_GE(lines_of(kept), 2) << stopped_log;
  EXPECT_LT(lines_of(kept), 6) << stopped_log;
  const auto resumed = run_talus(common + " --ranks 2 --jobs 1 --out " + parts);
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_EQ(rows_of(parts + "/realisations.csv"), expected);
}
