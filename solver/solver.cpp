#include "solver/solver.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <new>
#include <optional>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "common/error.hpp"
#include "solver/io/io.hpp"
#include "solver/parallel/parallel.hpp"
#include "solver/solve_observers.hpp"
#include "solver/step/step.hpp"

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
std::string local_step_failure(const Simulation& sim, bool blown_up) {
  const Particles& P = sim.particles;
  const Scratch& s = sim.scratch;
  std::ostringstream where;
  where << " at step " << sim.steps << ", t = " << sim.time << " s";
  if (s.lost_particle >= 0)
    return std::string(blown_up ? "numerical blow-up (kinetic energy beyond what gravity can supply): " : "") +
           "particle " + std::to_string(P.id[s.lost_particle]) + " left the domain at " + point(P.x[s.lost_particle]) +
           where.str() + (blown_up ? " (try a smaller run.cfl)" : "");
  return "numerical blow-up: particle " + std::to_string(P.id[s.bad_particle]) + " near " +
         point(P.x[s.bad_particle]) + " has a non-finite or inverted state" + where.str() + " (try a smaller run.cfl)";
}

// On several ranks every rank calls it: the message is that of the first rank where the step
// failed.
std::string step_failure(const Simulation& sim, const BlowUpBudget& budget) {
  const bool blown_up = budget.exceeded_by(energies(sim));
  const Scratch& s = sim.scratch;
  const bool here = s.lost_particle >= 0 || s.bad_particle >= 0;
  if (!sim.domain.distributed()) return local_step_failure(sim, blown_up);
  std::string message = here ? local_step_failure(sim, blown_up) : std::string();
  mpi::broadcast(message, mpi::first_rank_with(here));
  return message;
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
  // Each rank of a distributed solve threads its own share of the particles.
  const ThreadChoice threads = choose_threads(static_cast<long>(particles) / mpi::size(), options.threads);
  Fingerprints fingerprints = model_fingerprints(model);
  // Several MPI ranks (domain.hpp): every rank builds the whole simulation from the model and
  // keeps its share; rank 0 alone writes results.h5 (but for the frames' rows, which every rank
  // writes with the parallel HDF5) and the checkpoints. Errors every rank meets alike are
  // SharedErrors; on_root shares rank 0's.
  const bool distributed = mpi::distributed();
  const bool root = mpi::rank() == 0;
  auto shared = [&](auto&& build) {
    try {
      build();
    } catch (const SharedError&) {
      throw;
    } catch (const Error& error) {
      if (distributed) throw SharedError(error.what());
      throw;
    }
  };
  Simulation sim;
  LoopState loop;
  std::optional<ResultsWriter> writer;
  // Several ranks with the parallel HDF5: each rank writes its rows of the frames (made before
  // the model's columns move into the simulation).
  std::optional<RankFrames> rank_frames;
  auto start_rank_frames = [&] {
    if (RankFrames::wanted(writer ? &*writer : nullptr))
      rank_frames.emplace(model, (std::filesystem::path(options.out_dir) / "results.h5").string());
  };
  const std::string checkpoint = checkpoint_path(options.out_dir);
  on_root([&] {
    // What a checkpoint write that was killed left (it is written to NAME.tmp and renamed): this
    // solve holds the folder's lock, so no one else is writing it.
    std::error_code ignored;
    std::filesystem::remove(checkpoint + ".tmp", ignored);
  });
  if (options.restart) {
    shared([&] {
      sim = make_simulation(model, threads.threads);
      ResultsPosition position;
      read_checkpoint(options.out_dir, model, sim, loop, position);
      on_root([&] { writer.emplace(options.out_dir, model, position); });
      start_rank_frames();
      log << "restarting from " << checkpoint << " at step " << sim.steps << ", t = " << sim.time << " s ("
          << position.frames << " frames kept)\n";
    });
    distribute(sim);
  } else {
    on_root([&] {
      std::error_code ignored;  // a checkpoint of an earlier run would not match the new results
      std::filesystem::remove(checkpoint, ignored);
    });
    // A bad model, or memory that runs out before the first frame is written, leaves no results
    // behind.
    try {
      // The results' initial state comes from the model's columns before they move.
      on_root([&] { writer.emplace(options.out_dir, model); });
      start_rank_frames();
      shared([&] { sim = owned ? make_simulation(std::move(*owned), threads.threads) : make_simulation(model, threads.threads); });
      distribute(sim);
      const Energies initial = energies(sim);
      const BlowUpBudget budget = BlowUpBudget::starting_from(sim, initial);
      loop.budget = budget.budget();
      loop.budget_limit = budget.limit();
      loop.budget_supply = budget.supply();
      loop.start_potential = budget.start_potential();
      loop.next_output = run.output_interval;
      if (writer) writer->record_history(sim, initial);
      FrameWriter(writer ? &*writer : nullptr, loop, run.output_interval, 0, rank_frames ? &*rank_frames : nullptr)
          .write(sim);
    } catch (...) {
      rank_frames.reset();
      if (writer) {
        std::error_code ignored;
        const std::string results = writer->path(), xdmf = writer->xdmf_path();
        writer.reset();
        std::filesystem::remove(results, ignored);
        std::filesystem::remove(xdmf, ignored);
      }
      throw;
    }
    loop.next_output = run.output_interval;
  }
  sim.scratch.phase_times = options.phase_times;

  // The observers, in the order they see each step.
  const double tolerance = 1e-9 * run.end_time;
  ParticleSorter sorter;
  BlowUpBudget budget(loop.budget, loop.budget_limit, loop.budget_supply, loop.start_potential);
  ResultsWriter* results = writer ? &*writer : nullptr;
  HistoryRecorder history(results, run.history_interval);
  RestDetector rest(loop, run.rest_ratio, run.rest_window);
  StepLimit step_limit(run.max_steps);
  FrameWriter frames(results, loop, run.output_interval, tolerance, rank_frames ? &*rank_frames : nullptr);
  ProgressLine progress(options.progress && root, run.end_time);
  Checkpointer checkpoints(options.out_dir, std::move(fingerprints), results, loop, options.checkpoint_interval, tolerance, sim.time);
  const std::vector<Observer*> observers{&sorter, &budget,   &history,     &rest,        &step_limit,
                                         &frames, &progress, &checkpoints, &stop_signals};

  const auto start = Clock::now();
  const double setup_seconds = std::chrono::duration<double>(start - setup_start).count();
  auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  std::optional<ThreadPinning> pinning(std::in_place, sim.config.threads);
  const std::string results_path = (std::filesystem::path(options.out_dir) / "results.h5").string();
  auto frames_kept = [&] { return writer ? writer->frames() : 0L; };
  LoopEnd end;
  try {
    end = run_time_loop(sim, run.cfl, run.end_time, observers);
  } catch (const std::bad_alloc&) {
    // The frames written so far are kept, marked incomplete (what the step was building is freed).
    pinning.reset();
    progress.done();
    std::ostringstream message;
    message << "out of memory at step " << sim.steps << ", t = " << sim.time << " s (std::bad_alloc): ";
    try {
      on_root([&] { writer->finish(sim.steps, seconds(), false); });
      message << frames_kept() << " frames kept in " << results_path << " (incomplete)";
    } catch (const std::exception& error) {
      message << "closing " << results_path << " failed too: " << error.what();
    }
    message << "; free memory, raise the limits (ulimit -v, the cgroup's), or mesh coarser";
    throw OutOfMemory(message.str());
  }
  pinning.reset();  // the threads' masks back before anything else runs on them
  progress.done();

  if (end.kind == LoopEnd::StepFailed || end.kind == LoopEnd::Failed || end.kind == LoopEnd::BadTimeStep) {
    const std::string message = end.kind == LoopEnd::StepFailed ? step_failure(sim, budget) : end.reason;
    on_root([&] { writer->finish(sim.steps, seconds(), false); });
    const std::string text = "solve: " + message + "; " + std::to_string(frames_kept()) + " frames kept in " + results_path;
    if (distributed) throw SharedError(text);
    throw Error(text);
  }
  if (const int signal = stop_signals.signal()) {
    // The checkpoint records the frames of the uninterrupted run only; the last frame
    // written after it shows where the run stopped, and a restart drops it.
    checkpoints.write(sim);
    if (!frames.written_at(sim)) frames.write(sim);
    on_root([&] { writer->finish(sim.steps, seconds(), false); });
    std::ostringstream message;
    message << "interrupted by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << " at step " << sim.steps
            << ", t = " << sim.time << " s: " << frames_kept() << " frames kept in " << results_path
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
  summary.frame_seconds = frames.seconds();
  summary.setup_seconds = setup_seconds;
  summary.steps = sim.steps;
  summary.simulated_time = sim.time;
  summary.ranks = sim.domain.ranks;
  summary.halo_bytes_per_step = sim.steps > 0 ? sim.domain.halo_bytes / static_cast<double>(sim.steps) : 0;
  summary.migrated = sim.domain.migrated;
  summary.repartitions = sim.domain.repartitions;
  summary.frames_by_ranks = rank_frames.has_value();
  if (distributed) {
    summary.halo_bytes_per_step = mpi::sum_in_rank_order(summary.halo_bytes_per_step);
    summary.migrated = mpi::sum(summary.migrated);
  }
  on_root([&] {
    writer->finish(sim.steps, summary.loop_seconds, true);
    std::error_code ignored;  // the results are complete: nothing left to restart
    std::filesystem::remove(checkpoint, ignored);
  });
  summary.frames = frames_kept();
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
  if (s.ranks > 1)
    out << "  on " << s.ranks << " MPI ranks: " << std::fixed << std::setprecision(0) << s.halo_bytes_per_step
        << " bytes exchanged at shared nodes per step (all ranks), " << s.migrated << " particle migrations, "
        << s.repartitions << " repartitions"
        << (s.frames_by_ranks ? ", frames written by every rank (parallel HDF5)" : ", frames gathered on rank 0") << "\n"
        << std::defaultfloat;
}

}  // namespace talus::solver
