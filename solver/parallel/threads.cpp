#include "solver/parallel/threads.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/auxv.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>
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

int busy_cores_now() {
  std::vector<int> samples;
  for (int k = 0; k < 5; ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    std::ifstream stat("/proc/stat");
    std::string key;
    int running = -1;
    while (stat >> key)
      if (key == "procs_running") {
        stat >> running;
        break;
      }
    if (running < 1) return 0;
    samples.push_back(running - 1);  // procs_running counts this process
  }
  std::sort(samples.begin(), samples.end());
  return samples[samples.size() / 2];
}

int busy_cores_at_start() {
  const char* env = std::getenv(kBusyCoresVariable);
  return env && *env ? std::max(0, std::atoi(env)) : 0;
}

int thread_cap() {
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  return hardware > 0 ? std::min(4 * hardware, kMaxThreads) : kMaxThreads;
}

int environment_threads() {
  const char* env = std::getenv("OMP_NUM_THREADS");
  if (!env || !*env) return 0;
  char* end = nullptr;
  const long count = std::strtol(env, &end, 10);  // "4,2" (nested levels): the outer count
  if (end == env || count < 1) return 0;
  return count > thread_cap() ? -1 : static_cast<int>(count);
}

void bound_openmp_threads() {
  if (environment_threads() < 0) omp_set_num_threads(available_cores());
}

ThreadChoice choose_threads(long particles, int requested) {
  if (requested > 0) return {requested, "--threads"};
  const int env_threads = environment_threads();
  const bool from_env = env_threads > 0;
  const char* env = std::getenv("OMP_NUM_THREADS");
  // OpenMP's count is the user's OMP_NUM_THREADS, or what omp_set_num_threads set, or (by
  // default) the CPUs OpenMP found; the affinity mask bounds it unless the user asked for more.
  // Ranks of one machine (mpirun sets OMPI_COMM_WORLD_LOCAL_SIZE) share its cores.
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  const int sharing = local && *local ? std::max(1, std::atoi(local)) : 1;
  // An OMP_NUM_THREADS above the cap of --threads is not the user's count but a mistake (100000
  // started a thread per 250 particles: 1,202 threads and 7.6 GB for 300k): the cores decide.
  const int openmp = env_threads < 0 ? available_cores() : omp_get_max_threads();
  const int cores = from_env ? std::max(1, std::min(env_threads, openmp))
                             : std::max(1, std::min(available_cores(), openmp) / sharing);
  const long by_size = std::max(1L, particles / kParticlesPerThread);
  const int busy = busy_cores_at_start();
  ThreadChoice choice;
  // Cores that other programs leave free are this solve's; when none is free, all of them are,
  // for the fair share the scheduler gives each of the solve's threads (ThreadPinning keeps
  // those threads apart).
  choice.threads = static_cast<int>(std::min<long>(busy < cores ? cores - busy : cores, by_size));
  choice.why = "auto: " + with_commas(particles) + " particles, " + std::to_string(cores) +
               (from_env ? " from OMP_NUM_THREADS" : cores == 1 ? " core" : " cores") +
               (sharing > 1 && !from_env ? " of the machine's shared by its " + std::to_string(sharing) + " ranks" : "") +
               (busy > 0 ? ", " + std::to_string(busy) + " busy" : "") +
               (env_threads < 0 ? "; OMP_NUM_THREADS=" + std::string(env).substr(0, 20) + " ignored, above the cap of " +
                                      std::to_string(thread_cap())
                                : "");
  return choice;
}

namespace {

// Whether /proc/self/exe is this program: the file the kernel ran (AT_EXECFN) and /proc/self/exe
// are one file. Under a tool that runs the program itself (valgrind) /proc/self/exe is the tool,
// which refuses to be run directly, so the program is not restarted there.
bool self_is_this_program() {
  const char* name = reinterpret_cast<const char*>(getauxval(AT_EXECFN));
  struct stat named {}, self {};
  return name && stat(name, &named) == 0 && stat("/proc/self/exe", &self) == 0 && named.st_dev == self.st_dev &&
         named.st_ino == self.st_ino;
}

}  // namespace

bool spin_is_drivers() {
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  const char* ours = std::getenv(kDriverSpinVariable);
  return spin && ours && std::string(spin) == ours;
}

void bound_openmp_spin(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || (std::getenv("GOMP_SPINCOUNT") && !spin_is_drivers()) ||
      std::getenv(kBusyCoresVariable))
    return;
  const int busy = busy_cores_now();
  if (busy == 0) return;  // a quiet machine
  const std::string count = std::to_string(busy);
  if (spin_is_drivers()) {  // libgomp has the driver's spin, the one for a busy machine too
    setenv(kBusyCoresVariable, count.c_str(), 1);
    return;
  }
  if (!self_is_this_program()) return;
  if (setenv("GOMP_SPINCOUNT", kSpinCount, 1) != 0 || setenv(kBusyCoresVariable, count.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GOMP_SPINCOUNT");  // the exec failed: carry on with OpenMP's defaults
  unsetenv(kBusyCoresVariable);
}

namespace {

// Whether OpenMP's waiting threads sleep at once (OMP_WAIT_POLICY=passive, or no spin).
bool waits_sleep() {
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  std::string lower = policy ? policy : "";
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == "passive" || (spin && std::string(spin) == "0");
}

}  // namespace

ThreadPinning::ThreadPinning(int threads) : threads_(threads) {
  if (threads_ < 2 || omp_in_parallel() || std::getenv("OMP_PROC_BIND") || std::getenv("OMP_PLACES")) return;
  if (waits_sleep()) return;
  CPU_ZERO(&mask_);
  if (sched_getaffinity(0, sizeof mask_, &mask_) != 0) return;
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &mask_)) cpus.push_back(c);
  if (static_cast<int>(cpus.size()) != threads_) return;
  pinned_ = true;
  int failed = 0;
#pragma omp parallel num_threads(threads_) reduction(+ : failed)
  {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpus[static_cast<std::size_t>(omp_get_thread_num())], &one);
    failed += pthread_setaffinity_np(pthread_self(), sizeof one, &one) != 0;
  }
  if (failed > 0) release();  // some thread could not be pinned: none stays pinned
}

void ThreadPinning::release() {
  if (!pinned_) return;
#pragma omp parallel num_threads(threads_)
  pthread_setaffinity_np(pthread_self(), sizeof mask_, &mask_);
  pinned_ = false;
}

}  // namespace talus::solver
