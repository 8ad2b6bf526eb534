// The pieces `talus post` and `talus fos` share (postproc/analysed_slope.hpp and
// extract_slip_surface): the analysed body and its errors, the slope of a body that descends to
// the left (mirrored into the canonical frame and back), Bishop's critical circle in the scene's
// frame, and the slip surface of a displacement measured from a state other than the initial one.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.hpp"
#include "postproc/analysed_slope.hpp"
#include "postproc/failure_surface.hpp"
#include "postproc/runout.hpp"

namespace talus::postproc {
namespace {

const Polyline kOutline = {{0, 0}, {60, 0}, {60, 5}, {30, 5}, {20, 15}, {0, 15}};
const Circle kSlip{{26, 21}, std::sqrt(16.0 + 256.0)};  // through the toe (30, 5)
constexpr double kSpacing = 0.25;

Polyline mirrored(const Polyline& line) {
  Polyline out;
  for (const auto& p : line) out.emplace_back(-p.x(), p.y());
  return out;
}

Model two_bodies() {
  Model model;
  BodyInfo ground, slope;
  ground.name = "ground";
  ground.loops = {{{0, -5}, {60, -5}, {60, 0}, {0, 0}}};
  slope.name = "slope";
  slope.loops = {mirrored(kOutline)};
  model.bodies = {ground, slope};
  model.post.body = "slope";
  return model;
}

TEST(AnalysedSlope, TheBodyNamedByPostBodyAndItsParticles) {
  Model model = two_bodies();
  const std::vector<int32_t> body_of = {0, 1, 1, 0, 1};
  const AnalysedBody body = analysed_body(model, body_of, {"results.h5"});
  EXPECT_EQ(body.index, 1);
  EXPECT_EQ(body.particles, (std::vector<std::size_t>{1, 2, 4}));

  model.post.body = "";  // default: the first body
  EXPECT_EQ(analysed_body(model, body_of, {"results.h5"}).index, 0);
}

TEST(AnalysedSlope, ErrorsNameTheFileAndTheItemAsTheSourceSpellsThem) {
  Model model = two_bodies();
  model.post.body = "dam";
  try {
    analysed_body(model, {0, 1}, {"results.h5"});
    FAIL() << "no body named dam";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("results.h5: settings/post@body: no body named 'dam'"), std::string::npos)
        << e.what();
  }
  try {
    analysed_body(model, {0, 1}, {"slope.toml", true});
    FAIL() << "no body named dam";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("slope.toml: post.body: no body named 'dam'"), std::string::npos) << e.what();
  }
  model.post.body = "slope";
  EXPECT_THROW(analysed_body(model, {0, 0}, {"results.h5"}), Error);  // the slope has no particles

  BodyInfo flat = model.bodies[0];
  try {
    analysed_slope(flat, {"slope.toml", true, "fos needs"});
    FAIL() << "a flat ground surface";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("slope.toml: bodies.ground: fos needs a slope, but the ground surface is flat"),
              std::string::npos)
        << e.what();
  }
}

TEST(AnalysedSlope, ASlopeDescendingToTheLeftIsMirroredIntoTheCanonicalFrame) {
  const Model model = two_bodies();
  const AnalysedSlope slope = analysed_slope(model.bodies[1], {"results.h5"});
  EXPECT_TRUE(slope.mirror.active);
  EXPECT_NEAR(slope.profile.height, 10, 1e-12);
  EXPECT_NEAR(slope.profile.crest.x(), 20, 1e-12);  // canonical frame
  EXPECT_NEAR(slope.profile.toe.x(), 30, 1e-12);
  const auto x = canonical_positions({{-1, 2}, {-3, 4}, {-5, 6}}, {2, 0}, slope.mirror);
  ASSERT_EQ(x.size(), 2u);
  EXPECT_EQ(x[0], Eigen::Vector2d(5, 6));
  EXPECT_EQ(x[1], Eigen::Vector2d(1, 2));

  // Bishop's critical circle comes back in the scene's frame, the entry uphill of the exit.
  const SoilStrength soil{1e4, 20, 2e4};
  const auto left = critical_circle(slope, soil);
  BodyInfo right_body = model.bodies[1];
  right_body.loops = {kOutline};
  const auto right = critical_circle(analysed_slope(right_body, {"results.h5"}), soil);
  ASSERT_TRUE(left && right);
  EXPECT_NEAR(left->factor_of_safety, right->factor_of_safety, 1e-12);
  EXPECT_NEAR(left->circle.centre.x(), -right->circle.centre.x(), 1e-9);
  EXPECT_NEAR(left->circle.radius, right->circle.radius, 1e-9);
  EXPECT_NEAR(left->x_entry, -right->x_entry, 1e-9);
  EXPECT_NEAR(left->x_exit, -right->x_exit, 1e-9);
  EXPECT_GT(left->x_entry, left->x_exit);  // descending to the left: uphill is to the right
}

// A slope descending to the left whose particles first settle by 0.1 m (the "equilibrium"),
// after which those inside kSlip (mirrored) move by (-2, -1): the slip surface of the second
// displacement alone, drawn at the initial positions, in the scene's frame.
TEST(AnalysedSlope, SlipSurfaceOfADisplacementFromAStateOtherThanTheInitialOne) {
  const Mirror mirror{true};
  const SlopeProfile profile = slope_profile(kOutline);
  std::vector<Eigen::Vector2d> x0, from, to;  // canonical frame
  for (double x = kSpacing / 2; x < 60; x += kSpacing)
    for (double y = kSpacing / 2; y < 15; y += kSpacing)
      if (y < surface_height(profile.surface, x)) {
        const Eigen::Vector2d p(x, y), settled(x, y - 0.1);
        x0.push_back(p);
        from.push_back(settled);
        to.push_back((p - kSlip.centre).norm() < kSlip.radius ? Eigen::Vector2d(settled + Eigen::Vector2d(2, -1))
                                                               : settled);
      }
  const std::vector<double> volume(x0.size(), kSpacing * kSpacing);
  const double width = column_rule_for(volume).width;

  // Measured from the initial positions, the settlement of 0.1 m would make the whole body
  // (550 m^2) slide.
  EXPECT_NEAR(extract_slip_surface(x0, x0, to, volume, 0.05, width, mirror).failed_area, 550, 5);

  const SlipSurface slip = extract_slip_surface(x0, from, to, volume, 0.5, width, mirror);
  EXPECT_NEAR(slip.failed_area, 108.2, 0.02 * 108.2);  // the body inside kSlip
  ASSERT_GT(slip.surface.size(), 20u);
  EXPECT_LT(slip.surface.front().x(), slip.surface.back().x());  // x increasing in the scene's frame
  EXPECT_NEAR(slip.surface.front().x(), -30, 0.5);               // the toe, mirrored
  EXPECT_NEAR(slip.surface.back().x(), -10.64, 0.5);             // the crown, mirrored
  ASSERT_TRUE(slip.circle);
  EXPECT_NEAR(slip.circle->centre.x(), -kSlip.centre.x(), 0.3);
  EXPECT_NEAR(slip.circle->centre.y(), kSlip.centre.y(), 0.3);
  EXPECT_NEAR(slip.circle->radius, kSlip.radius, 0.3);
  EXPECT_LT(slip.circle_rms, 0.2);
}

}  // namespace
}  // namespace talus::postproc
