// The output folder: --out naming something that cannot be a folder is bad input (exit status 1,
// a plain message; issue 17, item 12), and one folder admits one writer (item 3): a second talus
// aimed at a folder another talus is writing into stops at once with exit status 1, names the
// holder's pid and command, and leaves the first one's files alone.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"
#include "workflow/folder_lock.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::run_shell;
using testing::run_talus;
using testing::ScratchDir;

std::string text_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(OutFolder, ANameThatCannotBeAFolderIsBadInput) {
  ScratchDir dir("out-folder");
  const fs::path d = dir.path();
  const std::string scene = testing::scene_row(d, testing::kScene);
  const std::string file = testing::write_file(d / "a_file", "not a folder");
  const std::vector<std::pair<std::string, std::vector<std::string>>> rows = {
      {file, {file, "cannot use this as the output folder"}},
      {file + "/sub", {file + "/sub", "cannot use this as the output folder"}},
      {"''", {"--out: expected a folder, got an empty name"}},
      {"/dev/null", {"/dev/null", "cannot use this as the output folder"}},
      {"/proc/self", {"/proc/self/.talus.lock", "cannot create the folder's lock file", "is the folder writable?"}},
  };
  for (const auto& [out, words] : rows) {
    SCOPED_TRACE(out);
    for (const auto& command : std::vector<std::string>{scene, "run" + scene.substr(4)}) {
      const auto result = run_talus(command + " --out " + out);
      EXPECT_EQ(result.status, 1) << result.output;
      EXPECT_EQ(result.output.find("internal error"), std::string::npos) << result.output;
      for (const auto& word : words) EXPECT_NE(result.output.find(word), std::string::npos) << result.output;
    }
  }
  EXPECT_EQ(text_of(file), "not a folder");
}

TEST(FolderLock, EveryStageRefusesAFolderAnotherTalusHolds) {
  ScratchDir dir("folder-lock");
  const fs::path d = dir.path(), out = d / "out";
  const std::string scene = testing::scene_row(d, testing::kScene).substr(5);  // "mesh " dropped
  fs::create_directories(out);
  const std::string kept = "the first writer's results";
  testing::write_file(out / "results.h5", kept);
  testing::write_file(out / "model.h5", kept);
  const std::vector<std::string> commands = {"mesh " + scene, "solve " + (out / "model.h5").string(),
                                             "post " + (out / "results.h5").string(), "run " + scene,
                                             "fos " + scene};
  {
    const workflow::FolderLock holder(out.string());  // this test process holds the folder
    for (const auto& command : commands) {
      SCOPED_TRACE(command);
      const auto result = run_talus(command + " --out " + out.string());
      EXPECT_EQ(result.status, 1) << result.output;
      EXPECT_NE(result.output.find("another talus is writing into this folder"), std::string::npos) << result.output;
      EXPECT_NE(result.output.find("pid " + std::to_string(getpid()) + ": "), std::string::npos) << result.output;
      EXPECT_NE(result.output.find("output_folder_test"), std::string::npos) << result.output;
      EXPECT_EQ(text_of(out / "results.h5"), kept);
      EXPECT_EQ(text_of(out / "model.h5"), kept);
    }
  }
  // Released: the folder is free again.
  const auto meshed = run_talus("mesh " + scene + " --quiet --out " + out.string());
  EXPECT_EQ(meshed.status, 0) << meshed.output;
}

TEST(FolderLock, ASecondSolveLeavesTheFirstOnesResultsWhole) {
  ScratchDir dir("folder-lock-two-solves");
  const fs::path d = dir.path(), out = d / "out";
  const std::string scene =
      testing::scene_row(d, testing::replaced(testing::replaced(testing::kScene, "end_time = 0.01", "end_time = 100.0"),
                                              "gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]"));
  const auto meshed = run_talus(scene + " --quiet --out " + out.string());
  ASSERT_EQ(meshed.status, 0) << meshed.output;
  const std::string model = (out / "model.h5").string(), lock = (out / ".talus.lock").string();
  // The first solve runs in the background; once it holds the lock, a second one is started.
  // (The first solve is stopped by SIGTERM, which keeps what it wrote.)
  const std::string talus = TALUS_BINARY;
  const auto result = run_shell(
      "( " + talus + " solve " + model + " --quiet --checkpoint-interval 0.01 & pid=$!; " +
      "for i in $(seq 1 3000); do grep -q 'talus solve' '" + lock + "' 2>/dev/null && break; sleep 0.01; done; " +
      talus + " solve " + model + "; echo second=$?; " +  // then stop the first once its time loop runs
      "for i in $(seq 1 3000); do [ -f '" + (out / "checkpoint.h5").string() + "' ] && break; sleep 0.01; done; " +
      "kill -TERM $pid; wait $pid; echo first=$? )");
  EXPECT_NE(result.output.find("second=1"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("another talus is writing into this folder (pid "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("talus solve " + model), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("first=143"), std::string::npos) << result.output;
  // The first solve's results are readable: post reads them.
  const auto post = run_talus("post " + (out / "results.h5").string() + " --quiet");
  EXPECT_EQ(post.status, 0) << post.output;
}

}  // namespace
}  // namespace talus
