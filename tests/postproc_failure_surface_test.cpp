// Circle fit on noisy points, and the failure surface of a synthetic slide: the particles of a
// slope inside a known circle are moved, the rest stay; the extracted slip surface, its circle,
// the failed area and a synthetic shear band must recover that circle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "postproc/circle_fit.hpp"
#include "postproc/failure_surface.hpp"

namespace talus::postproc {
namespace {

TEST(CircleFit, RecoversAKnownCircleFromNoisyPointsOnAnArc) {
  const Circle truth{{3, -2}, 7};
  std::mt19937 random(42);
  std::normal_distribution<double> noise(0, 0.02);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 60; ++i) {
    const double angle = (-120 + 1.5 * i) * M_PI / 180;  // a 90-degree arc, as a slip surface
    points.push_back(truth.centre + truth.radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)) +
                     Eigen::Vector2d(noise(random), noise(random)));
  }
  const auto fit = fit_circle(points);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->centre.x(), 3, 0.05);
  EXPECT_NEAR(fit->centre.y(), -2, 0.05);
  EXPECT_NEAR(fit->radius, 7, 0.05);
  EXPECT_LT(circle_rms_distance(*fit, points), 0.03);
}

TEST(CircleFit, NoCircleThroughCollinearPoints) {
  EXPECT_FALSE(fit_circle({{0, 0}, {1, 1}, {2, 2}, {3, 3}}));
  EXPECT_FALSE(fit_circle({{0, 0}, {1, 1}}));
}

constexpr double kSpacing = 0.2;
const Polyline kOutline = {{0, 0}, {60, 0}, {60, 5}, {30, 5}, {20, 15}, {0, 15}};
// Through the toe (30, 5), entering the crest plateau at x = 26 - sqrt(R^2 - 36) = 10.64.
const Circle kSlip{{26, 21}, std::sqrt(16.0 + 256.0)};

struct Slide {
  std::vector<Eigen::Vector2d> initial, final;
};

Slide synthetic_slide() {
  const SlopeProfile profile = slope_profile(kOutline);
  Slide slide;
  for (double x = kSpacing / 2; x < 60; x += kSpacing)
    for (double y = kSpacing / 2; y < 15; y += kSpacing)
      if (y < surface_height(profile.surface, x)) {
        const Eigen::Vector2d p(x, y);
        slide.initial.push_back(p);
        const bool inside = (p - kSlip.centre).norm() < kSlip.radius;
        slide.final.push_back(inside ? Eigen::Vector2d(p + Eigen::Vector2d(2, -1)) : p);
      }
  return slide;
}

// Area of the body inside the circle, by columns of width 1e-3 m.
double slide_area() {
  const SlopeProfile profile = slope_profile(kOutline);
  double area = 0;
  const double dx = 1e-3;
  for (double x = dx / 2; x < 60; x += dx) {
    const double half = kSlip.radius * kSlip.radius - std::pow(x - kSlip.centre.x(), 2);
    if (half <= 0) continue;
    const double lo = std::max(0.0, kSlip.centre.y() - std::sqrt(half));
    const double hi = std::min(surface_height(profile.surface, x), kSlip.centre.y() + std::sqrt(half));
    area += std::max(hi - lo, 0.0) * dx;
  }
  return area;
}

double worst_distance(const Polyline& line, const Circle& circle) {
  double worst = 0;
  for (const auto& p : line) worst = std::max(worst, std::abs((p - circle.centre).norm() - circle.radius));
  return worst;
}

TEST(FailureSurface, SlipSurfaceOfASyntheticSlide) {
  Slide slide = synthetic_slide();
  std::vector<char> sliding = sliding_mask(slide.initial, slide.final, 0.5);

  const std::vector<double> volume(slide.initial.size(), kSpacing * kSpacing);
  EXPECT_NEAR(failed_area(sliding, volume), slide_area(), 0.01 * slide_area());

  // Stray misclassified particles, deep in the stable ground and inside the slide, must not
  // move the boundary.
  std::mt19937 random(7);
  std::uniform_int_distribution<std::size_t> pick(0, slide.initial.size() - 1);
  for (int flipped = 0; flipped < 20;) {
    const std::size_t p = pick(random);
    const double depth = std::abs((slide.initial[p] - kSlip.centre).norm() - kSlip.radius);
    if (depth > 1.0) sliding[p] = !sliding[p], ++flipped;
  }

  const Polyline surface = slip_surface(slide.initial, sliding, 2 * kSpacing);
  ASSERT_GT(surface.size(), 40u);
  EXPECT_NEAR(surface.front().x(), 10.64, 0.5);  // from the crest plateau...
  EXPECT_NEAR(surface.back().x(), 30, 0.5);      // ...to the toe
  EXPECT_LT(worst_distance(surface, kSlip), 0.75 * kSpacing);

  const auto fit = fit_circle(surface);
  ASSERT_TRUE(fit);
  EXPECT_NEAR(fit->centre.x(), kSlip.centre.x(), 0.3);
  EXPECT_NEAR(fit->centre.y(), kSlip.centre.y(), 0.3);
  EXPECT_NEAR(fit->radius, kSlip.radius, 0.3);
}

TEST(FailureSurface, OnsetFrameAndShearBand) {
  const Slide slide = synthetic_slide();
  std::vector<std::vector<Eigen::Vector2d>> frames;
  for (double fraction : {0.0, 0.1, 0.3, 1.0}) {
    std::vector<Eigen::Vector2d> frame;
    for (std::size_t p = 0; p < slide.initial.size(); ++p)
      frame.push_back(slide.initial[p] + fraction * (slide.final[p] - slide.initial[p]));
    frames.push_back(frame);
  }
  // Displacement sqrt(5) x fraction: 0.22 at the second frame, 0.67 at the third.
  EXPECT_EQ(onset_frame(frames, slide.initial, 0.5), 2u);
  EXPECT_FALSE(onset_frame(frames, slide.initial, 5.0));

  // Plastic strain concentrated in a band of half-width ~0.3 m along the slip circle.
  std::vector<double> strain;
  for (const auto& p : slide.initial) {
    const double d = (p - kSlip.centre).norm() - kSlip.radius;
    strain.push_back(0.2 * std::exp(-d * d / (2 * 0.3 * 0.3)));
  }
  const Polyline band = shear_band(slide.initial, strain, 2 * kSpacing);
  ASSERT_GT(band.size(), 40u);
  // Where the ground surface cuts the band (at the crown and the toe) the centroid shifts, by
  // at most the band's half-width at half maximum, 1.18 x 0.3 m; elsewhere it is on the circle.
  EXPECT_LT(worst_distance(band, kSlip), 0.36);
  std::vector<double> distances;
  for (const auto& p : band) distances.push_back(std::abs((p - kSlip.centre).norm() - kSlip.radius));
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  EXPECT_LT(distances[distances.size() / 2], 0.05);
  EXPECT_TRUE(shear_band(slide.initial, std::vector<double>(slide.initial.size(), 0.0), 0.4).empty());
}

}  // namespace
}  // namespace talus::postproc
