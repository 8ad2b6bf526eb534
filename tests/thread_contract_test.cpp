// The solver's thread contract and determinism (solver/parallel/threads.hpp). ctest runs this file
// under OMP_NUM_THREADS=8 (tests/CMakeLists.txt); each test also sets OpenMP's count itself,
// so that it means the same when run by hand. A simulation built for T threads runs T threads
// whatever OpenMP's setting, and the same T gives bit-identical results run after run.
#include <gtest/gtest.h>
#include <omp.h>
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "solver/parallel/parallel.hpp"
#include "solver/step/step.hpp"
#include "solver/stress/stress.hpp"
#include "support/test_support.hpp"

using namespace talus;
using namespace talus::solver;
using talus::testing::add_box_body;
using talus::testing::elastic;
using talus::testing::fix_base_roll_sides;
using talus::testing::rectangle_mesh;
using talus::testing::set_run;

namespace {

Material sand() {
  Material m = talus::testing::mohr_coulomb(1800, 1e7, 0.3, 30, 1e3);
  m.name = "sand";
  return m;
}

// Every pass of the step at work: two bodies in frictional contact (a Mohr-Coulomb block
// resting on an elastic one), EVS, damping, on a fixed base with roller sides.
Model busy_model() {
  Model model = rectangle_mesh(0, 0, 24, 16, 0.05);
  add_box_body(model, "base", elastic(2000, 5e6, 0.3), 0.0, 1.2, 0.0, 0.3);
  add_box_body(model, "block", sand(), 0.3, 0.8, 0.3, 0.6);
  fix_base_roll_sides(model);
  model.contact.enabled = true;
  model.contact.friction = 0.4;
  set_run(model, 1.0, Eigen::Vector2d(0, -9.81));
  model.run.evs = true;
  model.run.damping = 0.05;
  return model;
}

void run_steps(Simulation& sim, int steps) {
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(step(sim, 0.5 * stable_time_step(sim, 0.5)));
    if (sim.steps % 25 == 0) sort_particles(sim);
  }
}

// Differing values between the two simulations' particle states (model order).
long differing_values(const Simulation& a, const Simulation& b) {
  const Particles& P = a.particles;
  const Particles& Q = b.particles;
  std::vector<long> where(P.size());
  for (std::size_t q = 0; q < Q.size(); ++q) where[Q.id[q]] = static_cast<long>(q);
  long differing = 0;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const long q = where[P.id[p]];
    differing += (P.x[p] != Q.x[q]) + (P.v[p] != Q.v[q]) + (P.sigma[p] != Q.sigma[q]) + (P.volume[p] != Q.volume[q]) +
                 (P.eps_p[p] != Q.eps_p[q]);
  }
  return differing;
}

double largest_position_difference(const Simulation& a, const Simulation& b) {
  std::vector<Vec2> x(a.particles.size());
  for (std::size_t q = 0; q < b.particles.size(); ++q) x[b.particles.id[q]] = b.particles.x[q];
  double worst = 0;
  for (std::size_t p = 0; p < a.particles.size(); ++p)
    worst = std::max(worst, (a.particles.x[p] - x[a.particles.id[p]]).norm());
  return worst;
}

}  // namespace

TEST(ThreadContract, BuiltForTwoThreadsRunsTwoUnderAnyOpenMPSetting) {
  const Model model = busy_model();
  omp_set_num_threads(2);
  Simulation two = make_simulation(model, 2);
  run_steps(two, 120);

  omp_set_num_threads(8);  // what OMP_NUM_THREADS=8 sets; the buffers are for 2
  Simulation under_eight = make_simulation(model, 2);
  run_steps(under_eight, 120);
  EXPECT_EQ(under_eight.config.threads, 2);
  EXPECT_EQ(differing_values(two, under_eight), 0) << "a simulation built for 2 threads ran with another count";
}

TEST(ThreadContract, BuiltForEightThreadsRunsOnAnyMachine) {
  const Model model = busy_model();
  omp_set_num_threads(1);
  Simulation one = make_simulation(model, 1);
  run_steps(one, 120);
  Simulation eight = make_simulation(model, 8);
  run_steps(eight, 120);
  EXPECT_EQ(eight.scratch.buffers.size(), 8u);
  // Another thread count adds the same terms in another order: equal to round-off.
  EXPECT_LT(largest_position_difference(one, eight), 1e-12);
  EXPECT_GT(largest_position_difference(one, Simulation(make_simulation(model, 1))), 1e-4)
      << "the block did not move: the comparison above would prove nothing";
}

// The stress update's split (OwnerFirstChunks): every particle exactly once, whether the team
// has the threads it was built for, fewer (OMP_THREAD_LIMIT), or the particles are fewer than a
// chunk or than the threads.
TEST(ThreadContract, OwnerFirstChunksVisitEveryIndexOnce) {
  for (const long n : {0L, 1L, 3L, 255L, 256L, 257L, 10007L}) {
    for (const int threads : {1, 2, 3, 8}) {
      for (const int team : {1, threads}) {
        std::vector<std::atomic<int>> visits(static_cast<std::size_t>(n));
        for (auto& v : visits) v.store(0);
        OwnerFirstChunks chunks(n, threads, 256);
#pragma omp parallel num_threads(team)
        chunks.for_each([&](long begin, long end) {
          for (long i = begin; i < end; ++i) visits[static_cast<std::size_t>(i)].fetch_add(1);
        });
        long wrong = 0;
        for (const auto& v : visits) wrong += v.load() != 1;
        EXPECT_EQ(wrong, 0) << n << " indices, built for " << threads << " threads, team of " << team;
      }
    }
  }
}

TEST(Determinism, SameThreadCountGivesBitIdenticalRuns) {
  const Model model = busy_model();
  for (int threads : {2, 3}) {
    SCOPED_TRACE(threads);
    omp_set_num_threads(8);
    Simulation first = make_simulation(model, threads), second = make_simulation(model, threads);
    run_steps(first, 150);
    run_steps(second, 150);
    EXPECT_EQ(differing_values(first, second), 0);
    const Energies a = energies(first), b = energies(second);
    EXPECT_EQ(a.kinetic, b.kinetic);
    EXPECT_EQ(a.grid_kinetic, b.grid_kinetic);
    EXPECT_EQ(a.strain, b.strain);
    EXPECT_GT(largest_position_difference(first, make_simulation(model, threads)), 1e-4);
  }
}

TEST(ThreadChoice, SmallProblemsRunOnOneThreadLargeOnTheCores) {
  omp_set_num_threads(8);
  const ThreadChoice asked = choose_threads(100, 3);
  EXPECT_EQ(asked.threads, 3);
  EXPECT_EQ(asked.why, "--threads");
  // Below two threads' worth of particles: one thread, whatever the machine.
  EXPECT_EQ(choose_threads(2 * kParticlesPerThread - 1, 0).threads, 1);
  EXPECT_EQ(choose_threads(1, 0).threads, 1);
  // Above: no more threads than cores (OMP_NUM_THREADS, when set, stands for the cores).
  const int cores = std::getenv("OMP_NUM_THREADS") ? 8 : std::min(available_cores(), 8);
  EXPECT_EQ(choose_threads(1000 * kParticlesPerThread, 0).threads, cores);
  EXPECT_EQ(choose_threads(3 * kParticlesPerThread, 0).threads, std::min(cores, 3));
  EXPECT_EQ(choose_threads(48812, 0).why.rfind("auto: 48,812 particles, ", 0), 0u) << choose_threads(48812, 0).why;
  if (!std::getenv("OMP_NUM_THREADS")) {
    omp_set_num_threads(1);  // a program that asked OpenMP for one thread gets one
    EXPECT_EQ(choose_threads(1000 * kParticlesPerThread, 0).threads, 1);
  }
}

// A busy machine at the start (what bound_openmp_spin hands over in TALUS_BUSY_CORES): the
// automatic count leaves the busy cores to the other programs while one stays free, takes all
// of them when none does (the fair share; ThreadPinning keeps the threads apart), and says so;
// --threads still wins.
TEST(ThreadChoice, LeavesTheCoresThatWereBusyAtTheStart) {
  omp_set_num_threads(8);
  const int cores = std::getenv("OMP_NUM_THREADS") ? 8 : std::min(available_cores(), 8);
  setenv(kBusyCoresVariable, "1", 1);
  const ThreadChoice one_busy = choose_threads(1000 * kParticlesPerThread, 0);
  setenv(kBusyCoresVariable, "64", 1);
  const ThreadChoice all_busy = choose_threads(1000 * kParticlesPerThread, 0);
  const ThreadChoice asked = choose_threads(1000 * kParticlesPerThread, 2);
  unsetenv(kBusyCoresVariable);
  EXPECT_EQ(one_busy.threads, cores > 1 ? cores - 1 : 1);
  EXPECT_NE(one_busy.why.find(", 1 busy"), std::string::npos) << one_busy.why;
  EXPECT_EQ(all_busy.threads, cores);
  EXPECT_NE(all_busy.why.find(", 64 busy"), std::string::npos) << all_busy.why;
  EXPECT_EQ(asked.threads, 2);
  EXPECT_EQ(choose_threads(1000 * kParticlesPerThread, 0).threads, cores);
  EXPECT_EQ(busy_cores_at_start(), 0);
}

// The driver's spin is told apart from a user's GOMP_SPINCOUNT by its mark: with the driver's,
// talus still looks at the machine (and needs no restart); a user's turns the look off.
TEST(ThreadChoice, TheDriversSpinIsToldApartFromTheUsers) {
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  const char* mark = std::getenv(kDriverSpinVariable);
  const std::string spin_before = spin ? spin : "", mark_before = mark ? mark : "";
  setenv("GOMP_SPINCOUNT", "30000", 1);
  setenv(kDriverSpinVariable, "30000", 1);
  const bool drivers = spin_is_drivers();
  setenv("GOMP_SPINCOUNT", "5000", 1);  // the user's, though the mark is there
  const bool users = spin_is_drivers();
  unsetenv(kDriverSpinVariable);
  setenv("GOMP_SPINCOUNT", "30000", 1);  // the user's, with the driver's number
  const bool unmarked = spin_is_drivers();
  unsetenv("GOMP_SPINCOUNT");
  const bool none = spin_is_drivers();
  if (spin) setenv("GOMP_SPINCOUNT", spin_before.c_str(), 1);
  if (mark) setenv(kDriverSpinVariable, mark_before.c_str(), 1);
  EXPECT_TRUE(drivers);
  EXPECT_FALSE(users);
  EXPECT_FALSE(unmarked);
  EXPECT_FALSE(none);
}

namespace {

// The lowest CPU each thread of a team of `threads` may run on, by thread number, and how many.
std::vector<int> cpus_of_team(int threads, std::vector<int>* counts = nullptr) {
  std::vector<int> first(static_cast<std::size_t>(threads), -1), count(static_cast<std::size_t>(threads), 0);
#pragma omp parallel num_threads(threads)
  {
    cpu_set_t mask;
    CPU_ZERO(&mask);
    if (pthread_getaffinity_np(pthread_self(), sizeof mask, &mask) == 0) {
      const auto t = static_cast<std::size_t>(omp_get_thread_num());
      count[t] = CPU_COUNT(&mask);
      for (int c = CPU_SETSIZE - 1; c >= 0; --c)
        if (CPU_ISSET(c, &mask)) first[t] = c;
    }
  }
  if (counts) *counts = count;
  return first;
}

}  // namespace

// A team that takes every CPU of the mask is pinned one thread per CPU for the time loop and
// gets its mask back afterwards; a smaller team, or one whose waits sleep, is left alone.
TEST(ThreadChoice, ATeamOfEveryCpuIsPinnedOneThreadPerCpuAndReleased) {
  const int cpus = available_cores();
  if (cpus < 2 || std::getenv("OMP_PROC_BIND") || std::getenv("OMP_PLACES"))
    GTEST_SKIP() << "needs 2 or more CPUs and no OMP_PROC_BIND/OMP_PLACES";
  // Waits that sleep at once (the test suite's OMP_WAIT_POLICY=passive) pin nothing.
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  const std::string policy_before = policy ? policy : "";
  setenv("OMP_WAIT_POLICY", "Passive", 1);
  const bool pinned_passive = ThreadPinning(cpus).pinned();
  unsetenv("OMP_WAIT_POLICY");
  std::vector<int> counts;
  {
    const ThreadPinning pinning(cpus);
    if (policy) setenv("OMP_WAIT_POLICY", policy_before.c_str(), 1);
    EXPECT_FALSE(pinned_passive);
    ASSERT_TRUE(pinning.pinned());
    std::vector<int> first = cpus_of_team(cpus, &counts);
    for (int n : counts) EXPECT_EQ(n, 1);
    std::sort(first.begin(), first.end());
    EXPECT_TRUE(std::adjacent_find(first.begin(), first.end()) == first.end()) << "two threads on one CPU";
  }
  cpus_of_team(cpus, &counts);
  for (int n : counts) EXPECT_EQ(n, cpus);  // released
  EXPECT_FALSE(ThreadPinning(1).pinned());
  if (cpus > 2) {
    EXPECT_FALSE(ThreadPinning(cpus - 1).pinned());
  }
}

TEST(ThreadContract, AMovedModelBuildsTheSameSimulationAndKeepsNoParticles) {
  const Model model = busy_model();
  Model handed_over = model;
  Simulation copied = make_simulation(model, 2);
  Simulation moved = make_simulation(std::move(handed_over), 2);
  EXPECT_EQ(handed_over.particle_count(), 0u);
  EXPECT_TRUE(handed_over.mass.empty() && handed_over.stress.empty() && handed_over.element.empty());
  EXPECT_EQ(handed_over.triangles.size(), model.triangles.size());  // the mesh and settings stay
  EXPECT_EQ(moved.config.initial_volume, copied.config.initial_volume);
  run_steps(copied, 60);
  run_steps(moved, 60);
  EXPECT_EQ(differing_values(copied, moved), 0);
  EXPECT_GT(largest_position_difference(moved, make_simulation(model, 2)), 1e-5) << "nothing moved";
}

TEST(ThreadContract, PhaseTimerTimesEveryStepAndChangesNothing) {
  const Model model = busy_model();
  Simulation timed = make_simulation(model, 2), untimed = make_simulation(model, 2);
  PhaseTimes times;
  timed.scratch.phase_times = &times;
  run_steps(timed, 50);
  run_steps(untimed, 50);
  EXPECT_EQ(differing_values(timed, untimed), 0);
  EXPECT_EQ(times.steps, 50);
  for (int phase : {PhaseTimes::ToGrid, PhaseTimes::Contact, PhaseTimes::CellSums, PhaseTimes::Stresses})
    EXPECT_GT(times.seconds[phase], 0) << PhaseTimes::kNames[phase];
  EXPECT_EQ(times.seconds[PhaseTimes::GridVelocity], 0) << "FLIP has no Lagrangian grid velocity phase";
}
