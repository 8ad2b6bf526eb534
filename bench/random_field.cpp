// Random-field benchmark (preproc/random_field/random_field.hpp): the time to build the generators and to
// draw one realisation of two cross-correlated fields (lognormal cohesion, normal friction angle,
// Markov, correlation_length [20, 2] m) on an nx x ny grid of 0.25 m, and to take one field's
// values at 100,000 points. A printout only, on one thread.
//
//   talus_bench_random_field [--nx 256] [--ny 128] [--repeat 50]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "preproc/random_field/random_field.hpp"

namespace talus {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

Scene two_fields() {
  Scene scene;
  Material sand;
  sand.name = "sand";
  sand.model = MohrCoulomb::Parameters{.friction_angle = 30, .cohesion = 10e3};
  sand.density = 1800, sand.youngs_modulus = 1e7, sand.poisson_ratio = 0.3;
  scene.materials = {sand};
  RandomField cohesion;
  cohesion.name = "cohesion";
  cohesion.material = "sand";
  cohesion.parameter = "cohesion";
  cohesion.mean = 10e3;
  cohesion.cov = 0.3;
  cohesion.correlation_length = {20, 2};
  RandomField friction = cohesion;
  friction.name = "friction";
  friction.parameter = "friction_angle";
  friction.distribution = RandomDistribution::Normal;
  friction.mean = 30;
  friction.cov = 0.1;
  friction.cross_with = "cohesion";
  friction.cross_rho = -0.5;
  scene.random = {cohesion, friction};
  return scene;
}

int run(int nx, int ny, int repeat) {
  preproc::FieldGrid grid;
  grid.nx = nx, grid.ny = ny;
  grid.spacing = {0.25, 0.25};
  const auto built = Clock::now();
  const preproc::RandomFields fields(two_fields(), grid);
  const double build_time = seconds_since(built);
  const auto& generator = fields.generator(0);
  std::printf("grid %d x %d (%.2f x %.2f m), torus %d x %d (padding %d), one generator for both fields\n", nx, ny,
              (nx - 1) * 0.25, (ny - 1) * 0.25, generator.torus_x(), generator.torus_y(), generator.padding());
  std::printf("build (eigenvalues, plans): %.2f ms\n", 1e3 * build_time);

  std::vector<double> draw_times;
  for (int r = 0; r < repeat; ++r) {
    const auto start = Clock::now();
    const auto g = fields.gaussian(static_cast<std::uint64_t>(r));
    draw_times.push_back(seconds_since(start));
  }
  std::printf("one realisation of 2 fields: median %.2f ms, fastest %.2f ms (%d draws)\n",
              1e3 * median(draw_times), 1e3 * *std::min_element(draw_times.begin(), draw_times.end()), repeat);

  std::vector<Eigen::Vector2d> points;
  std::mt19937_64 stream(1);
  for (int p = 0; p < 100000; ++p)
    points.push_back({(nx - 1) * 0.25 * (stream() >> 11) * 0x1p-53, (ny - 1) * 0.25 * (stream() >> 11) * 0x1p-53});
  const auto g = fields.gaussian(0);
  std::vector<double> value_times;
  for (int r = 0; r < std::max(repeat / 5, 1); ++r) {
    const auto start = Clock::now();
    const auto values = fields.values_at(0, g[0], points);
    value_times.push_back(seconds_since(start));
  }
  std::printf("one field's values at 100,000 points: median %.2f ms\n", 1e3 * median(value_times));
  return 0;
}

}  // namespace
}  // namespace talus

int main(int argc, char** argv) {
  int nx = 256, ny = 128, repeat = 50;
  if (argc % 2 == 0) {
    std::fprintf(stderr, "usage: talus_bench_random_field [--nx N] [--ny N] [--repeat N]\n");
    return 1;
  }
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string option = argv[i];
    const int value = std::atoi(argv[i + 1]);
    if (value < 1) {
      std::fprintf(stderr, "talus_bench_random_field: %s needs a positive integer\n", option.c_str());
      return 1;
    }
    if (option == "--nx") nx = value;
    else if (option == "--ny") ny = value;
    else if (option == "--repeat") repeat = value;
    else {
      std::fprintf(stderr, "usage: talus_bench_random_field [--nx N] [--ny N] [--repeat N]\n");
      return 1;
    }
  }
  try {
    return talus::run(nx, ny, repeat);
  } catch (const talus::Error& e) {
    std::fprintf(stderr, "talus_bench_random_field: %s\n", e.what());
    return 1;
  }
}
