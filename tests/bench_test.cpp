// The accuracy benchmark at its smallest setting (one cheap run each of the spring-mass and
// box-on-incline scenes): the CSVs it writes have the documented columns, one row per run, and
// finite values that make sense (the runs are the cheapest of the grid, so the errors are loose
// but bounded). The sweeps themselves are benchmarks, not tests: `talus bench accuracy`.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

using talus::testing::run_shell;
using talus::testing::ScratchDir;

namespace {

// The bench programs sit beside the talus binary of the same build.
std::string bench_binary(const std::string& name) {
  return (std::filesystem::path(TALUS_BINARY).parent_path() / ("talus_bench_" + name)).string();
}

struct Csv {
  std::vector<std::string> header;
  std::vector<std::map<std::string, double>> rows;
};

Csv read_csv(const std::string& path) {
  std::ifstream in(path);
  Csv csv;
  std::string line;
  if (!std::getline(in, line)) return csv;
  std::stringstream head(line);
  for (std::string name; std::getline(head, name, ',');) csv.header.push_back(name);
  while (std::getline(in, line)) {
    std::stringstream cells(line);
    std::map<std::string, double> row;
    std::size_t k = 0;
    for (std::string cell; std::getline(cells, cell, ',') && k < csv.header.size(); ++k)
      row[csv.header[k]] = std::strtod(cell.c_str(), nullptr);
    csv.rows.push_back(row);
  }
  return csv;
}

const std::vector<std::string> kColumns = {"mesh_size_m", "particles_per_cell", "cfl", "elements", "particles",
                                           "steps", "particle_updates", "loop_seconds", "wall_seconds", "error",
                                           "error_at_1s", "pareto", "threads"};

}  // namespace

TEST(BenchAccuracy, SmallestSettingWritesFiniteCsvRowsWithTheDocumentedColumns) {
  ScratchDir dir("bench-accuracy");
  const auto run = run_shell(bench_binary("accuracy") + " --smallest --out " + dir.path().string() + " 2>&1");
  ASSERT_EQ(run.status, 0) << run.output;

  for (const std::string scene : {"spring_mass", "box_incline"}) {
    SCOPED_TRACE(scene);
    const Csv csv = read_csv(dir.file("accuracy_" + scene + ".csv"));
    EXPECT_EQ(csv.header, kColumns);
    ASSERT_EQ(csv.rows.size(), 1u);  // the smallest setting only
    const auto& row = csv.rows.front();
    ASSERT_EQ(row.size(), kColumns.size());
    for (const auto& [name, value] : row) EXPECT_TRUE(std::isfinite(value)) << name;
    EXPECT_EQ(row.at("particles_per_cell"), 1);
    EXPECT_EQ(row.at("cfl"), 1);
    EXPECT_EQ(row.at("threads"), 1);  // the default, --threads not given
    EXPECT_GT(row.at("particles"), 0);
    EXPECT_GT(row.at("steps"), 100);
    EXPECT_EQ(row.at("particle_updates"), row.at("particles") * row.at("steps"));
    EXPECT_GT(row.at("wall_seconds"), row.at("loop_seconds"));  // wall time includes meshing
    EXPECT_EQ(row.at("pareto"), 1);                             // alone, it is the front
    // Even the coarsest run follows its analytical solution to within a quarter of it.
    EXPECT_GT(row.at("error"), 0);
    EXPECT_LT(row.at("error"), 0.25);
    EXPECT_LE(row.at("error_at_1s"), row.at("error"));
  }
  EXPECT_TRUE(std::filesystem::exists(dir.file("accuracy.md")));
  EXPECT_TRUE(std::filesystem::exists(dir.file("bench_accuracy_spring_mass.png")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("accuracy_slope.csv")));  // --smallest leaves the slope out
}

TEST(BenchAccuracy, RejectsAnUnknownScene) {
  const auto run = run_shell(bench_binary("accuracy") + " --scenes nowhere 2>&1");
  EXPECT_EQ(run.status, 1);
  EXPECT_NE(run.output.find("unknown scene 'nowhere'"), std::string::npos) << run.output;
}
