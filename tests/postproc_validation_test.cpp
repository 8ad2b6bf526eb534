// The validation-scene comparisons: spring and mass, box on an incline.
#include <gtest/gtest.h>

#include <cmath>

#include "postproc/validation.hpp"

namespace talus::postproc {
namespace {

TEST(SpringMass, ErrorOverAmplitude) {
  const double amplitude = 1e-3, omega = 100;
  std::vector<double> t, centre_y;
  for (int k = 0; k <= 200; ++k) {
    t.push_back(1e-3 * k);
    // Exact settlement plus a 5% amplitude error at the period's quarter.
    const double error = (k == 16) ? 0.05 * amplitude : 0.0;
    centre_y.push_back(1.0 - amplitude * (1 - std::cos(omega * t.back())) - error);
  }
  const SpringMassCheck check = spring_mass_check(t, centre_y, 1.0, amplitude, omega);
  EXPECT_NEAR(check.max_error_over_amplitude, 0.05, 1e-9);
  EXPECT_NEAR(check.exact[31], amplitude * (1 - std::cos(3.1)), 1e-15);
}

TEST(BoxIncline, ExactMotionDownEitherSide) {
  const double angle = 30, g = 10, mu = 0.3;
  const double a = g * (std::sin(M_PI / 6) - mu * std::cos(M_PI / 6));  // 2.402, x = 1.201 t^2
  for (double side : {1.0, -1.0}) {
    std::vector<double> t;
    std::vector<Eigen::Vector2d> displacement;
    for (int k = 0; k <= 24; ++k) {
      t.push_back(0.05 * k);
      const double s = 0.5 * a * t.back() * t.back();
      displacement.emplace_back(side * s * std::cos(M_PI / 6), -s * std::sin(M_PI / 6));
    }
    displacement[10] *= 1.02;  // t = 0.5 s: 2% long
    const BoxInclineCheck check = box_incline_check(t, displacement, angle, Eigen::Vector2d(0, -g), mu, 0.0);
    EXPECT_NEAR(check.acceleration, 2.402, 1e-3);
    ASSERT_EQ(check.check_times.size(), 4u);
    EXPECT_NEAR(*check.relative_error[0], 0, 1e-12);
    EXPECT_NEAR(*check.relative_error[1], 0.02, 1e-12);
    EXPECT_NEAR(check.mpm_at_check[3], 1.201, 1e-3);
  }
}

// The same slide on a level slab with gravity tilted by the incline (box_incline_level.toml):
// down the slope is along x, the way gravity's x component points, and a slide across it (along
// y) is not counted.
TEST(BoxIncline, LevelSlabUnderTiltedGravity) {
  const double mu = 0.3, a = 10 * (0.5 - mu * std::sqrt(3.0) / 2);
  for (double side : {1.0, -1.0}) {
    const Eigen::Vector2d gravity(side * 5.0, -10 * std::sqrt(3.0) / 2);
    std::vector<double> t;
    std::vector<Eigen::Vector2d> displacement;
    for (int k = 0; k <= 20; ++k) {
      t.push_back(0.05 * k);
      displacement.emplace_back(side * 0.5 * a * t.back() * t.back(), 1e-4 * k);
    }
    const BoxInclineCheck check = box_incline_check(t, displacement, 30, gravity, mu, 0.0);
    EXPECT_NEAR(check.acceleration, a, 1e-12);
    ASSERT_EQ(check.relative_error.size(), 4u);
    for (const auto& e : check.relative_error) EXPECT_NEAR(*e, 0, 1e-12);
    EXPECT_NEAR(check.along_slope.back(), 0.5 * a, 1e-12);
  }
}

// With run.gravity_ramp = T the acceleration rises as (1 - cos(pi t / T)) / 2: the exact slide is
// the closed form of ramped_slide, checked here against the acceleration integrated twice by
// small steps (midpoint rule, 1e-5 s), before, at and after the ramp's end. A box that slid
// a t^2 / 2 from the start would be judged against it as too far.
TEST(BoxIncline, ExactSlideFollowsTheGravityRamp) {
  const double a = 10 * (0.5 - 0.3 * std::sqrt(3.0) / 2), ramp = 0.4, dt = 1e-5;  // mu = 0.3
  double v = 0, x = 0, t = 0;
  std::vector<double> times;
  std::vector<Eigen::Vector2d> displacement;
  const double c = std::cos(M_PI / 6), s = std::sin(M_PI / 6);
  for (int k = 0; k <= 100000; ++k) {
    if (k % 2500 == 0) {
      EXPECT_NEAR(ramped_slide(a, ramp, t), x, 1e-9) << "t = " << t;
      times.push_back(t);
      displacement.emplace_back(x * c, -x * s);
    }
    const double mid = t + 0.5 * dt;
    const double factor = mid < ramp ? 0.5 * (1 - std::cos(M_PI * mid / ramp)) : 1.0;
    x += dt * (v + 0.5 * dt * a * factor);
    v += dt * a * factor;
    t = (k + 1) * dt;
  }
  EXPECT_NEAR(ramped_slide(a, 0.0, 0.7), 0.5 * a * 0.49, 1e-15);
  // At t = 1 s the ramp costs a (T / 2 - T^2 / 4 + T^2 / pi^2) = 0.176 a of the unramped 0.5 a.
  EXPECT_NEAR(ramped_slide(a, ramp, 1.0), a * (0.5 - 0.2 + 0.04 - 0.16 / (M_PI * M_PI)), 1e-12);

  const double mu = 0.3;
  const BoxInclineCheck ramped = box_incline_check(times, displacement, 30, Eigen::Vector2d(0, -10), mu, ramp);
  ASSERT_EQ(ramped.relative_error.size(), 4u);
  for (const auto& e : ramped.relative_error) EXPECT_LT(*e, 1e-6);
  const BoxInclineCheck unramped = box_incline_check(times, displacement, 30, Eigen::Vector2d(0, -10), mu, 0.0);
  EXPECT_NEAR(*unramped.relative_error.back(), 0.176 / 0.5, 2e-3);  // judged 35 % short
}

TEST(BoxIncline, StaysPutWhenFrictionHolds) {
  const std::vector<double> t = {0, 0.5, 1.0};
  const std::vector<Eigen::Vector2d> displacement(3, Eigen::Vector2d(1e-5, 0));
  const BoxInclineCheck check = box_incline_check(t, displacement, 30, Eigen::Vector2d(0, -10), 0.6, 0.0);
  EXPECT_EQ(check.acceleration, 0);
  EXPECT_FALSE(check.relative_error[0]);
  EXPECT_NEAR(check.max_abs_displacement, 1e-5, 1e-15);
  EXPECT_EQ(check.check_times.size(), 4u);  // 0.25 and 0.75 s interpolated
}

TEST(Interpolate, InsideAndOutside) {
  EXPECT_NEAR(*interpolate({0, 1, 2}, {0, 10, 30}, 1.5), 20, 1e-12);
  EXPECT_FALSE(interpolate({0, 1}, {0, 1}, 1.5));
}

}  // namespace
}  // namespace talus::postproc
