// Solver throughput: an elastic block settling under gravity on a fixed base, at two sizes
// and two thread counts, through the same solve() that `talus solve` runs (results written at
// the first and last step). Each case runs in its own process, so that its peak resident
// memory is its own; the median of several repeats is reported.
//
//   build/bin/talus_bench_throughput                 all cases, 3 repeats, a Markdown table
//   build/bin/talus_bench_throughput --repeats 5 --csv out.csv
//   build/bin/talus_bench_throughput --case 50000 2  one case (used by the above)
#include <omp.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "solver/solver.hpp"
#include "support/test_support.hpp"

namespace {

using talus::Model;

// A square block of about `particles` particles (4 per triangle) in a domain 10% taller.
Model elastic_block(long particles) {
  const int n = static_cast<int>(std::lround(std::sqrt(particles / 8.0)));  // n x n squares, 8 particles each
  const double h = 10.0 / n;
  const int rows = n + n / 10 + 1;
  Model model = talus::testing::rectangle_mesh(0, 0, n, rows, h);
  talus::testing::add_box_body(model, "block", talus::testing::elastic(2000, 5e7, 0.3), 0, 10.0, 0, n * h);
  talus::testing::fix_base_roll_sides(model);
  talus::testing::set_run(model, 1e9, Eigen::Vector2d(0, -9.81));
  model.scene_name = "throughput";
  return model;
}

struct Measurement {
  long particles = 0, steps = 0;
  int threads = 0;
  double updates_per_second = 0, bytes_per_particle = 0, loop_seconds = 0;
};

int run_case(long target, int threads) {
  Model model = elastic_block(target);
  model.run.max_steps = std::max(20L, static_cast<long>(2e7 / model.particle_count()));
  const auto folder = std::filesystem::temp_directory_path() / ("talus-bench-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  talus::solver::SolveOptions options;
  options.out_dir = folder.string();
  options.progress = false;
  options.threads = threads;
  std::ostringstream ignored;
  const auto summary = talus::solver::solve(model, options, ignored);
  std::filesystem::remove_all(folder);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("%zu %ld %d %.6e %.2f %.4f\n", summary.particles, summary.steps, threads,
              summary.particle_updates_per_second(), usage.ru_maxrss * 1024.0 / summary.particles,
              summary.loop_seconds);
  return 0;
}

Measurement measure(const std::string& self, long target, int threads) {
  const std::string command = self + " --case " + std::to_string(target) + " " + std::to_string(threads);
  FILE* pipe = popen(command.c_str(), "r");
  Measurement m;
  if (!pipe || std::fscanf(pipe, "%ld %ld %d %lf %lf %lf", &m.particles, &m.steps, &m.threads,
                           &m.updates_per_second, &m.bytes_per_particle, &m.loop_seconds) != 6) {
    std::fprintf(stderr, "talus_bench_throughput: case %ld/%d failed\n", target, threads);
    std::exit(1);
  }
  pclose(pipe);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 3;
  std::string csv;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--case" && i + 2 < argc) return run_case(std::atol(argv[i + 1]), std::atoi(argv[i + 2]));
    if (arg == "--repeats" && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--csv" && i + 1 < argc) csv = argv[++i];
    else {
      std::fprintf(stderr, "usage: %s [--repeats N] [--csv FILE] | --case PARTICLES THREADS\n", argv[0]);
      return arg == "--help" || arg == "-h" ? 0 : 1;
    }
  }
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  std::ofstream table_csv;
  if (!csv.empty()) {
    table_csv.open(csv);
    table_csv << "particles,threads,steps,repeats,median_particle_updates_per_second,min,max,bytes_per_particle\n";
  }
  std::printf("| particles | threads | steps | particle-updates/s (median of %d) | range | bytes/particle |\n",
              repeats);
  std::printf("|---:|---:|---:|---:|---:|---:|\n");
  for (long target : {50000L, 400000L})
    for (int threads : {1, 2}) {
      std::vector<Measurement> runs;
      for (int r = 0; r < repeats; ++r) runs.push_back(measure(self, target, threads));
      std::sort(runs.begin(), runs.end(),
                [](const auto& a, const auto& b) { return a.updates_per_second < b.updates_per_second; });
      const Measurement& median = runs[runs.size() / 2];
      std::printf("| %ld | %d | %ld | %.3e | %.2e - %.2e | %.0f |\n", median.particles, threads, median.steps,
                  median.updates_per_second, runs.front().updates_per_second, runs.back().updates_per_second,
                  median.bytes_per_particle);
      std::fflush(stdout);
      if (table_csv)
        table_csv << median.particles << "," << threads << "," << median.steps << "," << repeats << ","
                  << median.updates_per_second << "," << runs.front().updates_per_second << ","
                  << runs.back().updates_per_second << "," << median.bytes_per_particle << "\n";
    }
  return 0;
}
