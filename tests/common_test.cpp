// The shared facilities of common/: plane geometry and fingerprints.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "common/fingerprint.hpp"
#include "common/geometry.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

TEST(Geometry, SignedAreaIsPositiveCounterClockwise) {
  std::vector<Eigen::Vector2d> square{{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  EXPECT_DOUBLE_EQ(signed_area(square), 2.0);
  std::reverse(square.begin(), square.end());
  EXPECT_DOUBLE_EQ(signed_area(square), -2.0);
  EXPECT_EQ(signed_area({}), 0.0);
}

TEST(Fingerprint, IsFnv1aFromTalusOwnStart) {
  // Reference values of 64-bit FNV-1a, from FNV's offset basis.
  constexpr uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ull;
  EXPECT_EQ(Fingerprint(kFnvOffsetBasis).add("a").value(), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(Fingerprint(kFnvOffsetBasis).add("foobar").value(), 0x85944171f73967e8ull);
  // The default start, which checkpoints and stamps have always used (see fingerprint.hpp).
  EXPECT_EQ(Fingerprint().value(), 1469598103934665603ull);
}

TEST(Fingerprint, ChainsAndAgreesAcrossOverloads) {
  EXPECT_EQ(Fingerprint(Fingerprint().add("foo").value()).add("bar").value(), Fingerprint().add("foobar").value());
  const std::vector<Eigen::Vector2d> points{{1, 2}, {3, 4}};
  const std::vector<double> flat{1, 2, 3, 4};
  EXPECT_EQ(Fingerprint().add(points).value(), Fingerprint().add(flat).value());
  EXPECT_EQ(Fingerprint().add(int32_t{7}).value(), Fingerprint().add(int64_t{7}).value());
  EXPECT_NE(Fingerprint().add(7).value(), Fingerprint().add(7.0).value());
  EXPECT_NE(Fingerprint().add(std::vector<std::string>{"ab", "c"}).value(),
            Fingerprint().add(std::vector<std::string>{"a", "bc"}).value());
}

TEST(Fingerprint, HashesAFilesBytes) {
  ScratchDir dir("fingerprint");
  const std::string path = dir.file("bytes");
  std::ofstream(path, std::ios::binary) << "foobar";
  Fingerprint f;
  EXPECT_TRUE(f.add_file(path));
  EXPECT_EQ(f.value(), Fingerprint().add("foobar").value());
  Fingerprint missing;
  EXPECT_FALSE(missing.add_file(dir.file("nowhere")));
  EXPECT_EQ(missing.value(), Fingerprint().value());
}

}  // namespace
}  // namespace talus
