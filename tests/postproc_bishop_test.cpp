// Bishop's simplified method against published slopes, and its circle search against a finer
// brute-force grid.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "postproc/bishop.hpp"

namespace talus::postproc {
namespace {

// Fredlund and Krahn (1977), "Comparison of slope stability methods of analysis", Can. Geotech.
// J. 14(3):429-439, example case 1: a 2H:1V slope 40 ft high on a base 20 ft below the toe,
// c' = 600 psf, phi' = 20 deg, gamma = 120 pcf, dry, the slip circle of centre (120, 90) ft and
// radius 80 ft (crest at (60, 60), toe at (140, 20)). Published simplified-Bishop factor of
// safety 2.080 (the paper's table, as listed by the MacSlope verification of this case).
TEST(Bishop, FredlundKrahnCaseOneCircle) {
  const SlopeProfile profile = slope_profile({{0, 0}, {170, 0}, {170, 20}, {140, 20}, {60, 60}, {0, 60}});
  ASSERT_DOUBLE_EQ(profile.height, 40);
  const SoilStrength soil{600, 20, 120};
  const auto result = bishop_factor_of_safety(profile, soil, {{120, 90}, 80});
  ASSERT_TRUE(result);
  EXPECT_NEAR(result->x_entry, 120 - std::sqrt(80.0 * 80 - 30 * 30), 1e-6);
  EXPECT_NEAR(result->x_exit, 120 + std::sqrt(80.0 * 80 - 70 * 70), 1e-6);
  EXPECT_NEAR(result->factor_of_safety, 2.080, 0.02 * 2.080);
  std::printf("Fredlund-Krahn case 1: F = %.4f (published 2.080)\n", result->factor_of_safety);
}

// The ACADS benchmark EX1(a) (Giam and Donald 1989, ACADS slope stability programs review):
// a simple dry slope 10 m high at 2H:1V, c' = 3 kPa, phi' = 19.6 deg, gamma = 20 kN/m^3;
// referee factor of safety 1.00 for the critical circle (the DeepEX verification page quotes
// the referee 1.00 and a mean simplified-Bishop result of 0.993 over 18 programs). Crest and toe
// plateaus of 20 m and a base 10 m below the toe leave the critical toe circle unconstrained.
SlopeProfile acads_simple_slope() {
  return slope_profile({{0, 0}, {60, 0}, {60, 10}, {40, 10}, {20, 20}, {0, 20}});
}

TEST(Bishop, AcadsSimpleSlopeCriticalCircle) {
  const SoilStrength soil{3e3, 19.6, 20e3};
  const auto critical = bishop_search(acads_simple_slope(), soil);
  ASSERT_TRUE(critical);
  EXPECT_NEAR(critical->factor_of_safety, 1.00, 0.02);
  std::printf("ACADS EX1(a): F = %.4f (referee 1.00), centre (%.2f, %.2f) m, R = %.2f m\n",
              critical->factor_of_safety, critical->circle.centre.x(), critical->circle.centre.y(),
              critical->circle.radius);
  // A toe circle: it leaves the ground within a metre of the toe, and enters behind the crest.
  EXPECT_NEAR(critical->x_exit, 40, 1.0);
  EXPECT_LT(critical->x_entry, 20);
}

TEST(Bishop, SearchIsNoWorseThanAFinerGrid) {
  const SoilStrength soil{3e3, 19.6, 20e3};
  const SlopeProfile profile = acads_simple_slope();
  const auto search = bishop_search(profile, soil);
  BishopSearchSettings fine;
  fine.centres_x = fine.centres_y = fine.radii = 64;
  fine.refine_from = 0;
  const auto grid = bishop_search(profile, soil, fine);
  ASSERT_TRUE(search && grid);
  EXPECT_LE(search->factor_of_safety, 1.01 * grid->factor_of_safety);
  std::printf("search F = %.4f, 64^3 grid F = %.4f\n", search->factor_of_safety, grid->factor_of_safety);
}

TEST(Bishop, RejectsCirclesThatLeaveTheBody) {
  const SlopeProfile profile = acads_simple_slope();
  const SoilStrength soil{3e3, 19.6, 20e3};
  EXPECT_FALSE(bishop_factor_of_safety(profile, soil, {{30, 30}, 40}));  // below the base
  EXPECT_FALSE(bishop_factor_of_safety(profile, soil, {{30, 30}, 5}));   // misses the ground
  EXPECT_FALSE(bishop_factor_of_safety(profile, soil, {{-5, 25}, 10}));  // out through the left side
}

// With phi = 0, Bishop's method is the Swedish circle method, exact for a circle:
// F = c R L_arc / sum(W x_arm). A circle centred on the crest edge of a vertical cut, of radius
// the cut's height, bounds a quarter disc: moment gamma R^3 / 3 about the centre, arc pi R / 2.
// The base turns vertical at the crest end, where the slices' b / cos(alpha) under-counts the
// arc; 2000 slices bring that within 1%.
TEST(Bishop, FrictionlessQuarterDiscMatchesClosedForm) {
  // A vertical cut of height 10 m; the circle centred on the crest edge at (20, 10) with radius
  // 10 runs from the crest surface at x = 10 to the cut's toe at (20, 0).
  const SlopeProfile profile = slope_profile({{0, -20}, {40, -20}, {40, 0}, {20.0001, 0}, {20, 10}, {0, 10}});
  const SoilStrength soil{10e3, 0, 20e3};
  const double r = 9.99;  // just inside, so that the circle exits on the cut face
  const auto result = bishop_factor_of_safety(profile, soil, {{20, 10}, r}, 2000);
  ASSERT_TRUE(result);
  const double expected = soil.cohesion * r * (M_PI * r / 2) / (soil.unit_weight * r * r * r / 3);
  EXPECT_NEAR(result->factor_of_safety, expected, 1e-2 * expected);
}

}  // namespace
}  // namespace talus::postproc
