// `talus converge`: the grid-convergence arithmetic against the worked example of Celik et al.
// (2008), the rule for oscillatory and divergent values, and the command on a small study.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/test_support.hpp"
#include "common/error.hpp"
#include "workflow/gci.hpp"

using talus::testing::run_talus;
using talus::testing::ScratchDir;
using talus::testing::source_path;
using namespace talus::workflow;

TEST(GridConvergence, MatchesTheWorkedExampleOfCelikEtAl2008) {
  // Celik, Ghia, Roache and Freitas (2008), J. Fluids Eng. 130, 078001, Table 1, first column
  // (monotone): N = 18000, 8000, 4500 cells in 2D, so r21 = sqrt(18000/8000) = 1.5 and
  // r32 = sqrt(8000/4500) = 1.333; phi = 6.063, 5.972, 5.863. Published: p = 1.53,
  // phi_ext21 = 6.1685, e_a21 = 1.5 %, GCI_fine21 = 2.2 %.
  const double r21 = std::sqrt(18000.0 / 8000.0), r32 = std::sqrt(8000.0 / 4500.0);
  const GridConvergence g = grid_convergence(6.063, 5.972, 5.863, r21, r32);
  EXPECT_EQ(g.kind, Convergence::Monotone);
  EXPECT_TRUE(g.asymptotic);
  EXPECT_NEAR(g.observed_order, 1.53, 0.005);
  EXPECT_NEAR(g.extrapolated, 6.1685, 0.00005 + 0.0005);
  EXPECT_NEAR(100 * g.relative_band, 2.2, 0.05);
  EXPECT_DOUBLE_EQ(g.safety_factor, 1.25);
}

TEST(GridConvergence, AnExactPowerLawGivesItsOrderAndLimit) {
  // f(h) = 3 + 0.5 h^p at h = 1, 1/2, 1/4: the order, limit and error come back exactly, and the
  // band 1.25 |f1 - f2| / (2^p - 1) bounds the true error |f1 - 3| = 0.5 / 4^p.
  for (double p : {1.0, 1.5}) {
    const auto f = [&](double h) { return 3 + 0.5 * std::pow(h, p); };
    const GridConvergence g = grid_convergence(f(0.25), f(0.5), f(1.0), 2, 2);
    EXPECT_EQ(g.kind, Convergence::Monotone);
    EXPECT_NEAR(g.observed_order, p, 1e-12);
    EXPECT_NEAR(g.extrapolated, 3, 1e-12);
    EXPECT_NEAR(g.band, 1.25 * std::abs(f(0.25) - 3), 1e-12);
  }
  // An order above 2 is measured but the band uses 2.
  const auto cubic = [](double h) { return 1 + h * h * h; };
  const GridConvergence g = grid_convergence(cubic(0.25), cubic(0.5), cubic(1.0), 2, 2);
  EXPECT_NEAR(g.observed_order, 3, 1e-12);
  EXPECT_DOUBLE_EQ(g.order, 2);
  EXPECT_NEAR(g.band, 1.25 * (cubic(0.5) - cubic(0.25)) / 3, 1e-12);
}

TEST(GridConvergence, OscillatoryAndDivergentValuesGetRoachesFallback) {
  // Up then down: no order; Fs = 3 with p = 1, no extrapolate, not asymptotic.
  GridConvergence g = grid_convergence(3.1, 3.3, 3.0, 2, 2);
  EXPECT_EQ(g.kind, Convergence::Oscillatory);
  EXPECT_FALSE(g.asymptotic);
  EXPECT_TRUE(std::isnan(g.observed_order));
  EXPECT_TRUE(std::isnan(g.extrapolated));
  EXPECT_NEAR(g.band, 3 * 0.2 / (2 - 1), 1e-12);
  // The slope's runout before the friction base: 3.09, 3.29, 3.79 m from coarse to fine, the
  // change grows with refinement.
  g = grid_convergence(3.79, 3.29, 3.09, 2, 2);
  EXPECT_EQ(g.kind, Convergence::Divergent);
  EXPECT_NEAR(g.band, 3 * 0.5, 1e-12);
  EXPECT_NEAR(g.relative_band, 1.5 / 3.79, 1e-12);
  // No change between the two finest: converged, band 0.
  g = grid_convergence(2.0, 2.0, 2.5, 2, 2);
  EXPECT_EQ(g.kind, Convergence::Converged);
  EXPECT_EQ(g.band, 0);
  EXPECT_THROW(grid_convergence(1, 2, 3, 1.0, 2), talus::Error);
  EXPECT_THROW(grid_convergence(1, NAN, 3, 2, 2), talus::Error);
}

TEST(ConvergeCommand, ASmallStudyWritesItsTablesAndFigure) {
  // The default slope at 1, 0.67 and 0.44 m for 1.5 s: seconds. Every level has its folder,
  // the tables list each metric with the three values, and a rerun reuses the levels.
  ScratchDir dir("converge");
  const std::string out = dir.file("study");
  const std::string command = "converge " + source_path("geometries/slope.toml") +
                              " --set mesh.size=1 --set run.end_time=1.5 --levels 3 --ratio 1.5 --threads 1 --out " + out;
  const auto result = run_talus(command);
  ASSERT_EQ(result.status, 0) << result.output;
  for (const char* words : {"level 1/3: mesh.size = 1 m", "level 3/3: mesh.size = 0.444444 m", "done in", "runout (m)"})
    EXPECT_NE(result.output.find(words), std::string::npos) << words << "\n" << result.output;
  namespace fs = std::filesystem;
  for (const char* name : {"converge.csv", "converge.md", "converge.png", "level1_h1/metrics.json",
                           "level2_h0.666667/results.h5", "level3_h0.444444/metrics.json"})
    EXPECT_TRUE(fs::exists(fs::path(out) / name)) << name;
  std::ifstream csv(fs::path(out) / "converge.csv");
  std::string header, runout;
  std::getline(csv, header);
  std::getline(csv, runout);
  EXPECT_EQ(header.rfind("metric,unit,h=1,h=0.666667,h=0.444444,convergence,order", 0), 0u) << header;
  EXPECT_EQ(runout.rfind("runout,m,", 0), 0u) << runout;
  // The band written is the rule's for the three runouts written (at 1.5 s the front is still
  // near the toe: the values are small and need not converge).
  std::stringstream fields(runout);
  std::vector<std::string> cells;
  for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
  ASSERT_GE(cells.size(), 11u);
  const GridConvergence g = grid_convergence(std::stod(cells[4]), std::stod(cells[3]), std::stod(cells[2]), 1.5, 1.5);
  EXPECT_EQ(cells[5], convergence_name(g.kind)) << runout;
  EXPECT_NEAR(std::stod(cells[9]), g.band, 1e-8 * (1 + g.band)) << runout;

  const auto again = run_talus(command);
  ASSERT_EQ(again.status, 0) << again.output;
  std::ifstream csv_again(fs::path(out) / "converge.csv");
  std::string header_again, runout_again;
  std::getline(csv_again, header_again);
  std::getline(csv_again, runout_again);
  EXPECT_EQ(runout_again, runout);  // the levels were reused, not rerun differently
}

TEST(ConvergeCommand, TransfersRunTheFinestLevelWithEachAndReportTheirSpread) {
  // The default slope at 1 and 0.5 m for 1.5 s, then the finest level again with XPIC(2): the
  // scene's own FLIP is the finest level itself (reused), XPIC(2)'s runout is the one a plain
  // `talus run` with that transfer gives, and the spread is their difference.
  ScratchDir dir("converge_transfers");
  namespace fs = std::filesystem;
  const std::string out = dir.file("study");
  const std::string scene = source_path("geometries/slope.toml");
  const std::string common = " --set run.end_time=1.5 --threads 1";
  const auto result = run_talus("converge " + scene + common + " --set mesh.size=1 --levels 2 --transfers flip,xpic2 --out " + out);
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_NE(result.output.find("transfer flip: the scene's own, the finest level"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::exists(fs::path(out) / "finest_xpic2" / "metrics.json"));
  EXPECT_FALSE(fs::exists(fs::path(out) / "finest_flip"));
  const auto single = run_talus("run " + scene + common + " --set mesh.size=0.5 --set run.transfer=xpic --set run.xpic_order=2 -q --out " +
                                dir.file("xpic2"));
  ASSERT_EQ(single.status, 0) << single.output;
  auto runout_of = [](const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    const std::string json = text.str();
    const auto at = json.find("\"runout_distance_m\":");
    return at == std::string::npos ? std::nan("") : std::stod(json.substr(at + 20));
  };
  const double flip = runout_of(fs::path(out) / "level2_h0.5" / "metrics.json");
  const double xpic = runout_of(dir.file("xpic2/metrics.json"));
  ASSERT_TRUE(std::isfinite(flip) && std::isfinite(xpic));
  std::ifstream csv(fs::path(out) / "transfers.csv");
  std::string header, runout;
  std::getline(csv, header);
  std::getline(csv, runout);
  EXPECT_EQ(header, "metric,unit,flip,xpic2,spread,spread_percent_of_mean,gci");
  std::stringstream fields(runout);
  std::vector<std::string> cells;
  for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
  ASSERT_GE(cells.size(), 6u) << runout;
  EXPECT_EQ(cells[0], "runout");
  EXPECT_NEAR(std::stod(cells[2]), flip, 1e-9);
  EXPECT_NEAR(std::stod(cells[3]), xpic, 1e-9);
  EXPECT_NEAR(std::stod(cells[4]), std::abs(flip - xpic), 1e-9);
  EXPECT_GT(std::abs(flip - xpic), 1e-3) << "the two transfers should not give the same runout";
}

TEST(ConvergeCommand, TransfersThatCannotRunAreRefusedBeforeAnyLevelRuns) {
  ScratchDir dir("converge_transfers_refused");
  const std::string scene = source_path("geometries/slope.toml");
  for (const auto& [list, words] : std::vector<std::pair<std::string, std::string>>{
           {"flip,magic", "unknown transfer 'magic'"},
           {"flip,xpic0", "unknown transfer 'xpic0'"},
           {"flip,flip", "'flip' is listed twice"},
           {"flip,apic", "--transfers apic cannot run"}}) {
    const std::string out = dir.file("study_" + std::to_string(std::hash<std::string>{}(list)));
    const auto result = run_talus("converge " + scene + " --set mesh.size=1 --levels 2 --transfers " + list + " --out " + out);
    EXPECT_NE(result.status, 0) << list;
    EXPECT_NE(result.output.find(words), std::string::npos) << list << "\n" << result.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << list << ": nothing is written";
  }
}
