// Faults of `talus post` through the binary (issue 17, items 6 and 12): figures that fail are
// said in one message, with -q too; SIGTERM while the figures script runs stops the script with
// talus and says what was kept. The script is made to fail or hang by a matplotlib of our own,
// put first on PYTHONPATH.
#include <gtest/gtest.h>

#include <filesystem>

#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::run_shell;
using testing::ScratchDir;
using testing::write_file;

class PostFaults : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new ScratchDir("post-faults");
    const auto solved = testing::run_talus(testing::scene_row(dir_->path(), testing::kScene).replace(0, 4, "run") +
                                           " --quiet --out " + dir_->file("out"));
    ASSERT_EQ(solved.status, 0) << solved.output;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  // `talus post ARGS` of the solved results with `matplotlib` replaced by `module`.
  static testing::CommandResult post(const std::string& module, const std::string& args) {
    write_file(dir_->path() / "fake" / "matplotlib" / "__init__.py", module);
    return run_shell("PYTHONPATH=" + dir_->file("fake") + " " + TALUS_BINARY + " post " + dir_->file("out/results.h5") +
                     " " + args);
  }
  static ScratchDir* dir_;
};
ScratchDir* PostFaults::dir_ = nullptr;

TEST_F(PostFaults, FailedFiguresAreOneMessageWithAndWithoutQuiet) {
  for (const char* quiet : {"-q", ""}) {
    SCOPED_TRACE(quiet);
    const auto result = post("raise ImportError('matplotlib is broken here')\n", quiet);
    EXPECT_EQ(result.status, 1) << result.output;
    EXPECT_NE(result.output.find("figures.py: figures failed: exited with status 1: "
                                 "ImportError: matplotlib is broken here"),
              std::string::npos)
        << result.output;
    EXPECT_NE(result.output.find("what was written before the figures is kept"), std::string::npos) << result.output;
    EXPECT_EQ(result.output.find("Traceback"), std::string::npos) << result.output;
    EXPECT_TRUE(fs::exists(dir_->file("out/metrics.json")));
  }
}

TEST_F(PostFaults, SigtermStopsTheFiguresScriptWithTalus) {
  const std::string pid_file = dir_->file("script.pid");
  fs::remove(pid_file);
  write_file(dir_->path() / "fake" / "matplotlib" / "__init__.py",
             "import os, time\nopen('" + pid_file + "', 'w').write(str(os.getpid()))\ntime.sleep(60)\n");
  const std::string script = "( PYTHONPATH=" + dir_->file("fake") + " " + TALUS_BINARY + " post " +
                             dir_->file("out/results.h5") + " -q & pid=$!; for i in $(seq 1 3000); do [ -s '" +
                             pid_file + "' ] && break; sleep 0.01; done; kill -TERM $pid; wait $pid; echo status=$?; " +
                             "sleep 0.2; kill -0 $(cat '" + pid_file + "') 2>/dev/null && echo script=running " +
                             "|| echo script=stopped )";
  const auto result = run_shell(script);
  EXPECT_NE(result.output.find("status=143"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("script=stopped"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("talus: interrupted by SIGTERM while figures.py ran: the script was stopped with talus; "
                               "what was written before the figures is kept"),
            std::string::npos)
      << result.output;
  EXPECT_TRUE(fs::exists(dir_->file("out/metrics.json")));
  // Whatever the test's outcome, no script is left running.
  run_shell("kill -KILL $(cat '" + pid_file + "') 2>/dev/null");
}

}  // namespace
}  // namespace talus
