// The frames of a distributed solve written by every rank into the one results.h5 with the
// parallel HDF5 (solver/io/results_parallel.hpp), through the talus binary: on 2 and 3 ranks the
// file has exactly the objects, shapes and attributes of one rank's, its frames agree within
// 1e-10 relative and results.xdmf is the same text; a write that fails on one rank leaves no
// results behind and stops them all with one message. Skipped when the binary was built without
// MPI; built without the parallel HDF5 it gathers the frames on rank 0 instead, and the file
// must be the same all the same.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::run_talus;
using testing::ScratchDir;

bool is_group(const h5::File& file, const std::string& path) {
  H5O_info_t info;
  return H5Oget_info_by_name2(file.id(), path.c_str(), &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0 &&
         info.type == H5O_TYPE_GROUP;
}

// An attribute's value as text: a string, or its numbers.
std::string attribute_text(const h5::File& file, const std::string& path, const std::string& name) {
  try {
    return h5::get_string(file, path, name);
  } catch (const Error&) {
    std::string text;
    char number[32];
    for (double value : h5::get_doubles(file, path, name)) {
      std::snprintf(number, sizeof number, "%.17g ", value);
      text += number;
    }
    return text;
  }
}

// Every object below `group` (its path, "group" or the dataset's shape) and every attribute
// (path@name, its value; the time loop's wall time by name only).
void describe(const h5::File& file, const std::string& group, std::map<std::string, std::string>& out) {
  for (const std::string& name : h5::list_attributes(file, group))
    out[group + "@" + name] = name == "loop_seconds" ? "" : attribute_text(file, group, name);
  if (!is_group(file, group.empty() ? "/" : group)) {
    std::string shape;
    for (hsize_t d : h5::shape(file, group)) shape += std::to_string(d) + " ";
    out[group] = "dataset " + shape;
    return;
  }
  out[group] = "group";
  for (const std::string& name : h5::list(file, group)) describe(file, group.empty() ? name : group + "/" + name, out);
}

std::map<std::string, std::string> layout(const std::string& path) {
  std::map<std::string, std::string> objects;
  describe(h5::File::open_read(path), "", objects);
  return objects;
}

class MpiHdf5 : public ::testing::Test {
 protected:
  void SetUp() override {
    // "(with MPI..." or "(without MPI: one rank)".
    if (testing::talus_version().find("(with MPI") == std::string::npos) GTEST_SKIP() << "talus was built without MPI";
  }
  // The default slope coarsened to 0.5 m elements, to t = 1 s (11 frames): its failure crosses
  // the partitions. Meshed into DIR/model.
  std::string mesh(const ScratchDir& dir) {
    const auto meshed = run_talus("mesh " + testing::source_path("geometries/slope.toml") +
                                  " --quiet --set mesh.size=0.5 --set run.end_time=1.0 --out " + dir.file("model"));
    EXPECT_EQ(meshed.status, 0) << meshed.output;
    return dir.file("model/model.h5");
  }
  static testing::CommandResult solve(const std::string& model, int ranks, const std::string& out) {
    return run_talus("solve " + model + " --threads 1 --ranks " + std::to_string(ranks) + " --out " + out);
  }
};

TEST_F(MpiHdf5, TwoAndThreeRanksWriteTheFileOneRankWrites) {
  const ScratchDir dir("mpi-hdf5");
  const std::string model = mesh(dir);
  ASSERT_EQ(solve(model, 1, dir.file("r1")).status, 0);
  const auto serial = layout(dir.file("r1/results.h5"));
  ASSERT_GT(serial.count("frames/stress"), 0u);
  const std::string xdmf = testing::read_text(dir.file("r1/results.xdmf"));
  ASSERT_FALSE(xdmf.empty());
  const bool parallel = testing::talus_version().find("parallel HDF5") != std::string::npos;
  for (int ranks : {2, 3}) {
    const std::string out = dir.file("r" + std::to_string(ranks));
    const auto solved = solve(model, ranks, out);
    ASSERT_EQ(solved.status, 0) << solved.output;
    EXPECT_NE(solved.output.find(parallel ? "frames written by every rank" : "frames gathered on rank 0"),
              std::string::npos)
        << solved.output;
    const auto distributed = layout(out + "/results.h5");
    for (const auto& [path, what] : serial) {
      const auto found = distributed.find(path);
      EXPECT_TRUE(found != distributed.end() && found->second == what)
          << ranks << " ranks: " << path << ": " << what << " against "
          << (found == distributed.end() ? "missing" : found->second);
    }
    EXPECT_EQ(distributed.size(), serial.size()) << ranks << " ranks";
    std::string worst;
    EXPECT_LE(testing::frame_difference(dir.file("r1/results.h5"), out + "/results.h5", worst), 1e-10)
        << ranks << " ranks: " << worst;
    EXPECT_EQ(testing::read_text(out + "/results.xdmf"), xdmf) << ranks << " ranks";
  }
}

TEST_F(MpiHdf5, AWriteThatFailsOnOneRankLeavesNoResultsAndOneMessage) {
  if (testing::talus_version().find("parallel HDF5") == std::string::npos) GTEST_SKIP() << "frames gathered on rank 0";
  const ScratchDir dir("mpi-hdf5-full");
  const std::string out = dir.file("out");
  ASSERT_EQ(run_talus(testing::scene_row(dir.path(), testing::kScene) + " --quiet --out " + out).status, 0);
  // Rank 1 alone with a file size limit (ulimit -f, 512-byte blocks, SIGXFSZ ignored so that the
  // write fails instead of killing it): 210 kB passes the estimate of results.h5 (170 kB), rank 0
  // writes the metadata past it, and rank 1's rows of the last frame fail in the collective write.
  const std::string rank_one_limited = "trap \"\" XFSZ; if [ \"$OMPI_COMM_WORLD_RANK\" = 1 ]; then ulimit -f 420; fi; "
                                       "exec " + std::string(TALUS_BINARY) + " solve " + out + "/model.h5 --threads 1";
  const auto result = testing::run_shell(std::string("mpirun -n 2 --oversubscribe --bind-to none --quiet ") +
                                (geteuid() == 0 ? "--allow-run-as-root " : "") + "sh -c '" + rank_one_limited + "'");
  EXPECT_NE(result.status, 0) << result.output;
  EXPECT_NE(result.output.find(out + "/results.h5: frames/"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("cannot write the frame's rows"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("removed " + out + "/results.h5 and results.xdmf"), std::string::npos) << result.output;
  std::size_t messages = 0;
  for (auto at = result.output.find("talus: error"); at != std::string::npos; at = result.output.find("talus: error", at + 1))
    ++messages;
  EXPECT_EQ(messages, 1u) << result.output;
  EXPECT_FALSE(fs::exists(out + "/results.h5"));
  EXPECT_FALSE(fs::exists(out + "/results.xdmf"));
}

}  // namespace
}  // namespace talus
