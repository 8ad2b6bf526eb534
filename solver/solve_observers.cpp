#include "solver/solve_observers.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "solver/parallel/parallel.hpp"

namespace talus::solver {

double next_multiple_after(double time, double interval, double tolerance) {
  const double now = time + tolerance;
  const double k = std::floor(now / interval) + 1;
  if (k * interval > now) return k * interval;
  if ((k + 1) * interval > now) return (k + 1) * interval;  // round-off in the division
  return std::nextafter(now, kNever);  // k beyond 2^53: the interval no longer moves the time
}

Verdict FrameWriter::after_step(Simulation& sim, const StepEvent&) {
  if (due(sim)) write(sim);
  sim.particles.step_velocity.clear();  // kept for this frame only
  return Verdict::go_on();
}

void FrameWriter::write(const Simulation& sim) {
  const auto start = std::chrono::steady_clock::now();
  if (!sim.domain.distributed()) {
    writer_->write_frame(sim);
  } else if (ranks_) {
    ranks_->write(sim, grid_velocity_at_particles(sim), writer_);
  } else {
    const std::vector<Vec2> velocity = grid_velocity_at_particles(sim);
    std::vector<Vec2> all_velocity;
    const Particles all = gather_particles(sim, &velocity, &all_velocity);
    on_root([&] { writer_->write_frame(all, all_velocity, sim.time, sim.steps); });
  }
  last_step_ = sim.steps;
  loop_.next_output = next_multiple_after(sim.time, interval_, tolerance_);
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

Verdict HistoryRecorder::after_step(Simulation& sim, const StepEvent& event) {
  if (event.energies_due && writer_) writer_->record_history(sim, event.energies());
  return Verdict::go_on();
}

Verdict RestDetector::after_step(Simulation& sim, const StepEvent& event) {
  if (event.energies_due) {
    // Rest is judged on the grid's kinetic energy: the motion of the material itself.
    const double kinetic = event.energies().grid_kinetic;
    if (kinetic > loop_.peak_kinetic) loop_.peak_kinetic = kinetic, loop_.peak_time = sim.time;
    if (ratio_ > 0 && loop_.peak_kinetic > 0 && sim.time > loop_.peak_time && kinetic < ratio_ * loop_.peak_kinetic) {
      if (loop_.rest_since < 0) loop_.rest_since = sim.time;
    } else {
      loop_.rest_since = -1;
    }
  }
  return at_rest(sim) ? Verdict::stop("at rest") : Verdict::go_on();
}

ProgressLine::ProgressLine(bool enabled, double end_time)
    : enabled_(enabled), terminal_(isatty(STDERR_FILENO)), end_time_(end_time) {}

Verdict ProgressLine::after_step(Simulation& sim, const StepEvent& event) {
  if (!enabled_) return Verdict::go_on();
  const auto now = Clock::now();
  // A terminal gets one line rewritten four times a second; a log or a pipe a line a minute,
  // the first after a minute (a short run writes none).
  if (terminal_ ? now - last_ < std::chrono::milliseconds(250) : now - last_ < std::chrono::seconds(60))
    return Verdict::go_on();
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = sim.time > 0 ? elapsed * (end_time_ - sim.time) / sim.time : 0;
  std::fprintf(stderr, "%s  step %ld  t = %.4g / %.4g s  dt = %.3e s  ETA %.0f s%s", terminal_ ? "\r" : "", sim.steps,
               sim.time, end_time_, event.dt, eta, terminal_ ? "   " : "\n");
  std::fflush(stderr);
  shown_ = terminal_;
  return Verdict::go_on();
}

void ProgressLine::done() {
  if (shown_) std::fprintf(stderr, "\n");
  shown_ = false;
}

Checkpointer::Checkpointer(const std::string& out_dir, Fingerprints fingerprints, ResultsWriter* writer,
                           LoopState& loop, double interval, double tolerance, double time)
    : out_dir_(out_dir), fingerprints_(std::move(fingerprints)), writer_(writer), loop_(loop), interval_(interval), tolerance_(tolerance) {
  // Periodic checkpoints at multiples of the interval; they change what is on disk, not the run.
  loop_.next_checkpoint = interval > 0 ? next_multiple_after(time, interval, 0) : kNever;
}

Verdict Checkpointer::after_step(Simulation& sim, const StepEvent&) {
  if (sim.time >= loop_.next_checkpoint - tolerance_) {
    loop_.next_checkpoint = next_multiple_after(sim.time, interval_, tolerance_);
    write(sim);
  }
  return Verdict::go_on();
}

void Checkpointer::write(const Simulation& sim) {
  // On several ranks the checkpoint is gathered on rank 0 even with the parallel HDF5: it is
  // written rarely, and atomically (checkpoint.hpp), which a file the ranks share is not.
  if (!sim.domain.distributed()) {
    write_checkpoint(out_dir_, fingerprints_, sim, loop_, writer_->sync());
    return;
  }
  const Particles all = gather_particles(sim);
  on_root([&] {
    write_checkpoint(out_dir_, fingerprints_, all, sim.time, sim.steps, loop_, writer_->sync(), sim.absorbing_reaction);
  });
}

namespace {

// The signal that asked the run to stop (0: none). Set by the handler, read after each step.
volatile std::sig_atomic_t stop_signal = 0;

// SIGUSR1 and SIGUSR2 are SIGINT and SIGTERM as mpirun forwards them (workflow/launch.hpp).
extern "C" void on_stop_signal(int signal) {
  stop_signal = signal == SIGUSR1 ? SIGINT : signal == SIGUSR2 ? SIGTERM : signal;
}

}  // namespace

StopSignals::StopSignals() {
  stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // file writes in progress continue rather than fail with EINTR
  sigaction(SIGINT, &action, &previous_interrupt_);
  sigaction(SIGTERM, &action, &previous_terminate_);
  if (mpi::distributed()) {
    sigaction(SIGUSR1, &action, &previous_user1_);
    sigaction(SIGUSR2, &action, &previous_user2_);
  }
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &previous_interrupt_, nullptr);
  sigaction(SIGTERM, &previous_terminate_, nullptr);
  if (mpi::distributed()) {
    sigaction(SIGUSR1, &previous_user1_, nullptr);
    sigaction(SIGUSR2, &previous_user2_, nullptr);
  }
}

Verdict StopSignals::after_step(Simulation& sim, const StepEvent&) {
  distributed_ = sim.domain.distributed();
  seen_ = distributed_ ? static_cast<int>(mpi::max(static_cast<long>(stop_signal))) : stop_signal;
  return seen_ ? Verdict::stop("interrupted") : Verdict::go_on();
}

int StopSignals::signal() const { return distributed_ ? seen_ : stop_signal; }

}  // namespace talus::solver
