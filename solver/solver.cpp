#include "solver/solver.hpp"

#include <omp.h>

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
#include "solver/parallel.hpp"
#include "solver/results.hpp"
#include "solver/solve_observers.hpp"
#include "solver/step.hpp"

namespace talus::solver {
namespace {

using Clock = std::chrono::steady_clock;

std::string point(const Vec2& x) {
  std::ostringstream s;
  s << "(" << x.x() << ", " << x.y() << ") m";
  return s.str();
}

// Why the step failed: a particle left the domain (after a blow-up, when the kinetic energy is
// beyond what the run can have: an unstable run flings particles out before anything else
// shows), or a state became non-finite.
std::string step_failure(const Simulation& sim, const BlowUpBudget& budget) {
  const Particles& P = sim.particles;
  const Scratch& s = sim.scratch;
  std::ostringstream where;
  where << " at step " << sim.steps << ", t = " << sim.time << " s";
  const bool blown_up = budget.exceeded_by(energies(sim));
  if (s.lost_particle >= 0)
    return std::string(blown_up ? "numerical blow-up (kinetic energy beyond what gravity can supply): " : "") +
           "particle " + std::to_string(P.id[s.lost_particle]) + " left the domain at " + point(P.x[s.lost_particle]) +
           where.str() + (blown_up ? " (try a smaller run.cfl)" : "");
  return "numerical blow-up: particle " + std::to_string(P.id[s.bad_particle]) + " near " +
         point(P.x[s.bad_particle]) + " has a non-finite or inverted state" + where.str() + " (try a smaller run.cfl)";
}

// solve(); with `owned` (the same object as model, given up by its owner) the particle columns
// move from the model into the simulation (make_simulation(Model&&)) on a fresh run.
SolveSummary run_solve(const Model& model, Model* owned, const SolveOptions& options, std::ostream& log) {
  if (!(options.checkpoint_interval >= 0) || !std::isfinite(options.checkpoint_interval))
    throw Error("--checkpoint-interval: expected a finite time >= 0 s");
  const RunSettings& run = model.run;
  if (options.checkpoint_interval > 0 && run.end_time / options.checkpoint_interval > kMaxFrames) {
    std::ostringstream message;
    message << "--checkpoint-interval: got " << options.checkpoint_interval << " s: "
            << run.end_time / options.checkpoint_interval << " checkpoints over run.end_time = " << run.end_time
            << " s, at most " << kMaxFrames << " (raise --checkpoint-interval)";
    throw Error(message.str());
  }
  const auto setup_start = Clock::now();
  StopSignals stop_signals;
  const std::size_t particles = model.particle_count();
  const ThreadChoice threads = choose_threads(static_cast<long>(particles), options.threads);
  Fingerprints fingerprints = model_fingerprints(model);
  Simulation sim;
  LoopState loop;
  std::optional<ResultsWriter> writer;
  const std::string checkpoint = checkpoint_path(options.out_dir);
  if (options.restart) {
    sim = make_simulation(model, threads.threads);
    ResultsPosition position;
    read_checkpoint(options.out_dir, model, sim, loop, position);
    writer.emplace(options.out_dir, model, position);
    log << "restarting from " << checkpoint << " at step " << sim.steps << ", t = " << sim.time << " s ("
        << position.frames << " frames kept)\n";
  } else {
    std::error_code ignored;  // a checkpoint of an earlier run would not match the new results
    std::filesystem::remove(checkpoint, ignored);
    if (owned) {
      // The results' initial state comes from the model's columns before they move.
      writer.emplace(options.out_dir, model);
      try {
        sim = make_simulation(std::move(*owned), threads.threads);
      } catch (...) {  // a bad model leaves no results behind
        const std::string results = writer->path(), xdmf = writer->xdmf_path();
        writer.reset();
        std::filesystem::remove(results, ignored);
        std::filesystem::remove(xdmf, ignored);
        throw;
      }
    } else {
      sim = make_simulation(model, threads.threads);
      writer.emplace(options.out_dir, model);
    }
    const Energies initial = energies(sim);
    const BlowUpBudget budget = BlowUpBudget::starting_from(sim, initial);
    loop.budget = budget.budget();
    loop.budget_limit = budget.limit();
    loop.next_output = run.output_interval;
    writer->record_history(sim, initial);
    writer->write_frame(sim);
  }
  sim.scratch.phase_times = options.phase_times;

  // The observers, in the order they see each step.
  const double tolerance = 1e-9 * run.end_time;
  ParticleSorter sorter;
  BlowUpBudget budget(loop.budget, loop.budget_limit);
  HistoryRecorder history(*writer, run.history_interval);
  RestDetector rest(loop, run.rest_ratio, run.rest_window);
  StepLimit step_limit(run.max_steps);
  FrameWriter frames(*writer, loop, run.output_interval, tolerance);
  ProgressLine progress(options.progress, run.end_time);
  Checkpointer checkpoints(options.out_dir, std::move(fingerprints), *writer, loop, options.checkpoint_interval, tolerance, sim.time);
  const std::vector<Observer*> observers{&sorter, &budget,   &history,     &rest,        &step_limit,
                                         &frames, &progress, &checkpoints, &stop_signals};

  const auto start = Clock::now();
  const double setup_seconds = std::chrono::duration<double>(start - setup_start).count();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  const LoopEnd end = run_time_loop(sim, run.cfl, run.end_time, observers);
  progress.done();

  if (end.kind == LoopEnd::StepFailed || end.kind == LoopEnd::Failed || end.kind == LoopEnd::BadTimeStep) {
    const std::string message = end.kind == LoopEnd::StepFailed ? step_failure(sim, budget) : end.reason;
    writer->finish(sim.steps, seconds(), false);
    throw Error("solve: " + message + "; " + std::to_string(writer->frames()) + " frames kept in " + writer->path());
  }
  if (const int signal = stop_signals.signal()) {
    // The checkpoint records the frames of the uninterrupted run only; the last frame
    // written after it shows where the run stopped, and a restart drops it.
    checkpoints.write(sim);
    if (!frames.written_at(sim)) frames.write(sim);
    writer->finish(sim.steps, seconds(), false);
    std::ostringstream message;
    message << "interrupted by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << " at step " << sim.steps
            << ", t = " << sim.time << " s: " << writer->frames() << " frames kept in " << writer->path()
            << ", checkpoint in " << checkpoint << " (continue with --restart)";
    throw Interrupted(signal, message.str());
  }
  // Stopped at rest or by the step limit between output times: the state it stopped in.
  if (end.kind == LoopEnd::Stopped && !frames.written_at(sim)) frames.write(sim);

  SolveSummary summary;
  summary.particles = particles;
  summary.threads = sim.config.threads;
  summary.thread_choice = threads.why;
  summary.stopped_at_rest = rest.at_rest(sim);
  summary.loop_seconds = seconds();
  summary.setup_seconds = setup_seconds;
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

}  // namespace

SolveSummary solve(const Model& model, const SolveOptions& options, std::ostream& log) {
  return run_solve(model, nullptr, options, log);
}

SolveSummary solve(Model&& model, const SolveOptions& options, std::ostream& log) {
  return run_solve(model, &model, options, log);
}

void print_summary(const SolveSummary& s, std::ostream& out) {
  out << "solved: " << s.steps << " steps, " << s.particles << " particles, " << s.simulated_time
      << " s simulated, time loop " << std::fixed << std::setprecision(2) << s.loop_seconds << " s on " << s.threads
      << (s.threads == 1 ? " thread" : " threads")
      << (s.thread_choice.empty() ? "" : " (" + s.thread_choice + ")") << ", " << std::scientific << std::setprecision(3)
      << s.particle_updates_per_second() << " particle-updates/s, " << std::defaultfloat << s.frames << " frames\n";
}

}  // namespace talus::solver
