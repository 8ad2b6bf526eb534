// The thread contract: a simulation is built for a number of threads (its per-thread buffers
// are sized for them), and every parallel region of the solver asks for exactly that many
// with num_threads(threads), whatever OMP_NUM_THREADS or omp_set_num_threads say. Work is split
// with static schedules (OwnerFirstChunks, below, where the iterations are independent and
// unequal in cost) and every floating-point sum is taken in an order fixed by the thread
// count, so the same thread count gives bit-identical results run after run.
#pragma once
#include <omp.h>

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

// Set by bound_openmp_spin when it restarts the program on a busy machine: how many other
// programs were running then. The automatic thread count leaves that many cores to them.
inline constexpr const char* kBusyCoresVariable = "TALUS_BUSY_CORES";

// Other programs running now: procs_running of /proc/stat (less this process), the median of 5
// samples 2 ms apart; 0 when it cannot be read.
int busy_cores_now();
// The count bound_openmp_spin saw (kBusyCoresVariable), 0 when it did not restart the program.
int busy_cores_at_start();

// The cores this process may run on: the CPUs of its affinity mask (sched_getaffinity), else
// std::thread::hardware_concurrency, at least 1.
int available_cores();

struct ThreadChoice {
  int threads = 1;
  std::string why;  // for the summary line: "auto: 48,812 particles, 2 cores" or "--threads"
};

// `requested` > 0 is the user's count (--threads) and wins. Otherwise the count follows the
// problem size: particles / kParticlesPerThread, at least 1, at most the cores available
// (the affinity mask; OMP_NUM_THREADS when set in the environment; omp_set_num_threads when
// called with fewer) less the cores busy with other programs when talus started
// (busy_cores_at_start).
ThreadChoice choose_threads(long particles, int requested);

// OpenMP threads that wait at the end of a loop spin first (libgomp: 300,000 spins, about 9 ms
// on this machine's cores) and then sleep. When other programs hold the cores, a thread spinning
// for a descheduled partner burns the time that partner needs: a 2-thread solve took 12x its
// quiet time with one busy program per core, and up to 20x under the build load of this machine.
// A spin of kSpinCount (a few microseconds) then sleeping yields the core at once under load,
// but on a quiet machine it makes every barrier wait for a woken thread (the 6k-particle slope
// on 2 threads: 0.86 s against 0.61 s with libgomp's spin; docs/benchmarks.md, "Under load").
// So when other programs are running at the start (busy_cores_now() > 0), this starts the
// program again (execv of /proc/self/exe with the same arguments; libgomp reads its settings
// when it is loaded, before main) with GOMP_SPINCOUNT = kSpinCount and kBusyCoresVariable set.
// On a quiet machine it does nothing. The driver `./talus` starts the program with
// GOMP_SPINCOUNT = 30000 (about 0.9 ms), marked as its own by the same value in
// kQuietSpinVariable: longer than any wait inside a step, so a quiet solve runs as fast as with
// libgomp's default, and a tenth of that default, so a load that starts during the solve costs
// a waiting thread at most that long per barrier (docs/benchmarks.md, "A load that starts during
// the solve"). It cannot be set here: libgomp has read the variables before main runs, and
// restarting every quiet run would cost its start-up (0.2 s) again.
// A user's OMP_WAIT_POLICY or GOMP_SPINCOUNT is left alone, and so is a process where
// /proc/self/exe cannot be run or is not this program (under valgrind it is the tool, which
// cannot be run directly).
// Call it first thing in main.
inline constexpr const char* kSpinCount = "300";
inline constexpr const char* kQuietSpinVariable = "TALUS_QUIET_SPINCOUNT";
// Whether GOMP_SPINCOUNT is the driver's quiet spin (kQuietSpinVariable holds the same value).
bool spin_is_drivers();
void bound_openmp_spin(char** argv);

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
