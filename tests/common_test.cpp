// The shared facilities of common/: plane geometry, fingerprints, atomic file replacement and
// the material check.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/fingerprint.hpp"
#include "common/geometry.hpp"
#include "common/h5.hpp"
#include "common/materials/materials.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::ScratchDir;

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string message_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Geometry, SignedAreaIsPositiveCounterClockwise) {
  std::vector<Eigen::Vector2d> square{{0, 0}, {2, 0}, {2, 1}, {0, 1}};
  EXPECT_DOUBLE_EQ(signed_area(square), 2.0);
  std::reverse(square.begin(), square.end());
  EXPECT_DOUBLE_EQ(signed_area(square), -2.0);
  EXPECT_EQ(signed_area({}), 0.0);
}

TEST(Geometry, InsideLoopsIsTheEvenOddRule) {
  auto square = [](double x0, double y0, double side) {
    return std::vector<Eigen::Vector2d>{{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
  };
  // A 4x4 square with a 2x2 hole holding a 1x1 island.
  const std::vector<std::vector<Eigen::Vector2d>> loops{square(0, 0, 4), square(1, 1, 2), square(1.5, 1.5, 1)};
  EXPECT_TRUE(inside_loops(loops, {0.5, 0.5}));
  EXPECT_FALSE(inside_loops(loops, {1.2, 1.2}));
  EXPECT_TRUE(inside_loops(loops, {2, 2}));
  EXPECT_FALSE(inside_loops(loops, {5, 2}));
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

TEST(AtomicFile, ReplacesTheFileWhole) {
  ScratchDir dir("atomic");
  const std::string path = dir.file("out.txt");
  write_text_atomically(path, "first\n");
  write_text_atomically(path, "second\n");
  EXPECT_EQ(contents(path), "second\n");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST(AtomicFile, AFailedFillLeavesTheOldFileAndNoTemporary) {
  ScratchDir dir("atomic-fail");
  const std::string path = dir.file("out.txt");
  write_text_atomically(path, "old\n");
  EXPECT_THROW(write_stream_atomically(path,
                                       [](std::ostream& out) {
                                         out << "half";
                                         throw std::runtime_error("stop");
                                       }),
               std::runtime_error);
  EXPECT_EQ(contents(path), "old\n");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST(AtomicFile, ErrorsNameTheFile) {
  ScratchDir dir("atomic-error");
  const std::string unopenable = dir.file("missing/out.txt");
  EXPECT_NE(message_of([&] { write_text_atomically(unopenable, "x"); }).find("missing/out.txt.tmp: cannot open"),
            std::string::npos);
  // A folder in the way: the rename fails, and the temporary file goes.
  const std::string folder = dir.file("taken");
  fs::create_directories(folder + "/inside");
  EXPECT_NE(message_of([&] { write_text_atomically(folder, "x"); }).find("taken: cannot replace"), std::string::npos);
  EXPECT_FALSE(fs::exists(folder + ".tmp"));
}

TEST(AtomicFile, Hdf5FilesGoThroughTheSamePath) {
  ScratchDir dir("atomic-h5");
  const std::string path = dir.file("data.h5");
  h5::write_atomically(path, [](const h5::File& file) { h5::write(file, "x", std::vector<double>{1, 2}, {2}); });
  EXPECT_THROW(h5::write_atomically(path,
                                    [](const h5::File& file) {
                                      h5::write(file, "x", std::vector<double>{3}, {1});
                                      throw Error("stop");
                                    }),
               Error);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
  EXPECT_EQ(h5::read_doubles(h5::File::open_read(path), "x"), (std::vector<double>{1, 2}));
}

Material sand() { return testing::mohr_coulomb(1800, 1e7, 0.3, 30, 1e3); }

TEST(Material, ValidMaterialsHaveNoProblem) {
  EXPECT_FALSE(material_problem(sand()));
  Material elastic = testing::elastic(2000, 1e7, 0.25);
  EXPECT_FALSE(material_problem(elastic));
  Material tresca = sand();
  parameters_of<MohrCoulomb>(tresca).friction_angle = 0;
  EXPECT_FALSE(material_problem(tresca));
}

TEST(Material, TheFirstProblemIsNamedWithItsRange) {
  Material m = sand();
  m.poisson_ratio = 0.5;
  parameters_of<MohrCoulomb>(m).dilation_angle = 40;
  auto problem = material_problem(m);
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->key, "poisson_ratio");
  EXPECT_EQ(problem->message, "got 0.5, expected a finite number in [0, 0.5)");

  m = sand();
  parameters_of<MohrCoulomb>(m).dilation_angle = 40;
  problem = material_problem(m);
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->key, "dilation_angle");
  EXPECT_EQ(problem->message, "got 40, expected a finite number in [0, 30]");

  m = sand();
  m.density = std::numeric_limits<double>::infinity();
  EXPECT_EQ(material_problem(m)->message, "got inf, expected a finite number in (0, inf]");

  m = sand();
  parameters_of<MohrCoulomb>(m).friction_angle = 0;
  parameters_of<MohrCoulomb>(m).cohesion = 0;
  problem = material_problem(m);
  ASSERT_TRUE(problem);
  EXPECT_EQ(problem->key, "cohesion");
  EXPECT_NE(problem->message.find("friction_angle > 0 or cohesion > 0"), std::string::npos);
}

TEST(Material, CheckMaterialLocatesTheProblem) {
  Material m = sand();
  parameters_of<MohrCoulomb>(m).tensile_strength = std::numeric_limits<double>::quiet_NaN();
  const std::string message = message_of([&] { check_material(m, "model.h5", "materials/sand@"); });
  EXPECT_EQ(message.rfind("model.h5: materials/sand@tensile_strength: got ", 0), 0u) << message;
}

}  // namespace
}  // namespace talus
