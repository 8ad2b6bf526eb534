// Validation case 1 (seed section 2; shared/validation.md): the spring-mass scene through the
// whole pipeline, against y(t) = 1e-3 (1 - cos(100 t)) over two periods.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "common/h5.hpp"
#include "support/test_support.hpp"

using namespace talus;
using talus::testing::run_talus;
using talus::testing::ScratchDir;
using talus::testing::source_path;

TEST(SpringMass, MassFollowsTheAnalyticalSolutionWithinTwoPercentOfTheAmplitude) {
  ScratchDir dir("spring-mass");
  const auto run = run_talus("run " + source_path("geometries/spring_mass.toml") + " --out " + dir.path().string() + " -q");
  ASSERT_EQ(run.status, 0) << run.output;

  const h5::File file = h5::File::open_read(dir.file("results.h5"));
  h5::Dims dims;
  const auto time = h5::read_doubles(file, "frames/time");
  const auto position = h5::read_doubles(file, "frames/position", &dims);
  const auto body = h5::read_ints(file, "particles/body");
  const auto names = h5::read_strings(file, "bodies/names");
  const std::size_t frames = dims[0], n = dims[1];
  const int mass_body = static_cast<int>(std::find(names.begin(), names.end(), "mass") - names.begin());
  ASSERT_LT(mass_body, static_cast<int>(names.size()));

  auto mean_height = [&](std::size_t frame) {
    double sum = 0;
    int count = 0;
    for (std::size_t p = 0; p < n; ++p)
      if (body[p] == mass_body) sum += position[(frame * n + p) * 2 + 1], ++count;
    return sum / count;
  };
  const double amplitude = 1e-3, omega = 100, period = 2 * M_PI / omega;
  ASSERT_GE(time.back(), 2 * period);
  ASSERT_GE(frames, 40u);
  double worst = 0;
  const double start = mean_height(0);
  for (std::size_t f = 0; f < frames; ++f) {
    const double settlement = start - mean_height(f);
    const double exact = amplitude * (1 - std::cos(omega * time[f]));
    worst = std::max(worst, std::abs(settlement - exact));
  }
  EXPECT_LT(worst, 0.02 * amplitude);
  // The deflection really oscillates: the mass reaches twice the static settlement.
  double deepest = 0;
  for (std::size_t f = 0; f < frames; ++f) deepest = std::max(deepest, start - mean_height(f));
  EXPECT_NEAR(deepest, 2 * amplitude, 0.05 * amplitude);

  // The postprocessor's own comparison agrees with this one.
  std::ifstream metrics(dir.file("metrics.json"));
  std::stringstream text;
  text << metrics.rdbuf();
  const std::string json = text.str();
  const auto key = json.find("\"max_error_over_amplitude\":");
  ASSERT_NE(key, std::string::npos) << json;
  const double reported = std::stod(json.substr(key + 27));
  EXPECT_NEAR(reported, worst / amplitude, 1e-6);
}
