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
#include <mutex>
#include <sstream>
#include <thread>

#include "common/error.hpp"
#include "common/scene/scene.hpp"
#include "postproc/figure_script.hpp"
#include "postproc/output.hpp"
#include "preproc/preproc.hpp"
#include "solver/parallel/threads.hpp"
#include "solver/solver.hpp"
#include "workflow/ensemble_realisation.hpp"
#include "workflow/ensemble_report.hpp"
#include "workflow/folder_lock.hpp"
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

void on_ensemble_stop_signal(int signal_number) {
  int none = 0;
  stop_signal.compare_exchange_strong(none, signal_number);
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
  }
  ~StopSignalsWhileRunning() {
    sigaction(SIGINT, &previous_interrupt_, nullptr);
    sigaction(SIGTERM, &previous_terminate_, nullptr);
  }
  StopSignalsWhileRunning(const StopSignalsWhileRunning&) = delete;
  StopSignalsWhileRunning& operator=(const StopSignalsWhileRunning&) = delete;

 private:
  struct sigaction previous_interrupt_ {};
  struct sigaction previous_terminate_ {};
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

}  // namespace

int run_ensemble(const EnsembleOptions& options, std::ostream& out_log) {
  std::ostringstream discarded;
  std::ostream& log = options.quiet ? static_cast<std::ostream&>(discarded) : out_log;
  if (options.realisations < 1 || options.realisations > kMaxRealisations)
    throw Error("--realisations: expected an integer from 1 to " + std::to_string(kMaxRealisations) + ", got " +
                std::to_string(options.realisations));
  if (options.seed > kMaxSeed - static_cast<std::uint64_t>(options.realisations - 1))
    throw Error("--seed: the seeds S to S + N - 1 must be at most " + std::to_string(kMaxSeed) + " (2^53 - 1), got S = " +
                std::to_string(options.seed) + " with N = " + std::to_string(options.realisations));
  const Scene scene = load_scene(options.scene_path, options.overrides);
  if (scene.random.empty())
    throw Error(located(scene.path, "random",
                        "the scene has no [random.NAME] table: an ensemble needs at least one random field "
                        "(docs/scenes.md, [random.NAME]); nothing was written"));
  const int jobs = std::max(1, std::min<int>(options.jobs > 0 ? options.jobs : solver::available_cores(),
                                             static_cast<int>(options.realisations)));

  const fs::path folder = options.out ? fs::path(*options.out) : fs::path("out") / scene.name / "ensemble";
  create_output_folder(folder.string());
  const FolderLock lock(folder.string());

  const auto mesh_start = Clock::now();
  const EnsembleModel ensemble(scene, preproc::build_model(scene));
  EnsembleRun run;
  run.seed = options.seed;
  run.realisations = options.realisations;
  run.jobs = jobs;
  run.mesh_seconds = seconds_since(mesh_start);

  // What the rows depend on: the scene after --set, its .geo and the program.
  const std::uint64_t inputs =
      stamps::hash(scene.canonical_text, stamps::hash_file(scene.geometry, stamps::program()));
  const std::string csv = (folder / "realisations.csv").string();
  long dropped = 0;
  std::vector<std::string> field_names;
  for (const RandomField& field : scene.random) field_names.push_back(field.name);
  std::map<std::uint64_t, RealisationRow> done = read_rows(csv, inputs, field_names, dropped);
  std::vector<RealisationRow> rows;
  for (long k = 0; k < options.realisations; ++k)
    if (const auto found = done.find(options.seed + k); found != done.end()) {
      rows.push_back(found->second);
      rows.back().index = k;
    }
  const long resumed = static_cast<long>(rows.size());
  std::error_code ignored;
  fs::remove(folder / "ensemble.json", ignored);  // a summary of other rows would mislead until the new one is written
  write_rows(csv, inputs, field_names, rows);
  write_sample_fields((folder / "fields.csv").string(), ensemble, options.seed, options.realisations);

  std::vector<long> todo;
  for (long k = 0; k < options.realisations; ++k)
    if (!std::any_of(rows.begin(), rows.end(), [k](const RealisationRow& r) { return r.index == k; })) todo.push_back(k);
  log << "talus ensemble: " << scene.name << ", " << ensemble.model.particle_count() << " particles, "
      << scene.random.size() << (scene.random.size() == 1 ? " random field" : " random fields") << ", "
      << options.realisations << " realisations (seeds " << options.seed << " to " << options.seed + options.realisations - 1
      << "), " << jobs << (jobs == 1 ? " job" : " jobs") << " of one thread; meshed in " << std::fixed
      << std::setprecision(2) << run.mesh_seconds << " s" << std::defaultfloat << "\n";
  if (resumed > 0)
    log << "resuming: " << resumed << " realisations already in " << csv << ", " << todo.size() << " to run\n";
  if (dropped > 0) log << dropped << " unfinished or unreadable lines of " << csv << " dropped (run again)\n";
  log << std::flush;

  // The realisations, side by side; each finished row is appended to the CSV at once.
  std::ofstream journal(csv, std::ios::app | std::ios::binary);
  if (!journal) throw Error(located(csv, "", "cannot be opened for appending"));
  std::mutex guard;
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  long finished = resumed;
  const auto start = Clock::now();
  {
    const StopSignalsWhileRunning signals;
    auto work = [&] {
      Model worker = ensemble.model;
      for (std::size_t i; stop_signal.load() == 0 && (i = next++) < todo.size();) {
        try {
          const long k = todo[i];
          RealisationTiming timing;
          const std::optional<RealisationRow> row =
              run_realisation(ensemble, worker, k, options.seed + k, stop_signal, &timing);
          if (!row) break;
          const std::lock_guard<std::mutex> lock_rows(guard);
          const auto t = Clock::now();
          journal << csv_line(*row) << std::flush;
          if (!journal) throw Error(located(csv, "", "a row could not be written (disk full?)"));
          rows.push_back(*row);
          ++finished;
          run.record_seconds += seconds_since(t);
          run.field_seconds += timing.fields;
          run.solve_seconds += timing.solve;
          run.post_seconds += timing.post;
          ++run.timed;
          const double elapsed = seconds_since(start);
          const long left = options.realisations - finished;
          print_row(log, *row, finished, options.realisations);
          log << "; ETA " << duration(elapsed / static_cast<double>(finished - resumed) * static_cast<double>(left)) << "\n"
              << std::flush;
        } catch (...) {
          const std::lock_guard<std::mutex> lock_rows(guard);
          if (!error) error = std::current_exception();
          int none = 0;  // the others stop after their step, as on a signal
          stop_signal.compare_exchange_strong(none, kStoppedByError);
        }
      }
    };
    std::vector<std::thread> threads;
    for (int j = 0; j < jobs; ++j) threads.emplace_back(work);
    for (auto& t : threads) t.join();
  }
  run.wall_seconds = seconds_since(start);
  journal.close();
  write_rows(csv, inputs, field_names, rows);
  if (error) std::rethrow_exception(error);
  if (const int signal = stop_signal.load(); signal > 0) {
    std::ostringstream message;
    message << "interrupted by " << (signal == SIGINT ? "SIGINT" : "SIGTERM") << ": " << finished << " of "
            << options.realisations << " realisations in " << csv << " (run the same command again to continue)";
    throw solver::Interrupted(signal, message.str());
  }

  const std::string json = (folder / "ensemble.json").string();
  postproc::write_file_atomically(json, ensemble_json(ensemble, run, rows));
  print_summary(log, rows);
  log << "wrote " << json << ", " << csv << std::endl;
  if (!options.figures) return 0;
  try {
    postproc::run_figure_script(postproc::figure_script("ensemble_figure.py"), {"--out", folder.string()}, log);
  } catch (const Error& e) {
    out_log << "talus ensemble: figures failed: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace talus::workflow
