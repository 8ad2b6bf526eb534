// talus: the one executable of the pipeline. Each subcommand is one stage (mesh, solve, post)
// or their chain (run); see `talus --help`.
#include <omp.h>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/cli.hpp"
#include "app/stamps.hpp"
#include "common/error.hpp"
#include "common/model.hpp"
#include "common/scene.hpp"
#include "preproc/preproc.hpp"
#include "postproc/postproc.hpp"
#include "solver/solver.hpp"
#include "workflow/fos.hpp"

namespace fs = std::filesystem;
using namespace talus;

namespace {

constexpr const char* kUsage = R"(talus: slope failure and landslide runout with the Material Point Method

Usage:
  talus mesh  SCENE.toml [--set KEY=VALUE]... [--out DIR]
        Mesh the scene's .geo with gmsh, seed particles, write DIR/model.h5.
  talus solve MODEL.h5 [--out DIR] [--threads N] [--quiet]
              [--checkpoint-interval T] [--restart]
        Run the explicit MPM time loop; write DIR/results.h5 and results.xdmf
        (default DIR: the model's folder). Ctrl-C or SIGTERM stops after the
        current step with a checkpoint (DIR/checkpoint.h5) and the frames so far.
  talus post  RESULTS.h5 [--out DIR]
        Runout, failure surface, Bishop's factor of safety or the validation
        comparison (as the scene's [post] asks): metrics.json, CSV, PNG figures
        (default DIR: the results' folder).
  talus run   [SCENE.toml] [--set KEY=VALUE]... [--out DIR]
        The pipeline on a scene (default geometries/slope.toml): mesh, solve, post.
  talus fos   SCENE.toml [--set KEY=VALUE]... [--out DIR] [--threads N] [--tolerance DF]
        Factor of safety by shear strength reduction (trials on N threads, bracket
        width DF, default 0.01): DIR/fos.json and fos.png (docs/fos.md).

Options:
  --set KEY=VALUE   override a scene value by its dotted TOML path, e.g.
                    --set run.end_time=2.0  --set contact.friction=0.4
  --out DIR         output folder (default out/<scene name>/)
  --quiet, -q       no progress output
  --threads N       OpenMP threads for the solver (default: all cores)
  --checkpoint-interval T
                    solve, run: write DIR/checkpoint.h5 every T s of simulated
                    time (default 0: only when interrupted)
  --restart         solve, run: continue from DIR/checkpoint.h5 and
                    DIR/results.h5; with --threads 1 the frames are the same,
                    bit for bit, as those of an uninterrupted run
  --help, -h        this text

Exit status: 0 on success, 1 on bad input or a failed run, 2 on an internal
error, 130 when stopped by SIGINT (Ctrl-C), 143 when stopped by SIGTERM.
)";

std::string output_folder(const cli::Arguments& args, const Scene& scene) {
  const fs::path folder = args.out ? fs::path(*args.out) : fs::path("out") / scene.name;
  fs::create_directories(folder);
  return folder.string();
}

std::string require_input(const cli::Arguments& args, const char* what) {
  if (args.positional.empty()) throw Error(std::string("missing ") + what + " (see talus --help)");
  if (args.positional.size() > 1) throw Error("unexpected argument '" + args.positional[1] + "' (see talus --help)");
  return args.positional.front();
}

// Stage 1: scene -> model.h5. Returns the model's path.
std::string mesh_stage(const Scene& scene, const std::string& folder, bool quiet) {
  preproc::MeshReport report;
  const Model model = preproc::build_model(scene, &report);
  const std::string path = (fs::path(folder) / "model.h5").string();
  write_model(path, model);
  if (!quiet) {
    preproc::print_report(report, std::cout);
    std::cout << "wrote " << path << std::endl;
  }
  return path;
}

// Stage 2: model.h5 -> results.h5.
void solve_stage(const std::string& model_path, const std::string& folder, const cli::Arguments& args) {
  const Model model = read_model(model_path);
  solver::SolveOptions options;
  options.out_dir = folder;
  options.progress = !args.quiet;
  options.threads = args.threads;
  options.checkpoint_interval = args.checkpoint_interval.value_or(0);
  options.restart = args.restart;
  std::ostringstream discarded;
  const solver::SolveSummary summary =
      solver::solve(model, options, args.quiet ? static_cast<std::ostream&>(discarded) : std::cout);
  if (!args.quiet) {
    solver::print_summary(summary, std::cout);
    std::cout << "wrote " << (fs::path(folder) / "results.h5").string() << " and results.xdmf\n";
  }
}

// Stage 3: results.h5 -> metrics.json, CSV, PNG. Returns the exit status (1: figures failed).
int post_stage(const std::string& results_path, const std::string& folder, bool quiet) {
  std::ostringstream quiet_log;
  return postproc::run_post(results_path, folder, quiet ? static_cast<std::ostream&>(quiet_log) : std::cout);
}

std::string folder_of(const std::string& path) {
  const std::string folder = fs::path(path).parent_path().string();
  return folder.empty() ? "." : folder;
}

// mesh + solve + post, skipping each stage whose inputs have not changed since it last ran here.
int run_pipeline(const Scene& scene, const std::string& folder, const cli::Arguments& args) {
  const fs::path out(folder);
  const uint64_t mesh_inputs =
      stamps::hash(scene.canonical_text, stamps::hash_file(scene.geometry, stamps::program()));
  const uint64_t solve_inputs = stamps::hash("solve", mesh_inputs);
  const uint64_t post_inputs = stamps::hash_file(postproc::figures_script(), stamps::hash("post", solve_inputs));
  auto up_to_date = [&](const char* stage, uint64_t inputs, const fs::path& output) {
    const bool same = fs::exists(output) && stamps::recorded(folder, stage) == inputs;
    if (same && !args.quiet) std::cout << stage << ": inputs unchanged, skipped (" << output.string() << ")\n";
    return same;
  };
  if (!up_to_date("mesh", mesh_inputs, out / "model.h5")) {
    mesh_stage(scene, folder, args.quiet);
    stamps::record(folder, "mesh", mesh_inputs);
  }
  if (args.restart || !up_to_date("solve", solve_inputs, out / "results.h5")) {
    solve_stage((out / "model.h5").string(), folder, args);
    stamps::record(folder, "solve", solve_inputs);
  }
  if (!up_to_date("post", post_inputs, out / "metrics.json")) {
    const int status = post_stage((out / "results.h5").string(), folder, args.quiet);
    if (status != 0) return status;
    stamps::record(folder, "post", post_inputs);
  }
  return 0;
}

workflow::FosOptions fos_options(const cli::Arguments& args) {
  if (args.positional.size() != 1) throw Error("fos: expected one scene file (see talus --help)");
  if (!args.flags.empty()) throw Error("fos: unknown option '" + args.flags.front() + "' (see talus --help)");
  workflow::FosOptions options;
  options.scene_path = args.positional.front();
  options.overrides = args.overrides;
  options.out = args.out;
  options.threads = args.threads;
  options.tolerance = args.tolerance;
  options.quiet = args.quiet;
  return options;
}

// The options a stage does not know are mistakes, not silently ignored.
void reject_unknown_options(const cli::Arguments& args, bool solves) {
  if (!args.flags.empty())
    throw Error("unknown option '" + args.flags.front() + "' for talus " + args.command + " (see talus --help)");
  if (!solves && (args.restart || args.checkpoint_interval))
    throw Error("--checkpoint-interval and --restart belong to solve or run, not " + args.command);
  if (args.tolerance) throw Error("--tolerance belongs to fos, not " + args.command);
}

int run_command(const cli::Arguments& args) {
  if (args.help || args.command.empty() || args.command == "help") {
    std::cout << kUsage;
    return args.command.empty() && !args.help ? 1 : 0;
  }
  if (args.command == "--version" || args.command == "version") {
    std::cout << "talus " << TALUS_VERSION << "\n";
    return 0;
  }
  if (args.command == "mesh" || args.command == "solve" || args.command == "post" || args.command == "run")
    reject_unknown_options(args, args.command == "solve" || args.command == "run");
  if (args.command == "mesh") {
    const Scene scene = load_scene(require_input(args, "scene file"), args.overrides);
    const std::string folder = output_folder(args, scene);
    stamps::forget(folder);
    mesh_stage(scene, folder, args.quiet);
    return 0;
  }
  if (args.command == "solve") {
    const std::string model_path = require_input(args, "model file");
    if (!args.overrides.empty()) throw Error("solve reads a model, not a scene: --set belongs to mesh or run");
    const std::string folder = args.out ? *args.out : folder_of(model_path);
    fs::create_directories(folder);
    stamps::forget(folder);
    solve_stage(model_path, folder, args);
    return 0;
  }
  if (args.command == "post") {
    const std::string results_path = require_input(args, "results file");
    if (!args.overrides.empty()) throw Error("post reads results, not a scene: --set belongs to mesh or run");
    const std::string folder = args.out ? *args.out : folder_of(results_path);
    fs::create_directories(folder);
    stamps::forget(folder);
    return post_stage(results_path, folder, args.quiet);
  }
  if (args.command == "fos") return workflow::run_fos(fos_options(args), std::cout);
  if (args.command == "run") {
    const std::string scene_path = args.positional.empty() ? "geometries/slope.toml" : require_input(args, "scene");
    const Scene scene = load_scene(scene_path, args.overrides);
    return run_pipeline(scene, output_folder(args, scene), args);
  }
  throw Error("unknown command '" + args.command + "' (expected mesh, solve, post, run or fos; see talus --help)");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const cli::Arguments args = cli::parse(argc, argv);
    if (args.threads > 0) omp_set_num_threads(args.threads);
    return run_command(args);
  } catch (const Error& e) {
    std::cerr << "talus: error: " << e.what() << "\n";
    return 1;
  } catch (const solver::Interrupted& e) {
    std::cerr << "talus: " << e.what() << "\n";
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::cerr << "talus: internal error: " << e.what() << "\n";
    return 2;
  } catch (const std::string& e) {  // the gmsh API throws its messages as strings
    std::cerr << "talus: internal error: " << e << "\n";
    return 2;
  }
}
