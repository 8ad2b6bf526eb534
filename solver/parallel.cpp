#include "solver/parallel.hpp"

#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <thread>

namespace talus::solver {

int available_cores() {
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof mask, &mask) == 0) {
    const int count = CPU_COUNT(&mask);
    if (count > 0) return count;
  }
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

namespace {

// 48812 -> "48,812"
std::string with_commas(long n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

}  // namespace

ThreadChoice choose_threads(long particles, int requested) {
  if (requested > 0) return {requested, "--threads"};
  const char* env = std::getenv("OMP_NUM_THREADS");
  const bool from_env = env && *env;
  // OpenMP's count is the user's OMP_NUM_THREADS, or what omp_set_num_threads set, or (by
  // default) the CPUs OpenMP found; the affinity mask bounds it unless the user asked for more.
  const int cores = from_env ? std::max(1, omp_get_max_threads())
                             : std::max(1, std::min(available_cores(), omp_get_max_threads()));
  const long by_size = std::max(1L, particles / kParticlesPerThread);
  ThreadChoice choice;
  choice.threads = static_cast<int>(std::min<long>(cores, by_size));
  choice.why = "auto: " + with_commas(particles) + " particles, " + std::to_string(cores) +
               (from_env ? " from OMP_NUM_THREADS" : cores == 1 ? " core" : " cores");
  return choice;
}

void bound_openmp_spin(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;
  if (setenv("GOMP_SPINCOUNT", kSpinCount, 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GOMP_SPINCOUNT");  // exec failed: carry on with OpenMP's defaults
}

}  // namespace talus::solver
