// The critical-circle search (postproc/bishop_search.cpp) against brute force: every circle
// through an entry point and an exit point on fine grids along the ground, at radii from a
// half-circle to nearly the chord, each judged by bishop_factor_of_safety for a bare circle
// (which finds the cut and checks admissibility itself, without the search's construction).
// The search must come out at or below the brute-force minimum + 0.2%, and its circle, judged
// the same way, must give the same factor, entry and exit.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "postproc/bishop.hpp"

namespace talus::postproc {
namespace {

constexpr int kScan = 72;  // entries x exits x radii

struct Scan {
  double factor_of_safety = INFINITY;
  long circles = 0;
};

// The point at `length` along the ground from its first point.
Eigen::Vector2d along(const Polyline& surface, double length) {
  for (std::size_t i = 0; i + 1 < surface.size(); ++i) {
    const double piece = (surface[i + 1] - surface[i]).norm();
    if (length <= piece) return surface[i] + std::max(length, 0.0) / piece * (surface[i + 1] - surface[i]);
    length -= piece;
  }
  return surface.back();
}

double length_to(const Polyline& surface, const Eigen::Vector2d& vertex) {
  double length = 0;
  for (std::size_t i = 0; i + 1 < surface.size() && surface[i] != vertex; ++i) length += (surface[i + 1] - surface[i]).norm();
  return length;
}

// Entries at kScan points evenly along the ground from its start to the toe; exits at kScan
// points evenly along it from the crest to its end, and at the toe; for each pair with the exit
// downhill, the circles through both whose arc below the chord subtends 2 theta,
// theta = (pi/2) k / kScan, k = 1..kScan, i.e. radii |ab| / (2 sin theta) from |ab| / 2 up.
Scan brute_force(const SlopeProfile& profile, const SoilStrength& soil) {
  const Polyline& surface = profile.surface;
  const double crest = length_to(surface, profile.crest), toe = length_to(surface, profile.toe);
  const double end = length_to(surface, surface.back());
  std::vector<Eigen::Vector2d> exits{profile.toe};
  for (int j = 0; j < kScan; ++j) exits.push_back(along(surface, crest + (end - crest) * j / (kScan - 1)));
  Scan scan;
  for (int i = 0; i < kScan; ++i) {
    const Eigen::Vector2d a = along(surface, toe * i / (kScan - 1));
    for (const Eigen::Vector2d& b : exits) {
      if (!(b.x() > a.x())) continue;
      const Eigen::Vector2d chord = b - a;
      const Eigen::Vector2d up = Eigen::Vector2d(-chord.y(), chord.x()).normalized();
      for (int k = 1; k <= kScan; ++k) {
        const double radius = 0.5 * chord.norm() / std::sin(0.5 * M_PI * k / kScan);
        const double rise = std::sqrt(std::max(radius * radius - 0.25 * chord.squaredNorm(), 0.0));
        ++scan.circles;
        if (const auto r = bishop_factor_of_safety(profile, soil, {0.5 * (a + b) + rise * up, radius}))
          scan.factor_of_safety = std::min(scan.factor_of_safety, r->factor_of_safety);
      }
    }
  }
  return scan;
}

BishopResult search_against_brute_force(const char* name, const SlopeProfile& profile, const SoilStrength& soil) {
  const auto start = std::chrono::steady_clock::now();
  const auto found = bishop_search(profile, soil);
  const double search_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Scan scan = brute_force(profile, soil);
  const double scan_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - search_seconds;
  EXPECT_TRUE(found);
  if (!found) return {};
  std::printf("%s: search F = %.5f (%s circle%s, %ld circles, %.2f s), brute force F = %.5f (%ld circles, %.2f s), "
              "%+.3f%%\n",
              name, found->factor_of_safety, to_string(found->kind), found->tangent_to_base ? ", tangent to the base" : "",
              found->circles_evaluated, search_seconds, scan.factor_of_safety, scan.circles, scan_seconds,
              100 * (found->factor_of_safety / scan.factor_of_safety - 1));
  EXPECT_LE(found->factor_of_safety, 1.002 * scan.factor_of_safety) << name;

  // The search's circle is one the method admits on its own, with the same cut.
  const auto again = bishop_factor_of_safety(profile, soil, found->circle);
  EXPECT_TRUE(again) << name;
  if (again) {
    EXPECT_NEAR(again->factor_of_safety, found->factor_of_safety, 1e-6 * found->factor_of_safety) << name;
    EXPECT_NEAR(again->x_entry, found->x_entry, 1e-6 * profile.height) << name;
    EXPECT_NEAR(again->x_exit, found->x_exit, 1e-6 * profile.height) << name;
  }
  return *found;
}

// geometries/slope.geo and slope.toml: 5 m at 50 deg on the rigid base, c = 1 kPa, phi = 30 deg.
TEST(BishopSearch, DefaultSlope) {
  const double toe = 6 + 5 / std::tan(50 * M_PI / 180);
  const auto found = search_against_brute_force("default slope", slope_profile({{0, 0}, {toe, 0}, {6, 5}, {0, 5}}),
                                                {1000, 30, 1800 * 9.81});
  EXPECT_LE(found.factor_of_safety, 0.713);
  EXPECT_EQ(found.kind, CircleKind::Toe);
}

// geometries/griffiths_lane.geo and .toml: 10 m at 2:1, no foundation layer, c = 10 kPa,
// phi = 20 deg, gamma = 20 kN/m^3; the charts of Bishop and Morgenstern (1960) give 1.380. The
// critical circle touches the base and leaves the face just above the toe.
TEST(BishopSearch, GriffithsLaneExample1) {
  const auto found = search_against_brute_force("Griffiths and Lane", slope_profile({{0, 0}, {32, 0}, {12, 10}, {0, 10}}),
                                                {10e3, 20, 20e3});
  EXPECT_NEAR(found.factor_of_safety, 1.380, 0.005 * 1.380);
  EXPECT_TRUE(found.tangent_to_base);
}

// A steep cohesive cliff: 10 m, vertical but for 1 mm (the surface must be a function of x),
// phi = 0, c = 50 kPa, gamma = 20 kN/m^3, on the rigid base at the toe's level. Taylor's (1937)
// stability number for a vertical face and phi = 0, c / (gamma H F) = 0.261, gives
// F = 3.83 c / (gamma H) = 0.958, on a circle through the toe.
TEST(BishopSearch, SteepCohesiveCliff) {
  const auto found = search_against_brute_force("vertical cliff", slope_profile({{0, 0}, {20.001, 0}, {20, 10}, {0, 10}}),
                                                {50e3, 0, 20e3});
  EXPECT_NEAR(found.factor_of_safety, 3.83 * 50e3 / (20e3 * 10), 0.005);
  EXPECT_EQ(found.kind, CircleKind::Toe);
}

// A foundation layer: a 1:3 slope 5 m high in clay (phi = 0, c = 20 kPa, gamma = 20 kN/m^3)
// over 5 m more of it on a rigid base, with 30 m of ground beyond the toe. A deep circle
// tangent to the base and leaving the ground beyond the toe is critical.
TEST(BishopSearch, BaseCircleThroughAFoundationLayer) {
  const auto found = search_against_brute_force(
      "1:3 slope on a foundation", slope_profile({{0, 0}, {60, 0}, {60, 5}, {30, 5}, {15, 10}, {0, 10}}),
      {20e3, 0, 20e3});
  EXPECT_EQ(found.kind, CircleKind::Base);
  EXPECT_TRUE(found.tangent_to_base);
  EXPECT_GT(found.x_exit, 31);
}

// The cliff at 80 deg on a foundation layer: circles that leave the face just above the toe
// must not dip into the ground beyond it; the critical one grazes it.
TEST(BishopSearch, SteepCliffOnAFoundationLayer) {
  const double toe = 20 + 10 / std::tan(80 * M_PI / 180);
  const auto found = search_against_brute_force(
      "80 deg cliff on a foundation", slope_profile({{0, 0}, {40, 0}, {40, 5}, {toe, 5}, {20, 15}, {0, 15}}),
      {50e3, 0, 20e3});
  EXPECT_GE(found.circle.centre.y() - found.circle.radius, 5 - 1e-6);  // not below the ground beyond the toe
}

}  // namespace
}  // namespace talus::postproc
