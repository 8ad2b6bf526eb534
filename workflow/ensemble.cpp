// The ensemble workflow (ensemble.hpp). Method, outputs and criteria: docs/ensemble.md.
#include "workflow/ensemble.hpp"

#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <condition_variable>
#include <mutex>
#include <sstream>
#include <thread>

#include "common/error.hpp"
#include "common/scene/scene.hpp"
#include "postproc/figure_script.hpp"
#include "postproc/output.hpp"
#include "preproc/preproc.hpp"
#include "solver/parallel/parallel.hpp"
#include "solver/parallel/threads.hpp"
#include "solver/solver.hpp"
#include "workflow/ensemble_realisation.hpp"
#include "workflow/ensemble_report.hpp"
#include "workflow/folder_lock.hpp"
#include "workflow/fos.hpp"
#include "workflow/launch.hpp"
#include "workflow/pipeline.hpp"
#include "workflow/stamps.hpp"

namespace fs = std::filesystem;

namespace talus::workflow {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// SIGINT and SIGTERM while the realisations run: the first one asks every running realisation to
// stop after its step (StopRequest), and no new one starts.
std::atomic<int> stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "a signal handler stores into it");
constexpr int kStoppedByError = -1;  // stop_signal's value when a realisation threw

constexpr int kStoppedByPeer = -2;   // ... when another rank stopped (a signal or an error there)

// SIGUSR1 and SIGUSR2 are SIGINT and SIGTERM as mpirun forwards them from a `--ranks` driver
// (workflow/launch.hpp).
void on_ensemble_stop_signal(int signal_number) {
  int none = 0;
  stop_signal.compare_exchange_strong(none, signal_number == SIGUSR1   ? SIGINT
                                            : signal_number == SIGUSR2 ? SIGTERM
                                                                       : signal_number);
}

class StopSignalsWhileRunning {
 public:
  StopSignalsWhileRunning() {
    stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = on_ensemble_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_interrupt_);
    sigaction(SIGTERM, &action, &previous_terminate_);
    if (solver::mpi::distributed()) {
      sigaction(SIGUSR1, &action, &previous_user1_);
      sigaction(SIGUSR2, &action, &previous_user2_);
    }
  }
  ~StopSignalsWhileRunning() {
    sigaction(SIGINT, &previous_interrupt_, nullptr);
    sigaction(SIGTERM, &previous_terminate_, nullptr);
    if (solver::mpi::distributed()) {
      sigaction(SIGUSR1, &previous_user1_, nullptr);
      sigaction(SIGUSR2, &previous_user2_, nullptr);
    }
  }
  StopSignalsWhileRunning(const StopSignalsWhileRunning&) = delete;
  StopSignalsWhileRunning& operator=(const StopSignalsWhileRunning&) = delete;

 private:
  struct sigaction previous_interrupt_ {};
  struct sigaction previous_terminate_ {};
  struct sigaction previous_user1_ {};
  struct sigaction previous_user2_ {};
};

std::string duration(double seconds) {
  std::ostringstream out;
  const long s = std::lround(seconds);
  if (s >= 3600) out << s / 3600 << " h " << (s % 3600) / 60 << " min";
  else if (s >= 60) out << s / 60 << " min " << s % 60 << " s";
  else out << s << " s";
  return out.str();
}

// The fields of the first two realisations at every particle (the figure of two sample fields).
void write_sample_fields(const std::string& path, const EnsembleModel& ensemble, std::uint64_t seed, long count) {
  std::vector<std::string> header{"x_m", "y_m"};
  std::vector<std::vector<double>> columns(2);
  for (const auto& x : ensemble.model.position) columns[0].push_back(x.x()), columns[1].push_back(x.y());
  for (long k = 0; k < std::min(2L, count); ++k)
    for (const ParticleProperty& property : realisation_properties(ensemble, seed + k)) {
      header.push_back(property.material + "." + property.parameter + "@seed" + std::to_string(seed + k));
      columns.push_back(property.values);
    }
  postproc::write_csv(path, header, columns);
}

void print_row(std::ostream& log, const RealisationRow& row, long done, long total) {
  log << "  [" << done << "/" << total << "] realisation " << row.index << " (seed " << row.seed << "): ";
  if (!row.solved) log << "solve stopped: " << row.message;
  else if (row.failed)
    log << std::fixed << std::setprecision(2) << "failed, runout " << row.runout << " m, failed area "
        << row.failed_area << " m^2";
  else log << "stable";
  if (row.fos) log << std::fixed << std::setprecision(3) << ", F = " << *row.fos;
  log << std::defaultfloat;
}

void print_summary(std::ostream& log, const std::vector<RealisationRow>& rows) {
  std::size_t n = 0, failed = 0;
  std::vector<double> runout;
  for (const auto& row : rows)
    if (row.solved) ++n, failed += row.failed ? 1 : 0, runout.push_back(row.runout);
  if (n == 0) {
    log << "no realisation was solved\n";
    return;
  }
  const Interval band = wilson_interval(failed, n);
  log << std::fixed << std::setprecision(3) << "probability of failure " << static_cast<double>(failed) / n << " ("
      << failed << " of " << n << "; 95 % Wilson interval " << band.lower << " .. " << band.upper << ")\n"
      << std::setprecision(2) << "runout P50 " << quantile(runout, 0.5) << " m, P90 " << quantile(runout, 0.9)
      << " m, P95 " << quantile(runout, 0.95) << " m\n"
      << std::defaultfloat;
  if (n < rows.size()) log << rows.size() - n << " realisations stopped with a solver error (left out; see realisations.csv)\n";
}

// The same ensemble on options.ranks MPI ranks (`--ranks`): this process holds the folder's lock
// and starts the ranks under mpirun (workflow/launch.hpp), each a `talus ensemble` with --jobs
// given, and draws the figures once they have written ensemble.json.
int ensemble_on_ranks(const EnsembleOptions& options, const std::string& folder, int ranks, int jobs,
                      std::ostream& log) {
  RanksCommand command;
  command.ranks = ranks;
  command.arguments = {"ensemble",      options.scene_path, "--realisations", std::to_string(options.realisations),
                       "--seed",        std::to_string(options.seed), "--jobs", std::to_string(jobs),
                       "--out",         folder};
  for (const std::string& item : options.overrides) command.arguments.insert(command.arguments.end(), {"--set", item});
  if (options.fos) command.arguments.push_back("--fos");
  if (options.tolerance) {
    std::ostringstream text;
    text << std::setprecision(17) << *options.tolerance;
    command.arguments.insert(command.arguments.end(), {"--tolerance", text.str()});
  }
  if (options.quiet) command.arguments.push_back("--quiet");
  command.folder = folder;
  command.quiet = options.quiet;
  command.doing = "running the realisations";
  command.kept = (fs::path(folder) / "realisations.csv").string() +
                 " keeps the realisations finished before (run the same command again to continue)";
  run_on_ranks(command, log);
  if (!options.figures) return 0;
  try {
    postproc::run_figure_script(postproc::figure_script("ensemble_figure.py"), {"--out", folder}, log);
  } catch (const Error& e) {
    log << "talus ensemble: figures failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

// Runs `work` on every rank alike; an Error it throws is every rank's, printed once (SharedError).
template <class Work>
auto on_every_rank(Work&& work) {
  try {
    return work();
  } catch (const SharedError&) {
    throw;
  } catch (const Error& e) {
    if (solver::mpi::distributed()) throw SharedError(e.what());
    throw;
  }
}

std::string indices_text(const std::vector<long>& indices) {
  std::ostringstream text;
  for (long k : indices) text << k << ' ';
  return text.str();
}

std::vector<long> indices_of(const std::string& text) {
  std::istringstream in(text);
  std::vector<long> indices;
  for (long k; in >> k;) indices.push_back(k);
  return indices;
}

}  // namespace

int run_ensemble(const EnsembleOptions& options, std::ostream& out_log) {
  const bool distributed = solver::mpi::distributed();
  const bool root = solver::mpi::rank() == 0;
  std::ostringstream discarded;
  std::ostream& log = options.quiet || !root ? static_cast<std::ostream&>(discarded) : out_log;
  if (options.realisations < 1 || options.realisations > kMaxRealisations)
    throw Error("--realisations: expected an integer from 1 to " + std::to_string(kMaxRealisations) + ", got " +
                std::to_string(options.realisations));
  if (options.seed > kMaxSeed - static_cast<std::uint64_t>(options.realisations - 1))
    throw Error("--seed: the seeds S to S + N - 1 must be at most " + std::to_string(kMaxSeed) + " (2^53 - 1), got S = " +
                std::to_string(options.seed) + " with N = " + std::to_string(options.realisations));
  if (options.tolerance && !options.fos) throw Error("--tolerance: the bracket width of --fos's search; give --fos with it");
  const double fos_tolerance = options.tolerance.value_or(solver::SearchSettings{}.tolerance);
  if (options.fos) check_fos_tolerance(fos_tolerance);
  const Scene scene = on_every_rank([&] { return load_scene(options.scene_path, options.overrides); });
  if (scene.random.empty())
    throw Error(located(scene.path, "random",
                        "the scene has no [random.NAME] table: an ensemble needs at least one random field "
                        "(docs/scenes.md, [random.NAME]); nothing was written"));
  const fs::path folder = options.out ? fs::path(*options.out) : fs::path("out") / scene.name / "ensemble";

  // --ranks R: this process starts R ranks that run the realisations (one per core between them
  // unless --jobs says), and draws the figures.
  const int ranks = std::min<long>(std::max(1, options.ranks), options.realisations);
  if (ranks > 1 && !distributed) {
    const int jobs = options.jobs > 0 ? options.jobs : std::max(1, solver::available_cores() / ranks);
    create_output_folder(folder.string());
    const FolderLock lock(folder.string());
    return ensemble_on_ranks(options, folder.string(), ranks, jobs, out_log);
  }
  const int jobs = std::max(1, std::min<int>(options.jobs > 0 ? options.jobs : solver::available_cores(),
                                             static_cast<int>(options.realisations)));

  std::optional<FolderLock> lock;
  if (distributed) {
    // A rank of `--ranks`: the folder and its lock are the driver's (main refuses any other mpirun).
    take_lock_from_ranks_driver(folder.string());
  } else {
    create_output_folder(folder.string());
    lock.emplace(folder.string());
  }

  const auto mesh_start = Clock::now();
  const EnsembleModel ensemble = on_every_rank([&] {
    EnsembleModel made(scene, preproc::build_model(scene));
    if (options.fos) made.enable_fos(fos_tolerance);
    return made;
  });
  EnsembleRun run;
  run.seed = options.seed;
  run.realisations = options.realisations;
  run.jobs = jobs;
  run.ranks = solver::mpi::size();
  if (options.fos) run.fos_tolerance = fos_tolerance;
  run.mesh_seconds = seconds_since(mesh_start);

  // What the rows depend on: the scene after --set, its .geo, the program, and --fos's search.
  std::uint64_t inputs = stamps::hash(scene.canonical_text, stamps::hash_file(scene.geometry, stamps::program()));
  if (options.fos) {
    std::ostringstream search;
    search << "fos tolerance " << std::setprecision(17) << fos_tolerance;
    inputs = stamps::hash(search.str(), inputs);
  }
  const std::string csv = (folder / "realisations.csv").string();
  std::vector<std::string> field_names;
  for (const RandomField& field : scene.random) field_names.push_back(field.name);
  const bool fos = options.fos;

  // Rank 0 reads the rows already made and says which realisations are left.
  std::vector<RealisationRow> rows;
  std::vector<long> todo;
  long resumed = 0, dropped = 0;
  if (root) {
    std::map<std::uint64_t, RealisationRow> done = read_rows(csv, inputs, field_names, dropped, fos);
    for (long k = 0; k < options.realisations; ++k)
      if (const auto found = done.find(options.seed + k); found != done.end()) {
        rows.push_back(found->second);
        rows.back().index = k;
      } else {
        todo.push_back(k);
      }
    resumed = static_cast<long>(rows.size());
    std::error_code ignored;
    fs::remove(folder / "ensemble.json", ignored);  // a summary of other rows would mislead until the new one is written
    write_rows(csv, inputs, field_names, rows, fos);
    write_sample_fields((folder / "fields.csv").string(), ensemble, options.seed, options.realisations);
  }
  std::string todo_text = indices_text(todo);
  solver::mpi::broadcast(todo_text, 0);
  todo = indices_of(todo_text);
  // This rank's share: every ranks-th of them, from its own rank on.
  std::vector<long> mine;
  for (std::size_t i = static_cast<std::size_t>(solver::mpi::rank()); i < todo.size(); i += static_cast<std::size_t>(run.ranks))
    mine.push_back(todo[i]);

  log << "talus ensemble: " << scene.name << ", " << ensemble.model.particle_count() << " particles, "
      << scene.random.size() << (scene.random.size() == 1 ? " random field" : " random fields") << ", "
      << options.realisations << " realisations (seeds " << options.seed << " to " << options.seed + options.realisations - 1
      << "), ";
  if (run.ranks > 1) log << run.ranks << " ranks x ";
  log << jobs << (jobs == 1 ? " job" : " jobs") << " of one thread" << (fos ? ", with the factor of safety" : "")
      << "; meshed in " << std::fixed << std::setprecision(2) << run.mesh_seconds << " s" << std::defaultfloat << "\n";
  if (resumed > 0)
    log << "resuming: " << resumed << " realisations already in " << csv << ", " << todo.size() << " to run\n";
  if (dropped > 0) log << dropped << " unfinished or unreadable lines of " << csv << " dropped (run again)\n";
  log << std::flush;

  // The realisations, `jobs` threads on each rank. Each finished row waits in `pending` until this
  // thread collects the rows of every rank (every 0.2 s on several ranks, at once on one), and
  // rank 0 appends them to the CSV.
  std::ofstream journal;
  if (root) {
    journal.open(csv, std::ios::app | std::ios::binary);
    if (!journal) throw Error(located(csv, "", "cannot be opened for appending"));
  }
  std::mutex guard;
  std::condition_variable changed;
  std::vector<RealisationRow> pending;
  int workers_done = 0;
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  long finished = resumed;
  long stopped_by = 0;  // the stop seen on any rank: a signal, or kStoppedByError's stand-in
  constexpr long kErrorSomewhere = 1000;
  const auto start = Clock::now();
  {
    const StopSignalsWhileRunning signals;
    auto work = [&] {
      Model worker = ensemble.model;
      for (std::size_t i; stop_signal.load() == 0 && (i = next++) < mine.size();) {
        try {
          const long k = mine[i];
          RealisationTiming timing;
          const std::optional<RealisationRow> row =
              run_realisation(ensemble, worker, k, options.seed + k, stop_signal, &timing);
          if (!row) break;
          const std::lock_guard<std::mutex> lock_rows(guard);
          pending.push_back(*row);
          run.field_seconds += timing.fields;
          run.solve_seconds += timing.solve;
          run.post_seconds += timing.post;
          run.fos_seconds += timing.fos;
          ++run.timed;
          changed.notify_one();
        } catch (...) {
          const std::lock_guard<std::mutex> lock_rows(guard);
          if (!error) error = std::current_exception();
          int none = 0;  // the others stop after their step, as on a signal
          stop_signal.compare_exchange_strong(none, kStoppedByError);
        }
      }
      const std::lock_guard<std::mutex> lock_rows(guard);
      ++workers_done;
      changed.notify_one();
    };
    std::vector<std::thread> threads;
    for (int j = 0; j < jobs; ++j) threads.emplace_back(work);
    for (;;) {
      std::vector<RealisationRow> collected;
      bool here_done = false;
      {
        std::unique_lock<std::mutex> lock_rows(guard);
        // On several ranks every rank collects at the same pace (a collective each time).
        if (distributed) lock_rows.unlock(), std::this_thread::sleep_for(std::chrono::milliseconds(200)), lock_rows.lock();
        else changed.wait_for(lock_rows, std::chrono::milliseconds(200), [&] { return !pending.empty() || workers_done == jobs; });
        here_done = workers_done == jobs;
        collected.swap(pending);
      }
      // A stop on one rank (a signal that reached it alone, an error) stops them all; each rank
      // goes on saying its own cause (a stop passed on from another is none), so that every rank
      // ends with the same `stopped_by`.
      const int here = stop_signal.load();
      stopped_by = solver::mpi::max(here == kStoppedByError ? kErrorSomewhere : here > 0 ? static_cast<long>(here) : 0L);
      if (stopped_by != 0 && here == 0) {
        int none = 0;
        stop_signal.compare_exchange_strong(none, kStoppedByPeer);
      }
      std::string lines;
      for (const RealisationRow& row : collected) lines += csv_line(row, fos);
      const std::vector<std::string> all = solver::mpi::gather(lines);
      const bool everywhere_done = solver::mpi::min(here_done ? 1L : 0L) == 1;
      if (root) {
        const auto t = Clock::now();
        try {
          for (const std::string& text : all) {
            journal << text << std::flush;
            if (!journal) throw Error(located(csv, "", "a row could not be written (disk full?)"));
            std::istringstream in(text);
            for (std::string line; std::getline(in, line);) {
              const std::optional<RealisationRow> row = parse_csv_line(line, field_names.size(), fos);
              if (!row) throw std::logic_error("ensemble: a row did not read back: " + line);
              rows.push_back(*row);
              ++finished;
              const double elapsed = seconds_since(start);
              const long left = options.realisations - finished;
              print_row(log, *row, finished, options.realisations);
              log << "; ETA " << duration(elapsed / static_cast<double>(finished - resumed) * static_cast<double>(left))
                  << "\n" << std::flush;
            }
          }
        } catch (...) {  // the realisations stop after their step, as on an error in one of them
          const std::lock_guard<std::mutex> lock_rows(guard);
          if (!error) error = std::current_exception();
          int none = 0;
          stop_signal.compare_exchange_strong(none, kStoppedByError);
        }
        run.record_seconds += seconds_since(t);
      }
      if (everywhere_done) break;
    }
    for (auto& t : threads) t.join();
  }
  run.wall_seconds = seconds_since(start);
  // The timing of every rank's realisations.
  double sums[5] = {run.field_seconds, run.solve_seconds, run.post_seconds, run.fos_seconds, run.record_seconds};
  solver::mpi::sum_in_rank_order(sums, 5);
  run.field_seconds = sums[0], run.solve_seconds = sums[1], run.post_seconds = sums[2], run.fos_seconds = sums[3];
  run.record_seconds = sums[4];
  run.timed = solver::mpi::sum(run.timed);
  if (root) {
    journal.close();
    write_rows(csv, inputs, field_names, rows, fos);
  }
  // An error in a realisation (values that leave a material invalid): the first rank's, said once.
  if (distributed) {
    const int first = solver::mpi::first_rank_with(error != nullptr);
    if (first >= 0) {
      std::string message;
      if (first == solver::mpi::rank()) {
        try {
          std::rethrow_exception(error);
        } catch (const Error& e) {
          message = e.what();
        }  // another exception goes on from here, and mpi::abort_all stops the ranks
      }
      solver::mpi::broadcast(message, first);
      throw SharedError(message);
    }
  } else if (error) {
    std::rethrow_exception(error);
  }
  if (stopped_by > 0 && stopped_by != kErrorSomewhere) {
    const int signal = static_cast<int>(stopped_by);
    std::ostringstream message;
    message << "interrupted by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << ": " << finished << " of "
            << options.realisations << " realisations in " << csv << " (run the same command again to continue)";
    throw solver::Interrupted(signal, message.str());
  }
  if (!root) return 0;

  const std::string json = (folder / "ensemble.json").string();
  postproc::write_file_atomically(json, ensemble_json(ensemble, run, rows));
  print_summary(log, rows);
  log << "wrote " << json << ", " << csv << std::endl;
  // On several ranks the `--ranks` driver draws the figures.
  if (!options.figures || distributed) return 0;
  try {
    postproc::run_figure_script(postproc::figure_script("ensemble_figure.py"), {"--out", folder.string()}, log);
  } catch (const Error& e) {
    out_log << "talus ensemble: figures failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace talus::workflow
