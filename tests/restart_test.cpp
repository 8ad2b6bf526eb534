// Interrupting and restarting a solve through the talus binary: SIGTERM midway stops it with
// status 143, a checkpoint and a readable, incomplete results.h5; --restart then finishes the
// run with frames identical, bit for bit, to those of an uninterrupted run on the same number
// of threads (one or two). A restart on a changed model is refused, naming what changed. With
// a water table (drained and undrained, rising) the pore pressures restart bit for bit too.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/h5.hpp"
#include "solver/io/io.hpp"
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
    // The same column to t = 0.06 s under a water table at mid-height that rises 0.4 m in
    // 0.13 s; the undrained one with a soft water (K_w / n = 3.3e5 Pa against the spring's
    // E = 5e5 Pa), so that its excess pore pressure matters and the time step stays about the same.
    const std::string water = " --set run.end_time=0.06 --set 'water.table=[[0.0, 0.5], [0.1, 0.5]]'"
                              " --set 'water.rise=[[0.0, 0.0], [0.13, 0.4]]'";
    for (const char* mode : {"drained", "undrained"}) {
      const auto wet = run_talus("mesh " + testing::source_path("geometries/spring_mass.toml") + " --quiet" + water +
                                 " --set water.mode=" + mode +
                                 " --set water.bulk_modulus=1.0e5 --set materials.spring.porosity=0.3 --out " +
                                 dir_->file(std::string("model-") + mode));
      ASSERT_EQ(wet.status, 0) << wet.output;
    }
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string model() { return dir_->file("model/model.h5"); }
  static std::string water_model(const std::string& mode) { return dir_->file("model-" + mode + "/model.h5"); }
  static ScratchDir* dir_;
};
ScratchDir* Restart::dir_ = nullptr;

// Solves uninterrupted and stopped-then-restarted on `threads` threads; the frames and the
// history must agree bit for bit. With `check_refusals`, a checkpoint of another format
// version and one of a changed model are refused first. With `water`, the pore pressures too.
void expect_restart_bit_for_bit(const std::string& model, const fs::path& dir, int threads, bool check_refusals,
                                bool water = false) {
  const std::string t = " --threads " + std::to_string(threads);
  const fs::path whole = dir / "whole", parts = dir / "parts";
  const auto uninterrupted = run_talus("solve " + model + t + " --quiet --out " + whole.string());
  ASSERT_EQ(uninterrupted.status, 0) << uninterrupted.output;

  const auto stopped = interrupt("solve " + model + t + " --quiet --checkpoint-interval 0.01 --out " +
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

  if (check_refusals) {
    // A checkpoint of another format version is refused with both versions.
    const fs::path other = dir / "other-version";
    fs::create_directories(other);
    fs::copy(parts, other, fs::copy_options::recursive);
    {
      h5::File file = h5::File::open_write((other / "checkpoint.h5").string());
      h5::set_attribute(file, "/", "format_version", int64_t{7});
    }
    const auto refused = run_talus("solve " + model + t + " --quiet --restart --out " + other.string());
    EXPECT_EQ(refused.status, 1) << refused.output;
    EXPECT_NE(refused.output.find("file has version 7, this talus reads version " +
                                  std::to_string(solver::kCheckpointFormatVersion)),
              std::string::npos)
        << refused.output;

    // A model meshed from a changed scene is refused, naming what changed.
    const fs::path changed = dir / "changed-scene";
    fs::create_directories(changed);
    fs::copy(parts, changed, fs::copy_options::recursive);
    const auto meshed = run_talus("mesh " + testing::source_path("geometries/spring_mass.toml") +
                                  " --quiet --set materials.spring.youngs_modulus=6e5 --set run.cfl=0.4 --out " +
                                  (changed / "model").string());
    ASSERT_EQ(meshed.status, 0) << meshed.output;
    const auto stale = run_talus("solve " + (changed / "model" / "model.h5").string() + t +
                                 " --quiet --restart --out " + changed.string());
    EXPECT_EQ(stale.status, 1) << stale.output;
    EXPECT_NE(stale.output.find("materials.spring, run settings changed"), std::string::npos) << stale.output;
    EXPECT_EQ(stale.output.find("materials.block"), std::string::npos) << stale.output;
  }

  const auto restarted = run_talus("solve " + model + t + " --quiet --restart --out " + parts.string());
  ASSERT_EQ(restarted.status, 0) << restarted.output;
  EXPECT_FALSE(fs::exists(parts / "checkpoint.h5")) << "a complete run leaves no checkpoint";

  const std::string reference = (whole / "results.h5").string();
  EXPECT_EQ(h5::get_int(h5::File::open_read(results), "/", "complete"), 1);
  EXPECT_EQ(h5::get_int(h5::File::open_read(results), "/", "steps"),
            h5::get_int(h5::File::open_read(reference), "/", "steps"));
  const std::string last_view =
      "xdmf/" + std::to_string(h5::read_doubles(h5::File::open_read(reference), "frames/time").size() - 1) + "/";
  std::vector<std::string> compared{"frames/time", "frames/position", "frames/velocity", "frames/stress",
                                    "frames/plastic_strain", "frames/displacement", "frames/volume",
                                    "history/time", "history/kinetic_energy", "history/strain_energy",
                                    last_view + "displacement", last_view + "stress_yy"};
  if (water) compared.insert(compared.end(), {"frames/pore_pressure", last_view + "pore_pressure"});
  for (const std::string& path : compared) {
    SCOPED_TRACE(path);
    const auto expected = dataset(reference, path), actual = dataset(results, path);
    ASSERT_EQ(actual.size(), expected.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < expected.size(); ++i) differing += actual[i] != expected[i];
    EXPECT_EQ(differing, 0u) << "values differ from the uninterrupted run";
  }
  // The XDMF's views: one group per frame (the frames dropped by the restart made anew) and the
  // connectivity.
  EXPECT_EQ(h5::list(h5::File::open_read(results), "xdmf").size(),
            h5::list(h5::File::open_read(reference), "xdmf").size());
}

TEST_F(Restart, SigtermMidwayThenRestartGivesTheUninterruptedFramesBitForBit) {
  expect_restart_bit_for_bit(model(), dir_->path() / "one-thread", 1, true);
}

TEST_F(Restart, BitForBitOnTwoThreadsToo) {
  expect_restart_bit_for_bit(model(), dir_->path() / "two-threads", 2, false);
}

TEST_F(Restart, WithADrainedRisingWaterTableBitForBit) {
  expect_restart_bit_for_bit(water_model("drained"), dir_->path() / "drained", 1, false, true);
}

// The undrained excess pore pressure is carried by the particles (a checkpointed field).
TEST_F(Restart, WithUndrainedWaterBitForBit) {
  expect_restart_bit_for_bit(water_model("undrained"), dir_->path() / "undrained", 1, false, true);
  // Against the drained (hydrostatic) value at each particle's position, the table at
  // 0.5 + 0.4 t / 0.13 m: most particles below it carry an excess.
  const std::string results = dir_->file("undrained/parts/results.h5");
  const auto u = dataset(results, "frames/pore_pressure"), x = dataset(results, "frames/position"),
             t = dataset(results, "frames/time");
  const std::size_t n = u.size() / t.size();
  std::size_t wet = 0, excess = 0;
  for (std::size_t f = 0; f < t.size(); ++f)
    for (std::size_t p = 0; p < n; ++p) {
      const double depth = 0.5 + 0.4 * std::min(t[f], 0.13) / 0.13 - x[2 * (f * n + p) + 1];
      if (depth <= 0.01) continue;
      ++wet;
      excess += std::abs(u[f * n + p] - 9810 * depth) > 1.0;
    }
  EXPECT_GT(excess, wet / 2) << "the undrained run has no excess pore pressure";
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
