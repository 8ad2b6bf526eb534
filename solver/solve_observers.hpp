// The observers of `talus solve` (time_loop.hpp): frames and the energy history into
// results.h5, rest detection, the step limit, the progress line, periodic checkpoints, and
// SIGINT/SIGTERM. Their state that a restart needs lives in one LoopState (checkpoint.hpp).
#pragma once
#include <chrono>
#include <csignal>
#include <string>

#include "common/model/model.hpp"
#include "solver/io/io.hpp"
#include "solver/step/time_loop.hpp"

namespace talus::solver {

// The first multiple k x interval (k = floor(t / interval) + 1, k integer) beyond time +
// tolerance: computed, not summed, so no interval is too small to move it on (when k x
// interval cannot exceed time + tolerance in doubles, the next double beyond it).
double next_multiple_after(double time, double interval, double tolerance);

// On several MPI ranks only rank 0 holds a ResultsWriter (the others pass null), and every rank
// takes part in each frame and checkpoint: the ranks write their rows of a frame themselves
// with the parallel HDF5 (RankFrames, results_parallel.hpp), or else the particles are gathered
// on rank 0 (domain.hpp); checkpoints always gather them.

// Writes a frame at every multiple of the output interval, landing the step on it.
class FrameWriter : public Observer {
 public:
  // `ranks`: on several ranks with the parallel HDF5, every rank's writer of its rows (null:
  // gather the frames on rank 0).
  FrameWriter(ResultsWriter* writer, LoopState& loop, double interval, double tolerance, RankFrames* ranks = nullptr)
      : writer_(writer), ranks_(ranks), loop_(loop), interval_(interval), tolerance_(tolerance) {}
  double next_landing(const Simulation&) const override { return loop_.next_output; }
  bool wants_energies(const Simulation& sim) const override { return due(sim); }
  bool wants_step_velocity(const Simulation&, double time) const override { return due_at(time); }
  Verdict after_step(Simulation& sim, const StepEvent&) override;
  // Writes a frame now (the last one of a run that stops between output times).
  void write(const Simulation& sim);
  bool written_at(const Simulation& sim) const { return last_step_ == sim.steps; }
  double seconds() const { return seconds_; }  // wall time spent writing the frames so far

 private:
  bool due_at(double time) const { return time >= loop_.next_output - tolerance_; }
  bool due(const Simulation& sim) const { return due_at(sim.time); }
  ResultsWriter* writer_;
  RankFrames* ranks_;
  LoopState& loop_;
  double interval_, tolerance_;
  long last_step_ = -1;
  double seconds_ = 0;
};

// A row of the energy history every `interval` steps, and whenever another observer has the
// energies computed (at every frame).
class HistoryRecorder : public Observer {
 public:
  HistoryRecorder(ResultsWriter* writer, int interval) : writer_(writer), interval_(interval) {}
  bool wants_energies(const Simulation& sim) const override { return sim.steps % interval_ == 0; }
  Verdict after_step(Simulation& sim, const StepEvent& event) override;

 private:
  ResultsWriter* writer_;
  int interval_;
};

// Stops the run once the grid kinetic energy has stayed below rest_ratio x its peak for
// rest_window seconds after the peak (judged whenever the energies are computed).
class RestDetector : public Observer {
 public:
  RestDetector(LoopState& loop, double rest_ratio, double rest_window)
      : loop_(loop), ratio_(rest_ratio), window_(rest_window) {}
  Verdict after_step(Simulation& sim, const StepEvent& event) override;
  bool at_rest(const Simulation& sim) const { return loop_.rest_since >= 0 && sim.time - loop_.rest_since >= window_; }

 private:
  LoopState& loop_;
  double ratio_, window_;
};

// Stops the run after max_steps steps (0: never).
class StepLimit : public Observer {
 public:
  explicit StepLimit(long max_steps) : max_steps_(max_steps) {}
  Verdict after_step(Simulation& sim, const StepEvent&) override {
    return max_steps_ > 0 && sim.steps >= max_steps_ ? Verdict::stop("step limit") : Verdict::go_on();
  }

 private:
  long max_steps_;
};

// Progress on stderr: on a terminal one line rewritten at most four times a second; otherwise
// (a log, a pipe) a line a minute.
class ProgressLine : public Observer {
 public:
  ProgressLine(bool enabled, double end_time);
  ~ProgressLine() override { done(); }
  Verdict after_step(Simulation& sim, const StepEvent& event) override;
  void done();  // ends the line, once

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  bool terminal_;  // stderr is a terminal: the line is rewritten in place
  double end_time_;
  bool shown_ = false;  // a terminal line is open (done() ends it)
  Clock::time_point start_ = Clock::now(), last_ = Clock::now();
};

// Writes OUT/checkpoint.h5 at multiples of `interval` simulated seconds (0: never).
class Checkpointer : public Observer {
 public:
  // `fingerprints`: model_fingerprints of the run's model (checkpoint.hpp).
  Checkpointer(const std::string& out_dir, Fingerprints fingerprints, ResultsWriter* writer, LoopState& loop,
               double interval, double tolerance, double time);
  Verdict after_step(Simulation& sim, const StepEvent&) override;
  void write(const Simulation& sim);  // now, whatever the schedule

 private:
  std::string out_dir_;
  Fingerprints fingerprints_;
  ResultsWriter* writer_;
  LoopState& loop_;
  double interval_, tolerance_;
};

// SIGINT and SIGTERM (on several ranks also SIGUSR1 and SIGUSR2, as mpirun forwards a Ctrl-C
// from `--ranks`, workflow/launch.hpp) set a flag while it lives (the previous handlers come back after); the
// run stops after the step in which the flag was seen (on several ranks: seen on any rank,
// so that all stop after the same step).
class StopSignals : public Observer {
 public:
  StopSignals();
  ~StopSignals() override;
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;
  Verdict after_step(Simulation& sim, const StepEvent&) override;
  int signal() const;  // the signal that stopped the run, 0 for none

 private:
  int seen_ = 0;  // on several ranks: the signal that stopped the run (the largest over the ranks)
  bool distributed_ = false;
  struct sigaction previous_interrupt_ {};
  struct sigaction previous_terminate_ {};
  struct sigaction previous_user1_ {};
  struct sigaction previous_user2_ {};
};

}  // namespace talus::solver
