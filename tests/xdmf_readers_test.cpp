// results.xdmf as its readers see it: ParaView's three XDMF readers (legacy, Xdmf3 S, Xdmf3 T)
// through pvbatch, and meshio's time-series reader, each opening every frame of a small run
// (tests/support/xdmf_readers.py). Every reader must find all frames and particles, the
// documented arrays with their widths, each frame's geometry matching its displacement, and the
// numbers of results.h5. Skipped where pvbatch (Debian's python3-paraview) or meshio
// (python3-meshio) is missing; .ci/run installs both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "common/h5.hpp"
#include "solver/solver.hpp"
#include "support/test_support.hpp"

using namespace talus;
using talus::testing::ScratchDir;

namespace {

// Two bodies of two materials falling under gravity: 5 frames, a few hundred particles.
struct SmallRun {
  ScratchDir dir{"xdmf_readers"};
  std::size_t particles = 0;
  long frames = 0;
  double last_time = 0, max_displacement = 0;
  long material_sum = 0;

  SmallRun() {
    Model model = talus::testing::rectangle_mesh(0, 0, 10, 20, 0.1);
    talus::testing::add_box_body(model, "block", talus::testing::elastic(1000, 1e6, 0.3), 0.3, 0.7, 1.2, 1.6);
    talus::testing::add_box_body(model, "plate", talus::testing::elastic(500, 2e6, 0.2), 0.2, 0.8, 0.5, 0.7);
    model.fixed_nodes = model.node_sets["bottom"];
    talus::testing::set_run(model, 0.1, Eigen::Vector2d(0, -9.81));
    model.run.output_interval = 0.025;
    model.contact.enabled = false;
    solver::SolveOptions options;
    options.out_dir = dir.path().string();
    options.progress = false;
    std::ostringstream log;
    solver::solve(model, options, log);

    const h5::File file = h5::File::open_read(dir.file("results.h5"));
    particles = model.particle_count();
    const auto time = h5::read_doubles(file, "frames/time");
    frames = static_cast<long>(time.size());
    last_time = time.back();
    const auto displacement = h5::read_doubles(file, "frames/displacement");
    for (std::size_t p = 0; p < particles; ++p) {
      const std::size_t at = ((frames - 1) * particles + p) * 2;
      max_displacement = std::max(max_displacement, std::hypot(displacement[at], displacement[at + 1]));
    }
    for (int32_t material : h5::read_ints(file, "particles/material")) material_sum += material;
  }
};

const SmallRun& small_run() {
  static const SmallRun run;
  return run;
}

std::string script() { return talus::testing::source_path("tests/support/xdmf_readers.py"); }

bool available(const std::string& check) { return talus::testing::run_shell(check + " >/dev/null").status == 0; }

// The key=value pairs of the line of `output` that starts with "reader=NAME".
std::map<std::string, std::string> reader_line(const std::string& output, const std::string& name) {
  std::istringstream lines(output);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("reader=" + name + " ", 0) != 0) continue;
    std::map<std::string, std::string> values;
    std::istringstream words(line);
    for (std::string word; words >> word;)
      if (const auto eq = word.find('='); eq != std::string::npos) values[word.substr(0, eq)] = word.substr(eq + 1);
    return values;
  }
  return {};
}

void expect_reader(const std::string& output, const std::string& name) {
  SCOPED_TRACE(name);
  const SmallRun& run = small_run();
  const auto values = reader_line(output, name);
  ASSERT_FALSE(values.empty()) << "no line for reader " << name << " in:\n" << output;
  EXPECT_EQ(std::stol(values.at("frames")), run.frames);
  EXPECT_EQ(std::stoul(values.at("points")), run.particles);
  EXPECT_EQ(values.at("arrays"),
            "body:1,displacement:3,material:1,plastic_strain:1,stress_xx:1,stress_xy:1,stress_yy:1,stress_zz:1,"
            "velocity:3,volume:1");
  EXPECT_NEAR(std::stod(values.at("last_time")), run.last_time, 1e-12);
  EXPECT_GT(run.max_displacement, 1e-3);  // the bodies fell: the comparison below means something
  EXPECT_NEAR(std::stod(values.at("max_displacement")), run.max_displacement, 1e-10);
  EXPECT_LE(std::stod(values.at("position_mismatch")), 1e-12);
  EXPECT_EQ(std::stol(values.at("material_sum")), run.material_sum);
}

}  // namespace

TEST(XdmfReaders, ParaViewsThreeReadersOpenEveryFrame) {
  if (!available("command -v pvbatch"))
    GTEST_SKIP() << "pvbatch not installed (apt-get install python3-paraview): ParaView's readers not checked";
  const SmallRun& run = small_run();
  ASSERT_GE(run.frames, 5);
  const auto result = talus::testing::run_shell("pvbatch " + script() + " paraview " + run.dir.file("results.xdmf"));
  ASSERT_EQ(result.status, 0) << result.output;  // a crash (SIGSEGV) of a reader ends here
  for (const char* reader : {"legacy", "xdmf3_s", "xdmf3_t"}) expect_reader(result.output, reader);
}

TEST(XdmfReaders, MeshioReadsEveryFrame) {
  if (!available("/usr/bin/python3 -c 'import meshio'"))
    GTEST_SKIP() << "meshio not installed (apt-get install python3-meshio): meshio's reader not checked";
  const SmallRun& run = small_run();
  const auto result =
      talus::testing::run_shell("/usr/bin/python3 " + script() + " meshio " + run.dir.file("results.xdmf"));
  ASSERT_EQ(result.status, 0) << result.output;
  expect_reader(result.output, "meshio");
}
