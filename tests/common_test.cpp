// The shared facilities of common/: plane geometry.
#include <gtest/gtest.h>

#include <algorithm>

#include "common/geometry.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

TEST(Geometry, SignedAreaIsPositiveCounterClockwise) {
  std::vector<Eigen::Vector2d> square{{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  EXPECT_DOUBLE_EQ(signed_area(square), 2.0);
  std::reverse(square.begin(), square.end());
  EXPECT_DOUBLE_EQ(signed_area(square), -2.0);
  EXPECT_EQ(signed_area({}), 0.0);
}

}  // namespace
}  // namespace talus
