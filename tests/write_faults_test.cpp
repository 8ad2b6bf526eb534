// Write faults through the binary (issue 17, items 4 and 5): a full disk, simulated by a file
// size limit (ulimit -f, with SIGXFSZ ignored so that the write fails instead of killing the
// process), stops mesh, solve and post with exit status 1 and a message naming the file, and
// leaves no half-written file under a final name; results.h5 deleted while a solve writes it
// stops the solve.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::run_shell;
using testing::ScratchDir;
// `ulimit -f N`: files of at most N blocks of 512 bytes. talus ignores SIGXFSZ itself (before
// issue 43 the signal killed it: status 153, no message, model.h5.tmp left).
using testing::talus_with_limit;

void expect_failed_write(const testing::CommandResult& result, const std::string& file) {
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find(file + ": cannot write"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find("internal error"), std::string::npos) << result.output;
}

TEST(WriteFaults, AFullDiskStopsEveryStageAndLeavesNoHalfWrittenFile) {
  ScratchDir dir("write-faults");
  const fs::path out = dir.path() / "out";
  const std::string scene = testing::scene_row(dir.path(), testing::kScene) + " --out " + out.string();

  // 50 kB passes the estimate of model.h5 (28 kB: 88 B per particle, 16 B per node, 24 B per
  // triangle) and stops its write (the file takes 64 kB with HDF5's own).
  expect_failed_write(talus_with_limit("-f 100", scene), "model.h5.tmp");
  EXPECT_FALSE(fs::exists(out / "model.h5"));
  EXPECT_FALSE(fs::exists(out / "model.h5.tmp"));

  ASSERT_EQ(testing::run_talus(scene + " --quiet").status, 0);
  // 205 kB passes the estimate of results.h5 (170 kB: 4 frames of 344 particles at 100 B and
  // 8 kB) and stops the writes (the file takes 228 kB).
  const auto solved = talus_with_limit("-f 400", "solve " + (out / "model.h5").string());
  expect_failed_write(solved, "results.h5");
  EXPECT_NE(solved.output.find("removed " + (out / "results.h5").string() + " and results.xdmf"), std::string::npos)
      << solved.output;
  EXPECT_FALSE(fs::exists(out / "results.h5"));
  EXPECT_FALSE(fs::exists(out / "results.xdmf"));
}

TEST(WriteFaults, AModelLargerThanTheFileSizeLimitIsRefusedBeforeMeshing) {
  ScratchDir dir("write-faults-model-estimate");
  const fs::path out = dir.path() / "out";
  const auto result = talus_with_limit("-f 20", testing::scene_row(dir.path(), testing::kScene) + " --out " + out.string());
  EXPECT_EQ(result.status, 1) << result.output;
  for (const char* words : {"block.toml: mesh.size: an element size of 0.25 m over the domain's 2 m^2 gives about ",
                            "a model.h5 of about 0.0284 MB (88 B per particle, 16 B per node, 24 B per triangle), more "
                            "than the file size limit of 0.0102 MB (ulimit -f): raise mesh.size or the limit"})
    EXPECT_NE(result.output.find(words), std::string::npos) << words << " not in: " << result.output;
  EXPECT_FALSE(fs::exists(out));
}

TEST(WriteFaults, AFullDiskDuringTheFiguresLeavesNoTruncatedPicture) {
  ScratchDir dir("write-faults-figures");
  const fs::path out = dir.path() / "out";
  const std::string scene = testing::scene_row(dir.path(), testing::kScene).replace(0, 4, "run");
  ASSERT_EQ(testing::run_talus(scene + " --quiet --out " + out.string()).status, 0);
  for (const auto& entry : fs::directory_iterator(out))
    if (entry.path().extension() == ".png") fs::remove(entry.path());
  const auto result = talus_with_limit("-f 40", "post " + (out / "results.h5").string() + " -q");  // 20 kB
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find("figures.py: figures failed: exited with status 1: OSError: [Errno 27] File too large"),
            std::string::npos)
      << result.output;
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_EQ(entry.path().string().find(".png"), std::string::npos) << "left: " << entry.path();
}

TEST(WriteFaults, ResultsThatWouldNotFitAreRefusedBeforeTheSolve) {
  ScratchDir dir("write-faults-estimate");
  const fs::path out = dir.path() / "out";
  const std::string scene =
      testing::scene_row(dir.path(), testing::replaced(testing::kScene, "output_interval = 0.005", "output_interval = 1e-5"));
  ASSERT_EQ(testing::run_talus(scene + " --quiet --out " + out.string()).status, 0);
  const auto result = talus_with_limit("-f 1000", "solve " + (out / "model.h5").string());
  EXPECT_EQ(result.status, 1) << result.output;
  for (const char* words : {"model.h5: settings/run@output_interval: results.h5 would take about 0.0424",
                            " frames of 344 particles at 100 B each, and 8 kB a frame), more than the file size "
                            "limit of 0.000512 GB"})
    EXPECT_NE(result.output.find(words), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("raise run.output_interval"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out / "results.h5"));
}

TEST(WriteFaults, ResultsDeletedDuringASolveStopIt) {
  ScratchDir dir("write-faults-deleted");
  const fs::path out = dir.path() / "out";
  const std::string scene = testing::scene_row(
      dir.path(), testing::replaced(testing::replaced(testing::kScene, "end_time = 0.01", "end_time = 100.0"),
                                    "gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]"));
  ASSERT_EQ(testing::run_talus(scene + " --quiet --out " + out.string()).status, 0);
  const std::string results = (out / "results.h5").string();
  const auto result = run_shell("( " + std::string(TALUS_BINARY) + " solve " + (out / "model.h5").string() +
                                " -q & pid=$!; for i in $(seq 1 3000); do [ -f '" + results +
                                "' ] && break; sleep 0.01; done; sleep 0.2; rm '" + results +
                                "'; wait $pid; echo status=$? )");
  EXPECT_NE(result.output.find("status=1"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find(results + ": deleted while the solve was writing it"), std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(out / "results.xdmf"));
}

// A checkpoint write that was killed leaves checkpoint.h5.tmp; before issue 43 a restart (and a
// fresh solve) left it there for good. The solve holds the folder's lock, so it removes it.
TEST(WriteFaults, AStaleCheckpointTemporaryIsRemovedBySolveAndRestart) {
  ScratchDir dir("write-faults-stale-checkpoint");
  const fs::path out = dir.path() / "out";
  const std::string scene = testing::scene_row(
      dir.path(), testing::replaced(testing::replaced(testing::kScene, "end_time = 0.01", "end_time = 100.0\nmax_steps = 3000"),
                                    "gravity = [0.0, -9.81]", "gravity = [0.0, 0.0]"));
  ASSERT_EQ(testing::run_talus(scene + " --quiet --out " + out.string()).status, 0);
  const std::string model = (out / "model.h5").string(), stale = (out / "checkpoint.h5.tmp").string();
  testing::write_file(stale, "half a checkpoint");
  const auto stopped = run_shell("( " + std::string(TALUS_BINARY) + " solve " + model +
                                 " -q --checkpoint-interval 0.001 & pid=$!; for i in $(seq 1 3000); do [ -f '" +
                                 (out / "checkpoint.h5").string() + "' ] && break; sleep 0.01; done; kill -TERM $pid; "
                                 "wait $pid; echo status=$? )");
  ASSERT_NE(stopped.output.find("status=143"), std::string::npos) << stopped.output;
  EXPECT_FALSE(fs::exists(stale)) << "left by a fresh solve";
  testing::write_file(stale, "half a checkpoint");
  const auto restarted = testing::run_talus("solve " + model + " -q --restart");
  EXPECT_EQ(restarted.status, 0) << restarted.output;
  EXPECT_FALSE(fs::exists(stale)) << "left by a restart";
}

}  // namespace
}  // namespace talus
