// Process limits through the binary (issue 43, items 2 and 3): memory (ulimit -v, a cgroup's
// limit) and threads (OMP_NUM_THREADS). A mesh too large for the memory left is refused before
// gmsh runs, naming the limit; memory that runs out later ends the stage with one message and
// exit status 3 (before: std::terminate and SIGABRT while meshing, "internal error" and status 2
// while solving); an absurd OMP_NUM_THREADS is not trusted.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "common/h5.hpp"
#include "preproc/estimate.hpp"
#include "solver/parallel/threads.hpp"
#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::run_shell;
using testing::ScratchDir;

TEST(OutOfMemory, AMeshTooLargeForTheAddressSpaceLimitIsRefusedBeforeGmshRuns) {
  // Before: the estimate read MemAvailable only, gmsh ran out of memory in an OpenMP region and
  // std::terminate ended talus with SIGABRT (status 134), leaving the folder behind.
  const ScratchDir dir("oom-mesh");
  const auto result = testing::talus_with_limit("-v 150000", "mesh " + testing::source_path("geometries/slope.toml") +
                                           " --set mesh.size=0.0625 --out " + dir.file("out"));
  EXPECT_EQ(result.status, 1) << result.output;
  for (const char* words : {"slope.toml: mesh.size: an element size of 0.0625 m", " GB to solve (500 B per particle",
                            " GB left by the address-space limit (ulimit -v) of 0.154 GB, less the ",
                            " GB this process maps already: raise mesh.size"})
    EXPECT_NE(result.output.find(words), std::string::npos) << words << " not in: " << result.output;
  EXPECT_FALSE(fs::exists(dir.file("out")));
}

// Whatever the limit, a solve ends with its results or with one message and status 3: memory
// that runs out while the simulation is set up leaves no results, and in the time loop keeps the
// frames written so far, marked incomplete. Limits from too small to enough, so that both the
// set-up and the loop run out at some of them on any build.
TEST(OutOfMemory, ASolveUnderAnyAddressSpaceLimitEndsWithOneMessage) {
  const ScratchDir dir("oom-solve");
  const auto meshed = testing::run_talus("mesh " + testing::source_path("geometries/slope.toml") +
                                         " -q --set mesh.size=0.125 --set run.max_steps=40 --out " + dir.file("m"));
  ASSERT_EQ(meshed.status, 0) << meshed.output;
  // Below some limit the loader cannot map talus's libraries ("out of memory", status 127):
  // the sweep starts where talus runs.
  long lowest = 50000;
  while (lowest < 1000000 && testing::talus_with_limit("-v " + std::to_string(lowest), "--version").status != 0) lowest += 10000;
  int failed = 0, solved = 0;
  for (long kilobytes = lowest; kilobytes <= lowest + 260000; kilobytes += 20000) {
    SCOPED_TRACE("ulimit -v " + std::to_string(kilobytes));
    const std::string out = dir.file("out" + std::to_string(kilobytes));
    const auto result = testing::talus_with_limit("-v " + std::to_string(kilobytes), "solve " + dir.file("m/model.h5") + " --threads 1 -q --out " + out);
    ASSERT_TRUE(result.status == 0 || result.status == 3) << result.output;
    if (result.status == 0) {
      ++solved;
      continue;
    }
    ++failed;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
    EXPECT_EQ(result.output.rfind("talus: error: out of memory ", 0), 0u) << result.output;
    if (result.output.find("out of memory at step ") != std::string::npos) {
      EXPECT_NE(result.output.find(" frames kept in " + out + "/results.h5 (incomplete)"), std::string::npos)
          << result.output;
      EXPECT_EQ(h5::get_int(h5::File::open_read(out + "/results.h5"), "/", "complete"), 0);
    } else {
      EXPECT_NE(result.output.find("out of memory in talus solve (std::bad_alloc)"), std::string::npos)
          << result.output;
      EXPECT_FALSE(fs::exists(out + "/results.h5"));
    }
  }
  EXPECT_GT(failed, 0);
  EXPECT_GT(solved, 0);
}

// The cgroup's limit, read as the kernel lays it out, in a folder made to look alike: v2 (one
// hierarchy) and v1 (the memory controller's own), with a parent's limit tighter than the
// cgroup's own.
TEST(OutOfMemory, TheCgroupsMemoryLimitIsRead) {
  const ScratchDir dir("cgroup");
  const std::string root = dir.path().string();
  auto write = [&](const std::string& path, const std::string& text) { testing::write_file(root + path, text); };
  write("/proc/self/cgroup", "0::/user.slice/job\n");
  write("/proc/self/mountinfo", "35 24 0:30 / /sys/fs/cgroup rw,nosuid - cgroup2 cgroup2 rw\n");
  write("/sys/fs/cgroup/user.slice/job/memory.max", "1000000\n");
  write("/sys/fs/cgroup/user.slice/job/memory.current", "400000\n");
  write("/sys/fs/cgroup/user.slice/memory.max", "max\n");
  EXPECT_DOUBLE_EQ(preproc::cgroup_memory_left(root), 600000);
  write("/sys/fs/cgroup/user.slice/memory.max", "700000\n");
  write("/sys/fs/cgroup/user.slice/memory.current", "500000\n");
  EXPECT_DOUBLE_EQ(preproc::cgroup_memory_left(root), 200000);

  const ScratchDir v1("cgroup-v1");
  const std::string root1 = v1.path().string();
  testing::write_file(root1 + "/proc/self/cgroup", "5:devices:/\n4:memory:/batch/job\n0::/\n");
  testing::write_file(root1 + "/proc/self/mountinfo",
                      "31 23 0:28 / /sys/fs/cgroup rw - tmpfs tmpfs rw\n"
                      "35 31 0:32 / /sys/fs/cgroup/memory rw,relatime - cgroup cgroup rw,memory\n");
  testing::write_file(root1 + "/sys/fs/cgroup/memory/batch/job/memory.limit_in_bytes", "3000000\n");
  testing::write_file(root1 + "/sys/fs/cgroup/memory/batch/job/memory.usage_in_bytes", "1000000\n");
  // No limit: the kernel's largest page-aligned number.
  testing::write_file(root1 + "/sys/fs/cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");
  testing::write_file(root1 + "/sys/fs/cgroup/memory/memory.usage_in_bytes", "5000000\n");
  EXPECT_DOUBLE_EQ(preproc::cgroup_memory_left(root1), 2000000);
  // No cgroup files at all: no limit.
  EXPECT_EQ(preproc::cgroup_memory_left(dir.file("nowhere")), INFINITY);
}

// OMP_NUM_THREADS=100000 (issue 43, item 3): before, the automatic choice took a thread per 250
// particles up to it (17 threads for the slope at mesh.size 0.5 on two cores, 1,202 and 7.6 GB
// for 300k particles). Above the cap of --threads it is not trusted: the cores decide, as
// without it, and the summary line says so.
TEST(Threads, AnOmpNumThreadsAboveTheCapIsIgnored) {
  const ScratchDir dir("omp-threads");
  const auto meshed = testing::run_talus("mesh " + testing::source_path("geometries/slope.toml") +
                                         " -q --set mesh.size=0.5 --set run.end_time=0.2 --out " + dir.path().string());
  ASSERT_EQ(meshed.status, 0) << meshed.output;
  const std::string solve = std::string(TALUS_BINARY) + " solve " + dir.file("model.h5") + " --out " + dir.file("o");
  const auto plain = run_shell("env -u OMP_NUM_THREADS TALUS_BUSY_CORES=0 " + solve);
  const auto absurd = run_shell("env OMP_NUM_THREADS=100000 TALUS_BUSY_CORES=0 " + solve);
  ASSERT_EQ(plain.status, 0) << plain.output;
  ASSERT_EQ(absurd.status, 0) << absurd.output;
  auto threads = [](const std::string& output) {
    const auto at = output.find(" s on ");
    return at == std::string::npos ? -1 : std::stoi(output.substr(at + 6));
  };
  EXPECT_EQ(threads(absurd.output), threads(plain.output)) << plain.output << absurd.output;
  EXPECT_LE(threads(absurd.output), solver::available_cores());
  EXPECT_NE(absurd.output.find("; OMP_NUM_THREADS=100000 ignored, above the cap of " +
                               std::to_string(solver::thread_cap())),
            std::string::npos)
      << absurd.output;
  // Up to the cap it is the user's count, as before (more threads than cores when asked).
  setenv("OMP_NUM_THREADS", std::to_string(solver::thread_cap()).c_str(), 1);
  EXPECT_EQ(solver::environment_threads(), solver::thread_cap());
  setenv("OMP_NUM_THREADS", "100000", 1);
  EXPECT_EQ(solver::environment_threads(), -1);
  unsetenv("OMP_NUM_THREADS");
  EXPECT_EQ(solver::environment_threads(), 0);
}

}  // namespace
}  // namespace talus
