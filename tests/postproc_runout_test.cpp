// Runout, crest retreat, travel angle and time to rest on synthetic particle sets whose answers
// are known by construction, including stray particles the tip rule must ignore.
#include <gtest/gtest.h>

#include <cmath>

#include "postproc/runout.hpp"

namespace talus::postproc {
namespace {

constexpr double kSpacing = 0.25;  // particle spacing (m); particles at cell centres (i + 1/2) s

// A slope 10 m high: crest plateau at y = 15 up to x = 20, a 1:1 face to the toe at (30, 5),
// low ground at y = 5 to x = 60, base at y = 0.
const Polyline kOutline = {{0, 0}, {60, 0}, {60, 5}, {30, 5}, {20, 15}, {0, 15}};

std::vector<Eigen::Vector2d> grid_inside(double x_lo, double x_hi, double y_lo, double y_hi,
                                         const Polyline& surface) {
  std::vector<Eigen::Vector2d> points;
  for (double x = x_lo + kSpacing / 2; x < x_hi; x += kSpacing)
    for (double y = y_lo + kSpacing / 2; y < y_hi; y += kSpacing)
      if (y < surface_height(surface, x)) points.emplace_back(x, y);
  return points;
}

struct Scenario {
  SlopeProfile profile = slope_profile(kOutline);
  ColumnRule rule = column_rule_for(std::vector<double>(10, kSpacing * kSpacing));
  std::vector<Eigen::Vector2d> initial, final;
};

// The slope fails back to x = 16 (4 m behind the crest) down to the low ground; a deposit 2 m
// thick covers 30 < x < 42 on the low ground. Stray particles lie beyond it.
Scenario failed_slope(bool with_strays) {
  Scenario s;
  s.initial = grid_inside(0, 60, 0, 15, s.profile.surface);
  for (const auto& p : s.initial)
    if (p.x() < 16 || p.y() < 5) s.final.push_back(p);
  for (const auto& p : grid_inside(30, 42, 5, 7, {{0, 100}, {100, 100}})) s.final.push_back(p);
  if (with_strays) {
    s.final.emplace_back(45.01, 5.1);  // a pair after a gap: too few for a column
    s.final.emplace_back(45.11, 5.1);
    for (int k = 0; k < 5; ++k) s.final.emplace_back(50.1, 5.1 + 0.2 * k);  // a clump beyond a gap
    s.final.emplace_back(48.0, 9.0);   // one thrown high
  }
  return s;
}

TEST(Runout, ProfileOfTheOutline) {
  const SlopeProfile profile = slope_profile(kOutline);
  EXPECT_EQ(profile.crest, Eigen::Vector2d(20, 15));
  EXPECT_EQ(profile.toe, Eigen::Vector2d(30, 5));
  EXPECT_DOUBLE_EQ(profile.height, 10);
  EXPECT_DOUBLE_EQ(profile.base_y, 0);
  EXPECT_DOUBLE_EQ(surface_height(profile.surface, 25), 10);
  EXPECT_FALSE(descends_to_left(kOutline));
  Polyline mirrored;
  for (const auto& p : kOutline) mirrored.emplace_back(-p.x(), p.y());
  EXPECT_TRUE(descends_to_left(mirrored));
}

TEST(Runout, KnownDepositCrestRetreatAndTravelAngle) {
  for (bool strays : {false, true}) {
    SCOPED_TRACE(strays ? "with strays" : "clean");
    const Scenario s = failed_slope(strays);
    EXPECT_DOUBLE_EQ(s.rule.width, 2 * kSpacing);
    const RunoutMetrics m = runout_metrics(s.profile, s.initial, s.final, 0.05 * s.profile.height, s.rule);
    ASSERT_TRUE(m.deposit_found);
    const double tip_x = 42 - kSpacing / 2, tip_y = 5 + kSpacing / 2;
    EXPECT_NEAR(m.tip.x(), tip_x, 1e-9);
    EXPECT_NEAR(m.tip.y(), tip_y, 1e-9);
    EXPECT_NEAR(m.runout_distance, tip_x - 30, 1e-9);
    EXPECT_NEAR(m.crest_retreat, 4, 1e-9);
    EXPECT_NEAR(m.crown.x(), 16, 1e-9);
    EXPECT_NEAR(m.crown.y(), 15, 1e-9);
    ASSERT_TRUE(m.travel_angle_deg);
    EXPECT_NEAR(*m.travel_angle_deg, std::atan2(15 - tip_y, tip_x - 16) * 180 / M_PI, 1e-9);
  }
}

TEST(Runout, NothingMovedMeansNoRunout) {
  const Scenario s = failed_slope(false);
  const RunoutMetrics m = runout_metrics(s.profile, s.initial, s.initial, 0.5, s.rule);
  EXPECT_FALSE(m.deposit_found);
  EXPECT_EQ(m.runout_distance, 0);
  EXPECT_EQ(m.crest_retreat, 0);
  EXPECT_FALSE(m.travel_angle_deg);
}

TEST(Runout, FrontVelocityIsTheMeanOfTheTipColumn) {
  const Scenario s = failed_slope(true);
  std::vector<Eigen::Vector2d> velocity(s.final.size(), Eigen::Vector2d(0, 0));
  for (std::size_t p = 0; p < s.final.size(); ++p)
    if (s.final[p].x() > 41.5 && s.final[p].x() < 42) velocity[p] = {3.0, -1.0};
  const DepositFront front = deposit_front(s.final, velocity, s.profile.surface, s.rule);
  ASSERT_TRUE(front.found);
  EXPECT_NEAR(front.velocity, 3.0, 1e-12);
}

TEST(Runout, TimeToRest) {
  // Kinetic energy rising to a peak at t = 1 s, then decaying as exp(-(t - 1) / 0.2): below 1%
  // of the peak from t = 1 + 0.2 ln 100 = 1.921 s on; sampled every 0.01 s.
  std::vector<double> t, kinetic;
  for (int i = 0; i <= 400; ++i) {
    t.push_back(0.01 * i);
    kinetic.push_back(t.back() < 1 ? t.back() : std::exp(-(t.back() - 1) / 0.2));
  }
  ASSERT_TRUE(time_to_rest(t, kinetic));
  EXPECT_NEAR(*time_to_rest(t, kinetic), 1.93, 1e-9);

  // A late jolt above 1% moves the time of rest after it.
  kinetic[300] = 0.05;
  EXPECT_NEAR(*time_to_rest(t, kinetic), 3.01, 1e-9);

  // Still moving at the end: no time of rest.
  kinetic.back() = 0.5;
  EXPECT_FALSE(time_to_rest(t, kinetic));

  EXPECT_EQ(*time_to_rest(t, std::vector<double>(t.size(), 0.0)), 0.0);
}

}  // namespace
}  // namespace talus::postproc
