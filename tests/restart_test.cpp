// Interrupting and restarting a solve through the talus binary: SIGTERM midway stops it with
// status 143, a checkpoint and a readable, incomplete results.h5; --restart then finishes the
// run with frames identical, bit for bit (one thread), to those of an uninterrupted run.
#include <gtest/gtest.h>

#include <filesystem>

#include "common/h5.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::run_shell;
using testing::run_talus;
using testing::ScratchDir;

// Starts `talus ARGS` in the background, waits until it has written its first checkpoint (so
// the time loop is running), sends `signal` and returns the exit status.
testing::CommandResult interrupt(const std::string& args, const fs::path& checkpoint, const char* signal) {
  const std::string script = "( " + std::string(TALUS_BINARY) + " " + args + " & pid=$!; " +
                             "for i in $(seq 1 3000); do [ -f '" + checkpoint.string() +
                             "' ] && break; sleep 0.01; done; kill -" + signal + " $pid; wait $pid; echo status=$? )";
  auto result = run_shell(script);
  const auto at = result.output.rfind("status=");
  result.status = at == std::string::npos ? -1 : std::stoi(result.output.substr(at + 7));
  return result;
}

std::vector<double> dataset(const std::string& file, const std::string& path) {
  return h5::read_doubles(h5::File::open_read(file), path);
}

class Restart : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new ScratchDir("restart");
    const auto meshed = run_talus("mesh " + testing::source_path("geometries/spring_mass.toml") + " --quiet --out " +
                                  dir_->file("model"));
    ASSERT_EQ(meshed.status, 0) << meshed.output;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string model() { return dir_->file("model/model.h5"); }
  static ScratchDir* dir_;
};
ScratchDir* Restart::dir_ = nullptr;

TEST_F(Restart, SigtermMidwayThenRestartGivesTheUninterruptedFramesBitForBit) {
  const fs::path whole = dir_->path() / "whole", parts = dir_->path() / "parts";
  const auto uninterrupted = run_talus("solve " + model() + " --threads 1 --quiet --out " + whole.string());
  ASSERT_EQ(uninterrupted.status, 0) << uninterrupted.output;

  const auto stopped = interrupt("solve " + model() + " --threads 1 --quiet --checkpoint-interval 0.01 --out " +
                                     parts.string(),
                                 parts / "checkpoint.h5", "TERM");
  ASSERT_EQ(stopped.status, 143) << stopped.output;
  EXPECT_NE(stopped.output.find("interrupted by SIGTERM"), std::string::npos) << stopped.output;
  EXPECT_NE(stopped.output.find("--restart"), std::string::npos) << stopped.output;
  ASSERT_TRUE(fs::exists(parts / "checkpoint.h5"));
  EXPECT_FALSE(fs::exists(parts / "checkpoint.h5.tmp"));
  const std::string results = (parts / "results.h5").string();
  {
    const h5::File file = h5::File::open_read(results);
    EXPECT_EQ(h5::get_int(file, "/", "complete"), 0);
    const auto times = h5::read_doubles(file, "frames/time");
    ASSERT_GE(times.size(), 2u);
    EXPECT_LT(times.back(), 0.12) << "the run was not stopped midway";
  }

  // A checkpoint of another format version is refused with both versions.
  const fs::path other = dir_->path() / "other-version";
  fs::create_directories(other);
  fs::copy(parts, other, fs::copy_options::recursive);
  {
    h5::File file = h5::File::open_write((other / "checkpoint.h5").string());
    h5::set_attribute(file, "/", "format_version", int64_t{7});
  }
  const auto refused = run_talus("solve " + model() + " --threads 1 --quiet --restart --out " + other.string());
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_NE(refused.output.find("file has version 7, this talus reads version 1"), std::string::npos) << refused.output;

  const auto restarted = run_talus("solve " + model() + " --threads 1 --quiet --restart --out " + parts.string());
  ASSERT_EQ(restarted.status, 0) << restarted.output;
  EXPECT_FALSE(fs::exists(parts / "checkpoint.h5")) << "a complete run leaves no checkpoint";

  const std::string reference = (whole / "results.h5").string();
  EXPECT_EQ(h5::get_int(h5::File::open_read(results), "/", "complete"), 1);
  EXPECT_EQ(h5::get_int(h5::File::open_read(results), "/", "steps"),
            h5::get_int(h5::File::open_read(reference), "/", "steps"));
  for (const char* path : {"frames/time", "frames/position", "frames/velocity", "frames/stress",
                           "frames/plastic_strain", "history/time", "history/kinetic_energy", "history/strain_energy"}) {
    SCOPED_TRACE(path);
    const auto expected = dataset(reference, path), actual = dataset(results, path);
    ASSERT_EQ(actual.size(), expected.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) differing += actual[i] != expected[i];
    EXPECT_EQ(differing, 0u) << "values differ from the uninterrupted run";
  }
}

TEST_F(Restart, SigintStopsWithStatus130AndAClosedReadableFile) {
  const fs::path out = dir_->path() / "sigint";
  const auto stopped = interrupt("solve " + model() + " --threads 1 --quiet --checkpoint-interval 0.02 --out " +
                                     out.string(),
                                 out / "checkpoint.h5", "INT");
  ASSERT_EQ(stopped.status, 130) << stopped.output;
  EXPECT_NE(stopped.output.find("interrupted by SIGINT"), std::string::npos) << stopped.output;
  const h5::File file = h5::File::open_read((out / "results.h5").string());
  EXPECT_EQ(h5::get_int(file, "/", "complete"), 0);
  const auto times = h5::read_doubles(file, "frames/time");
  const auto positions = h5::read_doubles(file, "frames/position");
  EXPECT_EQ(positions.size(), times.size() * 2 * static_cast<std::size_t>(h5::get_int(file, "/", "particles")));
}

}  // namespace
}  // namespace talus
