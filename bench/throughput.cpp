// Solver throughput: an elastic block settling under gravity on a fixed base, over a sweep of
// sizes and thread counts, through the same solve() that `talus solve` runs (results written
// at the first and last step). Each case runs in its own process, so that its peak resident
// memory is its own; the median of several repeats is reported. Per case: the set-up (the
// model built, written to model.h5 and read back, the simulation built), the loop's rate,
// peak resident bytes per particle, the time per step phase, and how far the rate is from
// what the machine's memory bandwidth (a STREAM-like triad, measured here) allows; the frame the
// loop writes, against the rate at which the machine writes a new file (measured here).
//
//   build/bin/talus_bench_throughput                       50k, 400k, 2M, 10M; 1 and all cores
//   build/bin/talus_bench_throughput --sizes 50k,400k      a quick sweep (no 2M, 10M)
//   build/bin/talus_bench_throughput --threads 2 --repeats 5 --csv out.csv
//   build/bin/talus_bench_throughput --case 50000 2        one case (used by the above)
//   build/bin/talus_bench_throughput --model M.h5 2         a scene's model (talus mesh), its own
//                                                          run settings: rate and time per phase
#include <fcntl.h>
#include <omp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "solver/parallel/parallel.hpp"
#include "solver/io/io.hpp"
#include "solver/step/simulation.hpp"
#include "solver/solver.hpp"
#include "support/test_support.hpp"

namespace {

using talus::Model;
using talus::solver::PhaseTimes;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

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

constexpr int kPhases = PhaseTimes::Count;

struct Measurement {
  long particles = 0, steps = 0;
  int threads = 0;
  double updates_per_second = 0, bytes_per_particle = 0, loop_seconds = 0;
  double build_seconds = 0, model_file_seconds = 0, simulation_seconds = 0;  // the set-up
  double frame_seconds = 0;  // of the loop: writing the frames after the first (the last one here)
  double stepping_rate() const {  // particle-updates/s of the loop without its frames
    return static_cast<double>(particles) * steps / (loop_seconds - frame_seconds);
  }
  // particle-updates/s with the loop's frame written once per `interval` steps instead
  double rate_with_frame_every(long interval) const {
    const double per_step = (loop_seconds - frame_seconds) / static_cast<double>(steps) + frame_seconds / interval;
    return static_cast<double>(particles) / per_step;
  }
  double phase[kPhases] = {};                                                  // s over the loop
};

// solve() into `folder` (removed afterwards) on `threads` threads with the phase timer.
talus::solver::SolveSummary solve_timed(Model&& model, const std::filesystem::path& folder, int threads,
                                        PhaseTimes& phases) {
  talus::solver::SolveOptions options;
  options.out_dir = folder.string();
  options.progress = false;
  options.threads = threads;
  options.phase_times = &phases;
  std::ostringstream ignored;
  const auto summary = talus::solver::solve(std::move(model), options, ignored);
  std::filesystem::remove_all(folder);
  return summary;
}

// The child: one case, one line of numbers on stdout.
int run_case(long target, int threads) {
  const auto folder = std::filesystem::temp_directory_path() / ("talus-bench-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  auto start = Clock::now();
  Model built = elastic_block(target);
  built.run.max_steps = std::max(20L, static_cast<long>(2e7 / built.particle_count()));
  const double build_seconds = since(start);
  // The pipeline's hand-over: `talus mesh` writes model.h5, `talus solve` reads it.
  start = Clock::now();
  const std::string model_file = (folder / "model.h5").string();
  talus::write_model(model_file, built);
  built = Model();
  Model model = talus::read_model(model_file);
  const double model_file_seconds = since(start);

  PhaseTimes phases;
  const auto summary = solve_timed(std::move(model), folder, threads, phases);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  std::printf("%zu %ld %d %.6e %.2f %.4f %.4f %.4f %.4f %.4f", summary.particles, summary.steps, summary.threads,
              summary.particle_updates_per_second(), usage.ru_maxrss * 1024.0 / summary.particles,
              summary.loop_seconds, build_seconds, model_file_seconds, summary.setup_seconds, summary.frame_seconds);
  for (double s : phases.seconds) std::printf(" %.5f", s);
  std::printf("\n");
  return 0;
}

// A scene's model.h5 as `talus solve` runs it (its run settings: set run.max_steps when meshing),
// with the phase timer: the rate and the time per phase in ns per particle-update, readable.
int run_model(const std::string& model_file, int threads) {
  const auto folder = std::filesystem::temp_directory_path() / ("talus-bench-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  PhaseTimes phases;
  const auto summary = solve_timed(talus::read_model(model_file), folder, threads, phases);
  const double updates = static_cast<double>(summary.particles) * static_cast<double>(summary.steps);
  std::printf("%zu particles, %ld steps, %d threads: time loop %.3f s, %.4e particle-updates/s\n", summary.particles,
              summary.steps, summary.threads, summary.loop_seconds, summary.particle_updates_per_second());
  double phased = 0;
  for (int i = 0; i < kPhases; ++i) {
    phased += phases.seconds[i];
    std::printf("  %-28s %7.2f ns\n", PhaseTimes::kNames[i], 1e9 * phases.seconds[i] / updates);
  }
  std::printf("  %-28s %7.2f ns\n", "frames written", 1e9 * summary.frame_seconds / updates);
  std::printf("  %-28s %7.2f ns\n", "other", 1e9 * (summary.loop_seconds - phased - summary.frame_seconds) / updates);
  return 0;
}

Measurement measure(const std::string& self, long target, int threads) {
  const std::string command = self + " --case " + std::to_string(target) + " " + std::to_string(threads);
  FILE* pipe = popen(command.c_str(), "r");
  Measurement m;
  bool ok = pipe && std::fscanf(pipe, "%ld %ld %d %lf %lf %lf %lf %lf %lf %lf", &m.particles, &m.steps, &m.threads,
                                &m.updates_per_second, &m.bytes_per_particle, &m.loop_seconds, &m.build_seconds,
                                &m.model_file_seconds, &m.simulation_seconds, &m.frame_seconds) == 10;
  for (int i = 0; ok && i < kPhases; ++i) ok = std::fscanf(pipe, "%lf", &m.phase[i]) == 1;
  if (!ok) {
    std::fprintf(stderr, "talus_bench_throughput: case %ld/%d failed\n", target, threads);
    std::exit(1);
  }
  pclose(pipe);
  return m;
}

// STREAM's triad a = b + s c over arrays far larger than the caches, on `threads` threads:
// the best of 5 passes, in bytes per second (24 bytes per element, as STREAM counts).
double triad_bandwidth(int threads) {
  const long n = 1L << 25;  // 3 x 256 MiB
  std::vector<double> a(n), b(n), c(n);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (long i = 0; i < n; ++i) {  // first touch by the threads that use them
    a[i] = 0;
    b[i] = 1;
    c[i] = 2;
  }
  double best = 1e30;
  for (int pass = 0; pass < 5; ++pass) {
    const auto start = Clock::now();
    const double s = 3.0 + pass;
#pragma omp parallel for num_threads(threads) schedule(static)
    for (long i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    best = std::min(best, since(start));
  }
  volatile double keep = a[n / 2];
  (void)keep;
  return 24.0 * n / best;
}

// The rate at which this machine writes a new file in the temporary directory (where the cases
// write results.h5), as a frame is written: 2 MiB at a time (a frame piece of the stress, whose
// chunk is kFrameBlock rows of 4 doubles), without fsync (a frame is not synced either). Three
// files of 1 GiB (about a 10M-particle frame) are written one after the other and kept until the
// end, so that each goes to page cache not freed by the one before; the median of their rates,
// in bytes per second, and the slowest and fastest in `range`. 0 if the files cannot be written,
// and without trying where less than 4 GiB are free (the bench does not fill a disk).
double file_write_rate(double range[2]) {
  const std::size_t piece = talus::solver::kFrameBlock * 4 * sizeof(double), pieces = 512;
  std::error_code error;
  const auto space = std::filesystem::space(std::filesystem::temp_directory_path(), error);
  if (error || space.available < 4 * piece * pieces) return 0;
  const auto folder = std::filesystem::temp_directory_path() / ("talus-bench-write-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  const std::vector<char> data(piece, 1);
  std::vector<double> rates;
  for (int file = 0; file < 3; ++file) {
    const std::string path = (folder / ("file" + std::to_string(file))).string();
    const int fd = open(path.c_str(), O_CREAT | O_TRUNC | O_WRONLY, 0644);
    if (fd < 0) break;
    const auto start = Clock::now();
    bool ok = true;
    for (std::size_t k = 0; ok && k < pieces; ++k)
      ok = pwrite(fd, data.data(), piece, static_cast<off_t>(k * piece)) == static_cast<ssize_t>(piece);
    const double seconds = since(start);
    close(fd);
    if (!ok) break;
    rates.push_back(static_cast<double>(piece * pieces) / seconds);
  }
  std::filesystem::remove_all(folder);
  if (rates.size() < 3) return 0;
  std::sort(rates.begin(), rates.end());
  range[0] = rates.front(), range[1] = rates.back();
  return rates[1];
}

// Bytes of per-particle arrays the step reads and writes: the particle fields, the stencil's
// weights and row index and the strain increment, per particle, from a
// small block (they do not depend on the size).
double state_bytes_per_particle() {
  const Model model = elastic_block(4000);
  const talus::solver::Simulation sim = talus::solver::make_simulation(model, 1);
  double bytes = 0;
  sim.particles.for_each_field([&](const auto&, const auto& column) {
    bytes += static_cast<double>(column.size()) * sizeof(column[0]);
  });
  const auto& s = sim.scratch;
  bytes += s.stencil.N.size() * sizeof(double) + s.stencil.row.size() * sizeof(int32_t);
  bytes += s.d_eps.size() * sizeof(s.d_eps[0]);
  return bytes / static_cast<double>(sim.particles.size());
}

long parse_size(const std::string& text) {
  std::size_t used = 0;
  const double value = std::stod(text, &used);
  const std::string unit = text.substr(used);
  const double scale = unit.empty() ? 1 : unit == "k" ? 1e3 : unit == "M" ? 1e6 : 0;
  if (scale == 0 || !(value > 0)) throw std::invalid_argument(text);
  return std::lround(value * scale);
}

template <class T, class Parse>
std::vector<T> parse_list(const std::string& text, Parse parse) {
  std::vector<T> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(parse(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  talus::solver::bound_openmp_spin(argv);  // as `talus` does; the cases inherit it
  int repeats = 3;
  std::string csv;
  std::vector<long> sizes{50000, 400000, 2000000, 10000000};
  const int cores = talus::solver::available_cores();
  std::vector<int> thread_counts{1};
  if (cores > 1) thread_counts.push_back(cores);
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--case" && i + 2 < argc) return run_case(std::atol(argv[i + 1]), std::atoi(argv[i + 2]));
      if (arg == "--model" && i + 2 < argc) return run_model(argv[i + 1], std::max(1, std::atoi(argv[i + 2])));
      if (arg == "--repeats" && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
      else if (arg == "--csv" && i + 1 < argc) csv = argv[++i];
      else if (arg == "--sizes" && i + 1 < argc) sizes = parse_list<long>(argv[++i], parse_size);
      else if (arg == "--threads" && i + 1 < argc)
        thread_counts = parse_list<int>(argv[++i], [](const std::string& t) { return std::max(1, std::stoi(t)); });
      else {
        std::fprintf(stderr,
                     "usage: %s [--sizes 50k,400k,2M,10M] [--threads 1,%d] [--repeats N] [--csv FILE]\n"
                     "       %s --case PARTICLES THREADS\n"
                     "       %s --model MODEL.h5 THREADS\n",
                     argv[0], cores, argv[0], argv[0]);
        return arg == "--help" || arg == "-h" ? 0 : 1;
      }
    }
  } catch (const std::exception&) {
    std::fprintf(stderr, "talus_bench_throughput: bad --sizes or --threads (e.g. --sizes 50k,2M --threads 1,2)\n");
    return 1;
  }
  const std::string self = std::filesystem::canonical("/proc/self/exe").string();
  std::ifstream loadavg("/proc/loadavg");
  std::string load;
  std::getline(loadavg, load);
  const double state_bytes = state_bytes_per_particle();
  std::printf("Machine: %d cores; load average at the start %s\n", cores, load.c_str());
  std::printf("Per-particle state the step reads and writes: %.0f bytes; a step moves at least twice that "
              "(one read, one write) per particle\n",
              state_bytes);
  std::vector<double> bandwidth;
  for (int t : thread_counts) {
    bandwidth.push_back(triad_bandwidth(t));
    std::printf("Memory bandwidth (triad, %d thread%s): %.1f GB/s: at most %.3g particle-updates/s\n", t,
                t == 1 ? "" : "s", bandwidth.back() / 1e9, bandwidth.back() / (2 * state_bytes));
  }
  double write_range[2] = {0, 0};
  const double write_rate = file_write_rate(write_range);
  if (write_rate > 0)
    std::printf("New file written in %s (3 x 1 GiB in 2 MiB pieces, as a frame is): %.2f GB/s (%.2f - %.2f)\n",
                std::filesystem::temp_directory_path().c_str(), write_rate / 1e9, write_range[0] / 1e9,
                write_range[1] / 1e9);
  else
    std::printf("New file written in %s: not measured (less than 4 GiB free, or 3 GiB could not be written)\n",
                std::filesystem::temp_directory_path().c_str());
  std::printf("\n");
  std::ofstream table_csv;
  if (!csv.empty()) {
    table_csv.open(csv);
    table_csv << "particles,threads,steps,repeats,median_particle_updates_per_second,min,max,bytes_per_particle,"
                 "build_s,model_file_s,simulation_s,loop_s,bandwidth_bound,fraction_of_bound";
    for (const char* name : PhaseTimes::kNames) table_csv << "," << name << "_s";
    table_csv << ",frames_s,other_s,stepping_rate\n";
  }
  std::vector<Measurement> medians;
  std::printf("| particles | threads | steps | set-up: build + model.h5 + simulation (s) | particle-updates/s (median "
              "of %d) | range | without the last frame's writing | bytes/particle | of the bandwidth bound |\n",
              repeats);
  std::printf("|---:|---:|---:|---|---:|---:|---:|---:|---:|\n");
  for (long target : sizes)
    for (std::size_t ti = 0; ti < thread_counts.size(); ++ti) {
      const int threads = thread_counts[ti];
      std::vector<Measurement> runs;
      for (int r = 0; r < repeats; ++r) runs.push_back(measure(self, target, threads));
      std::sort(runs.begin(), runs.end(),
                [](const auto& a, const auto& b) { return a.updates_per_second < b.updates_per_second; });
      const Measurement& m = runs[runs.size() / 2];
      const double bound = bandwidth[ti] / (2 * state_bytes);
      std::printf("| %ld | %d | %ld | %.2f + %.2f + %.2f | %.3e | %.2e - %.2e | %.3e | %.0f | %.0f%% |\n",
                  m.particles, threads, m.steps, m.build_seconds, m.model_file_seconds, m.simulation_seconds,
                  m.updates_per_second, runs.front().updates_per_second, runs.back().updates_per_second,
                  m.stepping_rate(), m.bytes_per_particle, 100 * m.updates_per_second / bound);
      std::fflush(stdout);
      medians.push_back(m);
      double timed = 0;
      for (double s : m.phase) timed += s;
      if (table_csv) {
        table_csv << m.particles << "," << threads << "," << m.steps << "," << repeats << ","
                  << m.updates_per_second << "," << runs.front().updates_per_second << ","
                  << runs.back().updates_per_second << "," << m.bytes_per_particle << "," << m.build_seconds << ","
                  << m.model_file_seconds << "," << m.simulation_seconds << "," << m.loop_seconds << "," << bound
                  << "," << m.updates_per_second / bound;
        for (double s : m.phase) table_csv << "," << s;
        table_csv << "," << m.frame_seconds << "," << m.loop_seconds - timed - m.frame_seconds << ","
                  << m.stepping_rate() << "\n";
      }
    }
  // Where the loop's time goes: each phase's share of the median run's loop, in ns per particle-update.
  std::printf("\nTime per phase (ns per particle-update; the median run of each case):\n\n| phase |");
  for (const Measurement& m : medians) std::printf(" %ld, %d |", m.particles, m.threads);
  std::printf("\n|---|");
  for (std::size_t i = 0; i < medians.size(); ++i) std::printf("---:|");
  std::printf("\n");
  auto per_update = [](const Measurement& m, double s) { return 1e9 * s / (static_cast<double>(m.particles) * m.steps); };
  for (int p = 0; p < kPhases; ++p) {
    std::printf("| %s |", PhaseTimes::kNames[p]);
    for (const Measurement& m : medians) std::printf(" %.1f |", per_update(m, m.phase[p]));
    std::printf("\n");
  }
  std::printf("| frames written (results.h5) |");
  for (const Measurement& m : medians) std::printf(" %.1f |", per_update(m, m.frame_seconds));
  std::printf("\n| other (time step, observers, sorting) |");
  for (const Measurement& m : medians) {
    double timed = 0;
    for (double s : m.phase) timed += s;
    std::printf(" %.1f |", per_update(m, m.loop_seconds - timed - m.frame_seconds));
  }
  std::printf("\n| **loop** |");
  for (const Measurement& m : medians) std::printf(" %.1f |", per_update(m, m.loop_seconds));
  std::printf("\n");
  // The frame against the machine's file writing: a frame holds every frame field in doubles.
  int frame_width = 0;
  for (const auto& field : talus::solver::frame_fields(false)) frame_width += field.width;
  std::printf("\nThe last frame (%d doubles per particle), against the new file's %.2f GB/s above:\n", frame_width,
              write_rate / 1e9);  // 0.00 and 0% where it was not measured
  for (const Measurement& m : medians) {
    if (!(m.frame_seconds > 0)) continue;  // too short for the clock
    const double bytes = 8.0 * frame_width * static_cast<double>(m.particles);
    std::printf("  %ld particles, %d thread%s: %.0f MB in %.2f s, %.2f GB/s (%.0f%%)\n", m.particles, m.threads,
                m.threads == 1 ? "" : "s", bytes / 1e6, m.frame_seconds, bytes / m.frame_seconds / 1e9,
                write_rate > 0 ? 100 * bytes / m.frame_seconds / write_rate : 0.0);
  }
  // Each case against the smallest at the same thread count. Every case writes one frame in its
  // loop (the last), so that frame weighs 20 times more per update over the 20 steps of 10M
  // particles than over the 400 of 50k: the second ratio leaves it out, and the third spreads
  // the case's measured frame over as many steps as the smallest case's loop has (one frame per
  // that many steps, as a run with that output interval writes them).
  std::printf("\nRate against the smallest case of the same thread count (loop; loop without the frame; one frame "
              "per as many steps as the smallest case):\n");
  for (const Measurement& base : medians) {
    bool smallest = true;
    for (const Measurement& other : medians) smallest &= other.threads != base.threads || other.particles >= base.particles;
    if (!smallest) continue;
    for (const Measurement& m : medians)
      if (m.threads == base.threads && m.particles > base.particles)
        std::printf("  %ld against %ld particles, %d thread%s: %.2f; %.2f; %.2f\n", m.particles, base.particles,
                    m.threads, m.threads == 1 ? "" : "s", m.updates_per_second / base.updates_per_second,
                    m.stepping_rate() / base.stepping_rate(),
                    m.rate_with_frame_every(base.steps) / base.updates_per_second);
  }
  return 0;
}
