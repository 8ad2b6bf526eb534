// The talus executable as a user meets it: help, errors on the command line, and `talus run`
// re-running only the stages whose inputs changed.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/test_support.hpp"

using talus::testing::run_talus;
using talus::testing::ScratchDir;
using talus::testing::source_path;

namespace {

int count(const std::string& text, const std::string& word) {
  int n = 0;
  for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(Cli, HelpListsEveryStageAndExitsZero) {
  const auto result = run_talus("--help");
  EXPECT_EQ(result.status, 0);
  for (const char* word : {"talus mesh", "talus solve", "talus post", "talus run", "--set", "--out"})
    EXPECT_NE(result.output.find(word), std::string::npos) << word;
  // Every exit status, as docs/robustness.md lists them.
  for (const char* words : {"0 on success, 1 on bad input or a failed run, 2 on an internal", "3 when memory ran out",
                            "130 when stopped by SIGINT", "143 when", "128 + N when a rank was killed by signal N"})
    EXPECT_NE(result.output.find(words), std::string::npos) << words;
}

TEST(Cli, UnknownCommandAndMissingInputAreOneClearError) {
  auto result = run_talus("smash geometries/slope.toml");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.output.find("unknown command 'smash'"), std::string::npos) << result.output;
  result = run_talus("solve");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.output.find("missing model file"), std::string::npos) << result.output;
  result = run_talus("solve /nonexistent/model.h5");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.output.find("/nonexistent/model.h5: no such file"), std::string::npos) << result.output;
  result = run_talus("post /nonexistent/results.h5");
  EXPECT_EQ(result.status, 1);
  EXPECT_EQ(count(result.output, "error"), 1) << result.output;
}

TEST(Cli, RunSkipsTheStagesWhoseInputsDidNotChange) {
  ScratchDir dir("rerun");
  const std::string scene = source_path("geometries/spring_mass.toml");
  const std::string out = " --out " + dir.path().string() + " --set run.end_time=0.004";
  auto first = run_talus("run " + scene + out);
  ASSERT_EQ(first.status, 0) << first.output;
  EXPECT_EQ(count(first.output, "skipped"), 0) << first.output;

  auto second = run_talus("run " + scene + out);
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_EQ(count(second.output, "inputs unchanged, skipped"), 3) << second.output;

  // A physics change leaves the geometry alone but changes the scene: everything re-runs.
  auto third = run_talus("run " + scene + out + " --set run.cfl=0.4");
  ASSERT_EQ(third.status, 0) << third.output;
  EXPECT_EQ(count(third.output, "skipped"), 0) << third.output;

  // Lost results are made again, from the model that is still up to date.
  std::filesystem::remove(dir.file("results.h5"));
  auto fourth = run_talus("run " + scene + out + " --set run.cfl=0.4");
  ASSERT_EQ(fourth.status, 0) << fourth.output;
  EXPECT_NE(fourth.output.find("mesh: inputs unchanged, skipped"), std::string::npos) << fourth.output;
  EXPECT_NE(fourth.output.find("solved:"), std::string::npos) << fourth.output;
  EXPECT_TRUE(std::filesystem::exists(dir.file("results.h5")));
}
