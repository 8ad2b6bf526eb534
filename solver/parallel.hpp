// The thread contract: a simulation is built for a number of threads (its per-thread buffers
// are sized for them), and every parallel region of the solver asks for exactly that many
// with num_threads(threads), whatever OMP_NUM_THREADS or omp_set_num_threads say. Work is split
// with static schedules and every floating-point sum is taken in an order fixed by the thread
// count, so the same thread count gives bit-identical results run after run.
#pragma once
#include <omp.h>

#include <algorithm>
#include <vector>

namespace talus::solver {

// Thread t's share [begin, end) of [0, n) when split into `threads` contiguous chunks.
inline void chunk_of(long n, int threads, int t, long& begin, long& end) {
  begin = n * t / threads;
  end = n * (t + 1) / threads;
}

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
