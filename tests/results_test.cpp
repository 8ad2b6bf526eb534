// solve() as users and benchmarks see it: the results.h5 contract, frames flushed as written,
// blow-up detection that keeps the frames and never writes NaN, particles leaving the domain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "solver/io/io.hpp"
#include "solver/solver.hpp"
#include "support/test_support.hpp"

using namespace talus;
using talus::testing::add_box_body;
using talus::testing::elastic;
using talus::testing::rectangle_mesh;
using talus::testing::ScratchDir;
using talus::testing::set_run;

namespace {

Model falling_block() {
  Model model = rectangle_mesh(0, 0, 10, 20, 0.1);
  add_box_body(model, "block", elastic(1000, 1e6, 0.3), 0.3, 0.7, 1.2, 1.6);
  add_box_body(model, "plate", elastic(500, 2e6, 0.2), 0.2, 0.8, 0.5, 0.7);
  model.fixed_nodes = model.node_sets["bottom"];
  set_run(model, 0.2, Eigen::Vector2d(0, -9.81));
  model.run.output_interval = 0.05;
  model.run.history_interval = 5;
  model.contact.enabled = false;
  return model;
}

solver::SolveSummary run(const Model& model, const ScratchDir& dir) {
  solver::SolveOptions options;
  options.out_dir = dir.path().string();
  options.progress = false;
  std::ostringstream log;
  return solver::solve(model, options, log);
}

bool all_finite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

}  // namespace

TEST(Results, DatasetsHaveTheDocumentedNamesAndShapes) {
  ScratchDir dir("results");
  const Model model = falling_block();
  const auto summary = run(model, dir);
  const std::size_t n = model.particle_count();

  const h5::File file = h5::File::open_read(dir.file("results.h5"));
  EXPECT_EQ(h5::get_string(file, "/", "format"), "talus-results");
  EXPECT_EQ(h5::get_int(file, "/", "particles"), static_cast<int64_t>(n));
  EXPECT_EQ(h5::get_int(file, "/", "steps"), summary.steps);
  EXPECT_GT(h5::get_double(file, "/", "loop_seconds"), 0.0);

  const auto time = h5::read_doubles(file, "frames/time");
  ASSERT_EQ(time.size(), 5u);  // t = 0, 0.05, ..., 0.2: frames land on the output times
  for (std::size_t f = 0; f < time.size(); ++f) EXPECT_NEAR(time[f], 0.05 * f, 1e-12);
  EXPECT_EQ(h5::shape(file, "frames/position"), (h5::Dims{5, n, 2}));
  EXPECT_EQ(h5::shape(file, "frames/velocity"), (h5::Dims{5, n, 2}));
  EXPECT_EQ(h5::shape(file, "frames/stress"), (h5::Dims{5, n, 4}));
  EXPECT_EQ(h5::shape(file, "frames/plastic_strain"), (h5::Dims{5, n}));
  EXPECT_EQ(h5::shape(file, "frames/displacement"), (h5::Dims{5, n, 2}));
  EXPECT_EQ(h5::shape(file, "frames/volume"), (h5::Dims{5, n}));
  EXPECT_EQ(h5::shape(file, "particles/body"), (h5::Dims{n}));
  EXPECT_EQ(h5::shape(file, "particles/material"), (h5::Dims{n}));
  EXPECT_EQ(h5::shape(file, "particles/mass"), (h5::Dims{n}));
  EXPECT_EQ(h5::read_strings(file, "bodies/names"), (std::vector<std::string>{"block", "plate"}));

  // Frames keep the model's particle order although the solver sorts its particles.
  const auto position = h5::read_doubles(file, "frames/position");
  for (std::size_t p = 0; p < n; ++p) {
    EXPECT_EQ(position[2 * p], model.position[p].x());
    EXPECT_EQ(position[2 * p + 1], model.position[p].y());
  }
  // Displacement is position less the initial position; the first volume is the model's; each
  // particle carries its body's material; the XDMF's per-frame views read the frame datasets.
  const auto displacement = h5::read_doubles(file, "frames/displacement");
  ASSERT_EQ(displacement.size(), position.size());
  for (std::size_t k = 0; k < position.size(); ++k)
    EXPECT_EQ(displacement[k], position[k] - model.position[(k / 2) % n][k % 2]);
  const auto volume = h5::read_doubles(file, "frames/volume");
  for (std::size_t p = 0; p < n; ++p) EXPECT_EQ(volume[p], model.volume[p]);
  const auto material = h5::read_ints(file, "particles/material");
  for (std::size_t p = 0; p < n; ++p) EXPECT_EQ(material[p], model.bodies[model.body[p]].material);
  std::vector<double> view = h5::read_doubles(file, "xdmf/4/velocity");
  ASSERT_EQ(view.size(), 3 * n);
  const auto velocity_frames = h5::read_doubles(file, "frames/velocity");
  for (std::size_t p = 0; p < n; ++p) {
    EXPECT_EQ(view[3 * p], velocity_frames[(4 * n + p) * 2]);
    EXPECT_EQ(view[3 * p + 1], velocity_frames[(4 * n + p) * 2 + 1]);
    EXPECT_EQ(view[3 * p + 2], 0.0);
  }
  view = h5::read_doubles(file, "xdmf/3/stress_xy");
  const auto stress = h5::read_doubles(file, "frames/stress");
  for (std::size_t p = 0; p < n; ++p) EXPECT_EQ(view[p], stress[(3 * n + p) * 4 + 3]);

  // The block falls freely until it meets the plate (0.5 m below) after 0.2 s: sqrt(2 0.5 / g) = 0.32 s.
  const auto velocity = h5::read_doubles(file, "frames/velocity");
  for (std::size_t p = 0; p < n; ++p)
    if (model.body[p] == 0) {
      EXPECT_NEAR(velocity[((4 * n) + p) * 2 + 1], -9.81 * 0.2, 1e-9);
    }

  // Energy history every few steps, with gravity's work turned into kinetic energy.
  const auto history_time = h5::read_doubles(file, "history/time");
  const auto kinetic = h5::read_doubles(file, "history/kinetic_energy");
  const auto potential = h5::read_doubles(file, "history/potential_energy");
  const auto strain = h5::read_doubles(file, "history/strain_energy");
  ASSERT_GE(history_time.size(), static_cast<std::size_t>(summary.steps / 5));
  ASSERT_EQ(kinetic.size(), history_time.size());
  const double total0 = kinetic.front() + potential.front() + strain.front();
  const double total1 = kinetic.back() + potential.back() + strain.back();
  EXPECT_GT(kinetic.back(), 0.0);
  EXPECT_NEAR(total1, total0, 0.02 * kinetic.back());

  // ParaView's entry point refers to every frame.
  std::ifstream xdmf(dir.file("results.xdmf"));
  std::stringstream text;
  text << xdmf.rdbuf();
  std::size_t grids = 0;
  for (std::size_t at = text.str().find("<Time Value"); at != std::string::npos; at = text.str().find("<Time Value", at + 1))
    ++grids;
  EXPECT_EQ(grids, 5u);
  EXPECT_NE(text.str().find("results.h5:/xdmf/4/position"), std::string::npos);
  EXPECT_EQ(text.str().find("results.h5:/xdmf/5/"), std::string::npos);
}

TEST(Results, BlowUpStopsTheRunKeepsTheFramesAndWritesNoNaN) {
  ScratchDir dir("blowup");
  Model model = falling_block();
  model.run.cfl = 8;  // far past the stability limit of the explicit step (scenes cap it at 1)
  model.run.end_time = 1.0;
  model.run.output_interval = 0.1;  // frames must not shorten the step themselves
  try {
    run(model, dir);
    FAIL() << "the run should have blown up";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("blow-up"), std::string::npos) << message;
    EXPECT_NE(message.find("t = "), std::string::npos) << message;
    EXPECT_NE(message.find("frames kept"), std::string::npos) << message;
  }
  const h5::File file = h5::File::open_read(dir.file("results.h5"));
  EXPECT_EQ(h5::get_int(file, "/", "complete"), 0);
  EXPECT_GE(h5::read_doubles(file, "frames/time").size(), 1u);
  EXPECT_TRUE(all_finite(h5::read_doubles(file, "frames/position")));
  EXPECT_TRUE(all_finite(h5::read_doubles(file, "frames/stress")));
  EXPECT_TRUE(all_finite(h5::read_doubles(file, "history/kinetic_energy")));
}

TEST(Results, AParticleLeavingTheDomainIsAnErrorWithItsIdAndPosition) {
  ScratchDir dir("leaving");
  Model model = rectangle_mesh(0, 0, 10, 10, 0.1);
  add_box_body(model, "block", elastic(1000, 1e6, 0.3), 0.6, 0.8, 0.4, 0.6);
  for (auto& v : model.velocity) v = Eigen::Vector2d(3.0, 0.0);  // towards the open right side
  set_run(model, 1.0);
  model.run.output_interval = 0.05;
  try {
    run(model, dir);
    FAIL() << "a particle should have left the domain";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("left the domain at ("), std::string::npos) << message;
    EXPECT_NE(message.find("particle "), std::string::npos) << message;
  }
  // The block reaches x = 1 after about (1 - 0.8) / 3 = 0.067 s: frames up to then are kept.
  const h5::File file = h5::File::open_read(dir.file("results.h5"));
  const auto time = h5::read_doubles(file, "frames/time");
  ASSERT_GE(time.size(), 2u);
  EXPECT_LE(time.back(), 0.07);
}

TEST(Results, ARunStoppedMidwayLeavesAReadableFileWithItsFrames) {
  // Frames are flushed as written: the file is readable while the run is still going, which is
  // what a killed run leaves. max_steps stops the run midway the way an interruption would.
  ScratchDir dir("midway");
  Model model = falling_block();
  model.run.max_steps = 40;
  const auto summary = run(model, dir);
  EXPECT_EQ(summary.steps, 40);
  const h5::File file = h5::File::open_read(dir.file("results.h5"));
  const auto time = h5::read_doubles(file, "frames/time");
  EXPECT_LT(time.back(), model.run.end_time);
  EXPECT_EQ(h5::shape(file, "frames/position")[0], time.size());
}

// More particles than one piece of a frame (solver/io/results.hpp, kFrameBlock: the writer fills
// and writes a frame a block of particle ids at a time), in an order the solver changes (the
// model's particles reversed, so that its sort reverses them back): every row lands on its
// particle. Frame 0 has the model's positions and velocities row for row, the displacement is
// the position less the initial position in every frame, and no particle is found far from
// where it started.
TEST(Results, FramesOfSeveralBlocksKeepTheModelsParticleOrder) {
  ScratchDir dir("results-blocks");
  Model model = rectangle_mesh(0, 0, 200, 100, 0.05);
  add_box_body(model, "block", elastic(1000, 1e6, 0.3), 0, 10, 0, 4);
  model.fixed_nodes = model.node_sets["bottom"];
  set_run(model, 0.002, Eigen::Vector2d(0, -9.81));
  model.run.output_interval = 0.001;
  model.contact.enabled = false;
  const std::size_t n = model.particle_count();
  ASSERT_GT(n, solver::kFrameBlock);
  for (std::size_t p = 0; p < n; ++p) model.velocity[p] = Eigen::Vector2d(1e-7 * p, -2e-7 * p);
  std::reverse(model.position.begin(), model.position.end());
  std::reverse(model.velocity.begin(), model.velocity.end());
  std::reverse(model.volume.begin(), model.volume.end());
  std::reverse(model.mass.begin(), model.mass.end());
  std::reverse(model.stress.begin(), model.stress.end());
  std::reverse(model.body.begin(), model.body.end());
  std::reverse(model.element.begin(), model.element.end());
  run(model, dir);

  const h5::File file = h5::File::open_read(dir.file("results.h5"));
  const auto initial = h5::read_doubles(file, "particles/initial_position");
  const auto position = h5::read_doubles(file, "frames/position");
  const auto displacement = h5::read_doubles(file, "frames/displacement");
  const auto velocity = h5::read_doubles(file, "frames/velocity");
  const std::size_t frames = h5::read_doubles(file, "frames/time").size();
  ASSERT_EQ(frames, 3u);
  ASSERT_EQ(initial.size(), 2 * n);
  std::size_t wrong_start = 0, wrong_velocity = 0, wrong_displacement = 0, far = 0;
  for (std::size_t p = 0; p < n; ++p)
    for (int k = 0; k < 2; ++k) {
      wrong_start += initial[2 * p + k] != model.position[p][k] || position[2 * p + k] != model.position[p][k];
      wrong_velocity += velocity[2 * p + k] != model.velocity[p][k];
    }
  for (std::size_t f = 0; f < frames; ++f)
    for (std::size_t i = 0; i < 2 * n; ++i) {
      const double x = position[f * 2 * n + i];
      wrong_displacement += displacement[f * 2 * n + i] != x - initial[i];
      far += std::abs(x - initial[i]) > 1e-3;  // 2 ms of gravity and at most 0.03 m/s: < 0.1 mm
    }
  EXPECT_EQ(wrong_start, 0u);
  EXPECT_EQ(wrong_velocity, 0u);
  EXPECT_EQ(wrong_displacement, 0u);
  EXPECT_EQ(far, 0u);
}
