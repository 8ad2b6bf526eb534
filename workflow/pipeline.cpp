#include "workflow/pipeline.hpp"

#include <sys/resource.h>
#include <signal.h>
#include <sys/statvfs.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <system_error>

#include "common/error.hpp"
#include "common/model/model.hpp"
#include "postproc/postproc.hpp"
#include "preproc/preproc.hpp"
#include "solver/solver.hpp"
#include "solver/parallel/parallel.hpp"
#include "workflow/folder_lock.hpp"
#include "workflow/launch.hpp"
#include "workflow/ranks_link.hpp"
#include "workflow/stamps.hpp"

namespace fs = std::filesystem;

namespace talus::workflow {
namespace {

// `folder` created (with its parents) if missing; a path that cannot be a folder is bad input.
std::string created_folder(const std::string& folder) {
  create_output_folder(folder);
  return folder;
}

// The folder of a stage that reads a file: `out`, else the file's own folder; created.
std::string folder_beside(const std::optional<std::string>& out, const std::string& input) {
  std::string folder = out ? *out : fs::path(input).parent_path().string();
  if (folder.empty() && !out) folder = ".";
  return created_folder(folder);
}

// A failed mesh says which files of the folder an earlier run left (they are not this scene's)
// and forgets the folder's stamps, so that nothing there passes for this run's output.
Error mesh_failed(const Error& error, const std::string& folder) {
  stamps::forget(folder);
  std::string earlier;
  for (const char* name : {"model.h5", "results.h5", "metrics.json", "checkpoint.h5"})
    if (fs::exists(fs::path(folder) / name)) earlier += (earlier.empty() ? "" : ", ") + std::string(name);
  if (earlier.empty()) return error;
  return Error(std::string(error.what()) + "\n(nothing was written: " + earlier + " in " + folder +
               " are from an earlier run, not from this one)");
}

std::string mesh(const Scene& scene, const std::string& folder, bool quiet, std::ostream& log) {
  preproc::MeshReport report;
  const std::string path = (fs::path(folder) / "model.h5").string();
  try {
    write_model(path, preproc::build_model(scene, &report));
  } catch (const Error& error) {
    throw mesh_failed(error, folder);
  }
  if (!quiet) {
    preproc::print_report(report, log);
    log << "wrote " << path << std::endl;
  }
  return path;
}

// results.h5 keeps 12 doubles per particle and frame (position, velocity, displacement, stress,
// plastic strain, volume), 100 B with HDF5's overhead, and about 8 kB per frame for the XDMF's
// views; results.xdmf about 3 kB per frame. A run whose results would not fit in the folder's
// free space, or in the process's file size limit, is refused.
void check_results_fit(const Model& model, const std::string& model_path, const std::string& folder) {
  const double frames = std::floor(model.run.end_time / model.run.output_interval) + 2;
  const double h5_bytes = frames * (100.0 * static_cast<double>(model.particle_count()) + 8000.0);
  const double bytes = h5_bytes + frames * 3000.0;
  struct statvfs disk {};
  const double free_bytes =
      statvfs(folder.c_str(), &disk) == 0 ? static_cast<double>(disk.f_bavail) * disk.f_frsize : HUGE_VAL;
  struct rlimit limit {};
  const double file_limit = getrlimit(RLIMIT_FSIZE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY
                                ? static_cast<double>(limit.rlim_cur)
                                : HUGE_VAL;
  if (bytes <= free_bytes && h5_bytes <= file_limit) return;
  std::ostringstream message;
  message.precision(3);
  message << "results.h5 would take about " << h5_bytes / 1e9 << " GB (" << static_cast<long long>(frames) << " frames of "
          << model.particle_count() << " particles at 100 B each, and 8 kB a frame), more than ";
  if (h5_bytes > file_limit) message << "the file size limit of " << file_limit / 1e9 << " GB (ulimit -f)";
  else message << "the " << free_bytes / 1e9 << " GB free in " << folder;
  message << ": raise run.output_interval";
  throw Error(located(model_path, "settings/run@output_interval", message.str()));
}

// An error every rank of a distributed solve meets alike (they all read the same model) is
// printed once, by rank 0 (common/error.hpp).
[[noreturn]] void rethrow_shared(const Error& error) {
  if (solver::mpi::distributed() && !dynamic_cast<const SharedError*>(&error)) throw SharedError(error.what());
  throw;
}

void solve(const std::string& model_path, const std::string& folder, const StageOptions& options, std::ostream& log) {
  if (options.ranks > 1 && !solver::mpi::distributed()) {
    solve_on_ranks(model_path, folder, options, log);
    return;
  }
  Model model;
  try {
    model = read_model(model_path);
    check_results_fit(model, model_path, folder);
  } catch (const Error& error) {
    rethrow_shared(error);
  }
  solver::SolveOptions solve_options;
  solve_options.out_dir = folder;
  solve_options.progress = !options.quiet;
  solve_options.threads = options.threads;
  solve_options.checkpoint_interval = options.checkpoint_interval;
  solve_options.restart = options.restart;
  std::ostringstream discarded;
  solver::SolveSummary summary;
  try {
    summary = solver::solve(std::move(model), solve_options, options.quiet ? static_cast<std::ostream&>(discarded) : log);
  } catch (const Error& error) {
    // The solver's checks of the mesh and particles say "model: ...": name the file.
    const std::string message = error.what();
    if (message.rfind("model: ", 0) != 0) rethrow_shared(error);
    const Error located_error(located(model_path, "", message.substr(7)));
    if (solver::mpi::distributed()) throw SharedError(located_error.what());
    throw located_error;
  }
  if (!options.quiet) {
    solver::print_summary(summary, log);
    log << "wrote " << (fs::path(folder) / "results.h5").string() << " and results.xdmf\n";
  }
}

int post(const std::string& results_path, const std::string& folder, bool quiet, std::ostream& log) {
  std::ostringstream discarded;
  return postproc::run_post(results_path, folder, quiet ? static_cast<std::ostream&>(discarded) : log);
}

}  // namespace

std::string output_folder(const std::optional<std::string>& out, const Scene& scene) {
  return created_folder(out ? *out : (fs::path("out") / scene.name).string());
}

std::string mesh_stage(const std::string& scene_path, const StageOptions& options, std::ostream& log) {
  const Scene scene = load_scene(scene_path, options.overrides);
  const std::string folder = output_folder(options.out, scene);
  const FolderLock lock(folder);
  stamps::forget(folder);
  return mesh(scene, folder, options.quiet, log);
}

void solve_stage(const std::string& model_path, const StageOptions& options, std::ostream& log) {
  const std::string folder = folder_beside(options.out, model_path);
  if (!solver::mpi::distributed()) {
    const FolderLock lock(folder);
    stamps::forget(folder);
    solve(model_path, folder, options, log);
    return;
  }
  // One of several ranks (mpirun): rank 0 holds the folder's lock for them all, unless the
  // `--ranks` parent that started mpirun holds it already, when every rank takes it from the
  // parent (ranks_link.hpp); every rank learns whether it got it.
  std::optional<FolderLock> lock;
  std::string refused;
  if (launched_by_ranks_parent()) {
    take_lock_from_ranks_driver(folder);
  } else if (solver::mpi::rank() == 0) {
    try {
      lock.emplace(folder);
      stamps::forget(folder);
    } catch (const Error& error) {
      refused = error.what();
    }
  }
  solver::mpi::broadcast(refused, 0);
  if (!refused.empty()) throw SharedError(refused);
  solve(model_path, folder, options, log);
}

int post_stage(const std::string& results_path, const StageOptions& options, std::ostream& log) {
  const std::string folder = folder_beside(options.out, results_path);
  const FolderLock lock(folder);
  stamps::forget(folder);
  return post(results_path, folder, options.quiet, log);
}

int run_pipeline(const std::string& scene_path, const StageOptions& options, std::ostream& log) {
  const Scene scene = load_scene(scene_path, options.overrides);
  const std::string folder = output_folder(options.out, scene);
  const FolderLock lock(folder);
  const fs::path out(folder);
  uint64_t mesh_inputs = stamps::hash(scene.canonical_text, stamps::hash_file(scene.geometry, stamps::program()));
  // A motion record is read from its own file, which the scene's text only names.
  if (!scene.base_motion.time.empty()) {
    std::ostringstream record;
    record.precision(17);
    for (std::size_t k = 0; k < scene.base_motion.time.size(); ++k)
      record << scene.base_motion.time[k] << ' ' << scene.base_motion.acceleration[k].transpose() << '\n';
    mesh_inputs = stamps::hash(record.str(), mesh_inputs);
  }
  const uint64_t solve_inputs = stamps::hash("solve", mesh_inputs);
  const uint64_t post_inputs = stamps::hash_file(
      postproc::figure_script("animation.py"),
      stamps::hash_file(postproc::figures_script(), stamps::hash("post", solve_inputs)));
  auto up_to_date = [&](const char* stage, uint64_t inputs, const fs::path& output) {
    const bool same = fs::exists(output) && stamps::recorded(folder, stage) == inputs;
    if (same && !options.quiet) log << stage << ": inputs unchanged, skipped (" << output.string() << ")\n";
    return same;
  };
  if (!up_to_date("mesh", mesh_inputs, out / "model.h5")) {
    mesh(scene, folder, options.quiet, log);
    stamps::record(folder, "mesh", mesh_inputs);
  }
  if (options.restart || !up_to_date("solve", solve_inputs, out / "results.h5")) {
    solve((out / "model.h5").string(), folder, options, log);
    stamps::record(folder, "solve", solve_inputs);
  }
  if (!up_to_date("post", post_inputs, out / "metrics.json")) {
    const int status = post((out / "results.h5").string(), folder, options.quiet, log);
    if (status != 0) return status;
    stamps::record(folder, "post", post_inputs);
  }
  return 0;
}

}  // namespace talus::workflow
