#include "solver/solver.hpp"

#include <omp.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "common/error.hpp"
#include "solver/checkpoint.hpp"
#include "solver/results.hpp"
#include "solver/simulation.hpp"

namespace talus::solver {
namespace {

using Clock = std::chrono::steady_clock;

// Keeping particles ordered by element keeps the grid accesses of neighbouring particles close
// in memory; particles move by less than an element per step, so this need not be done often.
constexpr long kSortInterval = 25;

std::string point(const Vec2& x) {
  std::ostringstream s;
  s << "(" << x.x() << ", " << x.y() << ") m";
  return s.str();
}

// The most energy the run can have without a numerical source: the initial kinetic and strain
// energy plus everything gravity can release by bringing each particle to the lowest node.
double energy_budget(const Simulation& sim, const Energies& initial) {
  double lowest = std::numeric_limits<double>::infinity();
  const Vec2 down = sim.gravity.norm() > 0 ? Vec2(sim.gravity.normalized()) : Vec2(0, -1);
  for (const auto& x : sim.mesh.nodes) lowest = std::min(lowest, -down.dot(x));
  double release = 0;
  const Particles& P = sim.particles;
  for (std::size_t p = 0; p < P.moving_count; ++p) release += P.m[p] * sim.gravity.norm() * (-down.dot(P.x[p]) - lowest);
  return initial.kinetic + initial.strain + release;
}

class Progress {
 public:
  Progress(bool enabled, double end_time) : enabled_(enabled && isatty(STDERR_FILENO)), end_time_(end_time) {}
  void update(const Simulation& sim, double dt, Clock::time_point start) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (now - last_ < std::chrono::milliseconds(250)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start).count();
    const double eta = sim.time > 0 ? elapsed * (end_time_ - sim.time) / sim.time : 0;
    std::fprintf(stderr, "\r  step %ld  t = %.4g / %.4g s  dt = %.3e s  ETA %.0f s   ", sim.steps, sim.time,
                 end_time_, dt, eta);
    std::fflush(stderr);
    shown_ = true;
  }
  void done() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  bool enabled_;
  double end_time_;
  bool shown_ = false;
  Clock::time_point last_{};
};

// The signal that asked the run to stop (0: none). Set by the handler, read after each step.
volatile std::sig_atomic_t stop_signal = 0;

extern "C" void on_stop_signal(int signal) { stop_signal = signal; }

// SIGINT and SIGTERM set stop_signal while a solve runs; the previous handlers come back after.
class StopSignals {
 public:
  StopSignals() {
    stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // file writes in progress continue rather than fail with EINTR
    sigaction(SIGINT, &action, &previous_interrupt_);
    sigaction(SIGTERM, &action, &previous_terminate_);
  }
  ~StopSignals() {
    sigaction(SIGINT, &previous_interrupt_, nullptr);
    sigaction(SIGTERM, &previous_terminate_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction previous_interrupt_ {};
  struct sigaction previous_terminate_ {};
};

}  // namespace

SolveSummary solve(const Model& model, const SolveOptions& options, std::ostream& log) {
  if (options.threads > 0) omp_set_num_threads(options.threads);
  if (!(options.checkpoint_interval >= 0) || !std::isfinite(options.checkpoint_interval))
    throw Error("--checkpoint-interval: expected a finite time >= 0 s");
  const RunSettings& run = model.run;
  const StopSignals stop_signals;
  Simulation sim = make_simulation(model, omp_get_max_threads());
  LoopState loop;
  std::optional<ResultsWriter> writer;
  const std::string checkpoint = checkpoint_path(options.out_dir);
  if (options.restart) {
    ResultsPosition position;
    read_checkpoint(options.out_dir, model, sim, loop, position);
    writer.emplace(options.out_dir, model, position);
    log << "restarting from " << checkpoint << " at step " << sim.steps << ", t = " << sim.time << " s ("
        << position.frames << " frames kept)\n";
  } else {
    std::error_code ignored;  // a checkpoint of an earlier run would not match the new results
    std::filesystem::remove(checkpoint, ignored);
    writer.emplace(options.out_dir, model);
    const Energies initial = energies(sim);
    loop.budget = energy_budget(sim, initial);
    // Round-off in the budget's own terms, so a body at rest under no load is no blow-up.
    loop.budget_limit = 2 * loop.budget + 1e-9 * std::abs(initial.potential) + 1e-12;
    loop.next_output = run.output_interval;
    writer->record_history(sim, initial);
    writer->write_frame(sim);
  }
  // Periodic checkpoints at multiples of the interval; they change what is on disk, not the run.
  const double interval = options.checkpoint_interval;
  loop.next_checkpoint = interval > 0 ? interval * (std::floor(sim.time / interval) + 1)
                                      : std::numeric_limits<double>::infinity();

  SolveSummary summary;
  summary.particles = model.particle_count();
  Progress progress(options.progress, run.end_time);
  const auto start = Clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  auto fail = [&](const std::string& message) {
    progress.done();
    writer->finish(sim.steps, seconds(), false);
    throw Error("solve: " + message + "; " + std::to_string(writer->frames()) + " frames kept in " + writer->path());
  };

  const double end_tolerance = 1e-9 * run.end_time;
  while (sim.time < run.end_time - end_tolerance) {
    double dt = stable_time_step(sim, run.cfl);
    if (!std::isfinite(dt) || dt <= 0) fail("non-finite time step at t = " + std::to_string(sim.time) + " s");
    dt = std::min(dt, loop.next_output - sim.time);  // land on output times exactly
    if (!step(sim, dt)) {
      const Particles& P = sim.particles;
      std::ostringstream where;
      where << " at step " << sim.steps << ", t = " << sim.time << " s";
      // An unstable run flings particles out of the domain before anything else shows: an
      // energy beyond what the run can have tells a blow-up from a real exit.
      const Energies energy = energies(sim);
      const bool blown_up = !std::isfinite(energy.kinetic) || energy.kinetic > loop.budget_limit;
      if (sim.lost_particle >= 0)
        fail(std::string(blown_up ? "numerical blow-up (kinetic energy beyond what gravity can supply): " : "") +
             "particle " + std::to_string(P.id[sim.lost_particle]) + " left the domain at " +
             point(P.x[sim.lost_particle]) + where.str() + (blown_up ? " (try a smaller run.cfl)" : ""));
      fail("numerical blow-up: particle " + std::to_string(P.id[sim.bad_particle]) + " near " +
           point(P.x[sim.bad_particle]) + " has a non-finite or inverted state" + where.str() +
           " (try a smaller run.cfl)");
    }
    if (sim.steps % kSortInterval == 0) sort_particles(sim);

    const bool frame_due = sim.time >= loop.next_output - end_tolerance;
    if (sim.steps % run.history_interval == 0 || frame_due) {
      const Energies energy = energies(sim);
      if (!std::isfinite(energy.kinetic + energy.grid_kinetic) ||
          std::max(energy.kinetic, energy.grid_kinetic) > loop.budget_limit) {
        std::ostringstream message;
        message << "numerical blow-up at step " << sim.steps << ", t = " << sim.time << " s: kinetic energy "
                << energy.kinetic << " J/m exceeds the " << loop.budget
                << " J/m that gravity and the initial state can supply (try a smaller run.cfl)";
        fail(message.str());
      }
      writer->record_history(sim, energy);
      // Rest is judged on the grid's kinetic energy: the motion of the material itself.
      if (energy.grid_kinetic > loop.peak_kinetic) loop.peak_kinetic = energy.grid_kinetic, loop.peak_time = sim.time;
      if (run.rest_ratio > 0 && loop.peak_kinetic > 0 && sim.time > loop.peak_time &&
          energy.grid_kinetic < run.rest_ratio * loop.peak_kinetic) {
        if (loop.rest_since < 0) loop.rest_since = sim.time;
      } else {
        loop.rest_since = -1;
      }
    }
    const bool at_rest = loop.rest_since >= 0 && sim.time - loop.rest_since >= run.rest_window;
    const bool out_of_steps = run.max_steps > 0 && sim.steps >= run.max_steps;
    const bool frame_written = frame_due || at_rest || out_of_steps;
    if (frame_written) {
      writer->write_frame(sim);
      while (loop.next_output <= sim.time + end_tolerance) loop.next_output += run.output_interval;
    }
    progress.update(sim, dt, start);
    if (at_rest || out_of_steps) {
      summary.stopped_at_rest = at_rest;
      break;
    }
    if (sim.time >= loop.next_checkpoint - end_tolerance) {
      while (loop.next_checkpoint <= sim.time + end_tolerance) loop.next_checkpoint += interval;
      write_checkpoint(options.out_dir, model, sim, loop, writer->sync());
    }
    if (const int signal = stop_signal) {
      // The checkpoint records the frames of the uninterrupted run only; the last frame
      // written after it shows where the run stopped, and a restart drops it.
      progress.done();
      write_checkpoint(options.out_dir, model, sim, loop, writer->sync());
      if (!frame_written) writer->write_frame(sim);
      writer->finish(sim.steps, seconds(), false);
      std::ostringstream message;
      message << "interrupted by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << " at step " << sim.steps
              << ", t = " << sim.time << " s: " << writer->frames() << " frames kept in " << writer->path()
              << ", checkpoint in " << checkpoint << " (continue with --restart)";
      throw Interrupted(signal, message.str());
    }
  }
  progress.done();
  summary.loop_seconds = seconds();
  summary.steps = sim.steps;
  summary.simulated_time = sim.time;
  writer->finish(sim.steps, summary.loop_seconds, true);
  summary.frames = writer->frames();
  std::error_code ignored;  // the results are complete: nothing left to restart
  std::filesystem::remove(checkpoint, ignored);
  if (summary.stopped_at_rest)
    log << "at rest at t = " << sim.time << " s (kinetic energy below " << run.rest_ratio * 100 << "% of its peak for "
        << run.rest_window << " s)\n";
  return summary;
}

void print_summary(const SolveSummary& s, std::ostream& out) {
  out << "solved: " << s.steps << " steps, " << s.particles << " particles, " << s.simulated_time
      << " s simulated, time loop " << std::fixed << std::setprecision(2) << s.loop_seconds << " s, "
      << std::scientific << std::setprecision(3) << s.particle_updates_per_second() << " particle-updates/s, "
      << std::defaultfloat << s.frames << " frames\n";
}

}  // namespace talus::solver
