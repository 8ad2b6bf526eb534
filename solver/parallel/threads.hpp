// The thread contract: a simulation is built for a number of threads (its per-thread buffers
// are sized for them), and every parallel region of the solver asks for exactly that many
// with num_threads(threads), whatever OMP_NUM_THREADS or omp_set_num_threads say. Work is split
// with static schedules (OwnerFirstChunks, below, where the iterations are independent and
// unequal in cost) and every floating-point sum is taken in an order fixed by the thread
// count, so the same thread count gives bit-identical results run after run.
#pragma once
#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace talus::solver {

// ---- How many threads a solve uses (parallel.cpp) ---------------------------------------------

// Below this many particles per thread a second thread costs more at the step's barriers than
// it saves (measured on a quiet 2-core machine, docs/benchmarks.md "Thread choice": 2 threads
// broke even at 128 particles and were 1.2x faster at 288): the automatic choice gives every
// thread at least this many particles.
inline constexpr long kParticlesPerThread = 250;

// Set by bound_openmp_spin on a busy machine: how many other programs were running when talus
// started. The automatic thread count leaves that many cores to them while any core stays free.
inline constexpr const char* kBusyCoresVariable = "TALUS_BUSY_CORES";

// Other programs running now: procs_running of /proc/stat (less this process), the median of 5
// samples 2 ms apart; 0 when it cannot be read.
int busy_cores_now();
// The count bound_openmp_spin saw (kBusyCoresVariable), 0 on a quiet start.
int busy_cores_at_start();

// The cores this process may run on: the CPUs of its affinity mask (sched_getaffinity), else
// std::thread::hardware_concurrency, at least 1.
int available_cores();

// The most threads a solve may have: 4 x the machine's hardware threads, never above
// kMaxThreads (each thread keeps grid buffers of its own). --threads is refused above it, and an
// OMP_NUM_THREADS above it is not trusted (environment_threads).
inline constexpr int kMaxThreads = 1024;
int thread_cap();

// OMP_NUM_THREADS as a count (its first entry): 0 when unset, empty or not a positive number,
// and -1 when above thread_cap() (OMP_NUM_THREADS=100000: the automatic choice ignores it).
int environment_threads();

// Called first thing in main: when OMP_NUM_THREADS is above thread_cap(), OpenMP's count (what
// a parallel region without num_threads would start, and the default of fos's workers) is
// brought back to the available cores.
void bound_openmp_threads();

struct ThreadChoice {
  int threads = 1;
  std::string why;  // for the summary line: "auto: 48,812 particles, 2 cores" or "--threads"
};

// `requested` > 0 is the user's count (--threads) and wins. Otherwise the count follows the
// problem size: particles / kParticlesPerThread, at least 1, at most the cores available
// (the affinity mask; OMP_NUM_THREADS when set in the environment; omp_set_num_threads when
// called with fewer) less the cores busy with other programs when talus started
// (busy_cores_at_start), or all of them when no core was free.
ThreadChoice choose_threads(long particles, int requested);

// OpenMP threads that wait at the end of a loop spin first (libgomp: 300,000 spins, about 9 ms
// on this machine's cores) and then sleep. When other programs hold the cores, a thread spinning
// for a descheduled partner burns the time that partner needs: a 2-thread solve took 12x its
// quiet time with one busy program per core, and up to 20x under the build load of this machine.
// kSpinCount spins (about 0.9 ms) are longer than any wait inside a step, so a quiet solve runs
// as fast as with libgomp's default, and a tenth of it under load; with the threads pinned
// (ThreadPinning), the crossed default slope under one busy program per core took 2.1 times its
// quiet time on 2 threads, against 2.9 on 1 thread and 3.2 with a spin of 300 (medians;
// docs/benchmarks.md, "Under load"). libgomp reads the spin when it is loaded, before main, so
// the driver `./talus` starts the program with GOMP_SPINCOUNT = kSpinCount, marked as its own
// by the same value in kDriverSpinVariable (a restart of every run would cost talus's start-up,
// 0.2 s, again).
// This function looks at the machine (busy_cores_now): when other programs are running, it
// records their number in kBusyCoresVariable for choose_threads; a program started without the
// driver's spin is then started again (execv of /proc/self/exe with the same arguments) with
// GOMP_SPINCOUNT = kSpinCount. A user's OMP_WAIT_POLICY or GOMP_SPINCOUNT turns all of this off,
// and so does a process where /proc/self/exe cannot be run or is not this program (under
// valgrind it is the tool, which cannot be run directly) when it would have to restart.
// Call it first thing in main.
inline constexpr const char* kSpinCount = "30000";  // the driver `talus` sets the same
inline constexpr const char* kDriverSpinVariable = "TALUS_DRIVER_SPINCOUNT";
// Whether GOMP_SPINCOUNT is the driver's spin (kDriverSpinVariable holds the same value).
bool spin_is_drivers();
void bound_openmp_spin(char** argv);

// A solve whose threads take every CPU of the process's affinity mask pins thread t to the t-th
// of those CPUs for its time loop, and gives every thread its mask back at the end. Unpinned,
// the scheduler places a thread woken at a barrier beside the thread that woke it: when another
// program takes a core during the solve, both threads then share the other core and every
// barrier costs the waiter's whole spin (a load that started during the 3,000-step crossed slope:
// 14-17 s unpinned, the two threads on one CPU in 70-80 % of samples; 4.7-5.9 s pinned;
// docs/benchmarks.md, "Under load"). Nothing is pinned for one thread, for fewer threads than
// CPUs (other programs, or other ranks of an MPI solve, may need the rest), when the user set
// OMP_PROC_BIND or OMP_PLACES, or when waiting threads sleep at once (OMP_WAIT_POLICY=passive,
// as in the test suite): sleeping threads leave their CPUs idle, and unpinned ones move to
// idle CPUs (two solves at once with passive waits: 2.1 s unpinned, 3.0-3.8 s pinned; with
// the spin of 30,000, 35-37 s unpinned and 1.8-2.5 s pinned).
class ThreadPinning {
 public:
  explicit ThreadPinning(int threads);
  ~ThreadPinning() { release(); }
  ThreadPinning(const ThreadPinning&) = delete;
  ThreadPinning& operator=(const ThreadPinning&) = delete;
  bool pinned() const { return pinned_; }

 private:
  void release();  // every thread back to the mask it had
  int threads_ = 1;
  bool pinned_ = false;
  cpu_set_t mask_{};  // the mask the threads had, while pinned_
};

// Thread t's share [begin, end) of [0, n) when split into `threads` contiguous chunks.
inline void chunk_of(long n, int threads, int t, long& begin, long& end) {
  begin = n * t / threads;
  end = n * (t + 1) / threads;
}

// A split of [0, n) for loops whose iterations are independent but unequal in cost (the stress
// update: a plastic particle costs several times an elastic one, and plastic particles cluster).
// Each thread first takes chunks from the front of its own static share (chunk_of, the share
// every static loop over the particles gives it, so the particles' data is already in its
// core's caches), then takes what is left of the other threads' shares, a chunk at a time.
// Each iteration runs exactly once. (schedule(dynamic) balanced the work too, but handed about
// half the particles to the core whose caches did not hold them, and the next phase paid for
// moving their cache lines back: docs/benchmarks.md, "Owner-first chunks".)
// Use: construct before the parallel region, call for_each(body) inside it on every thread.
class OwnerFirstChunks {
 public:
  OwnerFirstChunks(long n, int threads, long chunk = 256)
      : n_(n), threads_(std::max(1, threads)), chunk_(std::max(1L, chunk)), next_(new Counter[threads_]) {
    for (int t = 0; t < threads_; ++t) {
      long begin, end;
      chunk_of(n_, threads_, t, begin, end);
      next_[t].value.store(begin, std::memory_order_relaxed);
    }
  }
  // body(begin, end) for the chunks this thread claims; thread t of a team of any size.
  template <class Body>
  void for_each(Body body) {
    const int me = omp_get_thread_num();
    for (int k = 0; k < threads_; ++k) {
      const int t = (me + k) % threads_;
      long begin, end;
      chunk_of(n_, threads_, t, begin, end);
      for (;;) {
        const long first = next_[t].value.fetch_add(chunk_, std::memory_order_relaxed);
        if (first >= end) break;
        body(first, std::min(first + chunk_, end));
      }
    }
  }

 private:
  struct alignas(64) Counter {
    std::atomic<long> value{0};
  };
  long n_;
  int threads_;
  long chunk_;
  std::unique_ptr<Counter[]> next_;
};

// The sum of term(i) over [0, n): each thread adds its contiguous chunk in index order, and the
// chunks are added in thread order, so the result depends on n and `threads` only. T is any
// type with operator+= and a zero from T{} (double, or a small struct of doubles).
template <class T, class Term>
T ordered_sum(long n, int threads, Term term) {
  std::vector<T> partial(static_cast<std::size_t>(threads), T{});
#pragma omp parallel num_threads(threads)
  {
    // A team smaller than asked for (OMP_THREAD_LIMIT) still covers every chunk.
    for (int c = omp_get_thread_num(); c < threads; c += omp_get_num_threads()) {
      long begin, end;
      chunk_of(n, threads, c, begin, end);
      T sum{};
      for (long i = begin; i < end; ++i) sum += term(i);
      partial[c] = sum;
    }
  }
  T total{};
  for (const T& value : partial) total += value;
  return total;
}

}  // namespace talus::solver
