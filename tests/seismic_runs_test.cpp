// Earthquakes end to end (docs/seismic.md): strength reduction with a seismic coefficient
// against Bishop's, and the shaken box against Newmark's sliding block.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "support/test_support.hpp"

namespace {

using talus::testing::json_number;
using talus::testing::read_text;

// Griffiths and Lane's (1999) example 1 (geometries/griffiths_lane.toml, F = 1.4 without k_h)
// with k_h = 0.1 towards the toe: `talus fos` applies k_h g as a body force from the start of its
// equilibrium phase, Bishop the force k_h W on each slice; within 5 %.
TEST(SeismicFos, StrengthReductionWithinFivePercentOfBishopOnGriffithsLane) {
  talus::testing::ScratchDir dir("seismic_fos_griffiths_lane");
  const auto run = talus::testing::run_talus("fos " + talus::testing::source_path("geometries/griffiths_lane.toml") +
                                             " --out " + dir.path().string() +
                                             " --threads 2 --quiet --tolerance=0.02 --set seismic.k_h=0.1");
  ASSERT_EQ(run.status, 0) << run.output;
  const std::string json = read_text(dir.file("fos.json"));
  const double srm = json_number(json, "factor_of_safety"), bishop = json_number(json, "bishop_fos");
  std::cout << "Griffiths and Lane with k_h = 0.1: fos " << srm << ", Bishop " << bishop << ", k_y "
            << json_number(json, "k_y") << "\n";
  EXPECT_NEAR(srm, bishop, 0.05 * bishop) << json;
  EXPECT_LT(bishop, 1.38 * 0.9);  // below the static 1.38
  EXPECT_NEAR(json_number(json, "k_h"), 0.1, 1e-12);
  // k_y: Bishop's F at k_y is 1, between F(0) = 1.38 and F(0.1) = bishop > 1.
  EXPECT_GT(json_number(json, "k_y"), 0.1);
}

// Newmark's (1965) block (geometries/newmark_block.toml): the box on the shaken 30 deg incline,
// mu = 0.6, a sine of 2 Hz for 3 cycles at two amplitudes; its permanent displacement down the
// incline, relative to the ground, within 5 % of Newmark's integration of the same record.
void expect_newmark(double amplitude) {
  talus::testing::ScratchDir dir("seismic_newmark_block");
  const auto run = talus::testing::run_talus("run " + talus::testing::source_path("geometries/newmark_block.toml") +
                                             " --out " + dir.path().string() + " --threads 1 --set base_motion.amplitude=" +
                                             std::to_string(amplitude) + " --set post.animate=false");
  ASSERT_EQ(run.status, 0) << run.output;
  const std::string json = read_text(dir.file("metrics.json"));
  const double mpm = json_number(json, "mpm_displacement_m"), newmark = json_number(json, "newmark_displacement_m");
  std::cout << "Newmark's block at " << amplitude << " m/s^2: MPM " << mpm << " m, Newmark " << newmark << " m\n";
  EXPECT_GT(newmark, 0.05);
  EXPECT_NEAR(mpm, newmark, 0.05 * newmark) << json;
}

TEST(NewmarkBlock, PermanentDisplacementWithinFivePercentAtOneMetrePerSecondSquared) { expect_newmark(1.0); }
TEST(NewmarkBlock, PermanentDisplacementWithinFivePercentAtTwoMetresPerSecondSquared) { expect_newmark(2.0); }

}  // namespace
