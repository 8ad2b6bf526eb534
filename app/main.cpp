// talus: the one executable of the pipeline. Each subcommand is one stage (mesh, solve, post),
// their chain (run) or the factor of safety (fos); see `talus --help`. This file parses the
// command line and calls the workflow library (workflow/pipeline.hpp, workflow/fos.hpp).
#include <omp.h>

#include <iostream>

#include "app/cli.hpp"
#include "common/error.hpp"
#include "postproc/figure_script.hpp"
#include "solver/parallel/parallel.hpp"
#include "solver/solver.hpp"
#include "workflow/converge.hpp"
#include "workflow/fos.hpp"
#include "workflow/launch.hpp"
#include "workflow/pipeline.hpp"

using namespace talus;

namespace {

constexpr const char* kUsage = R"(talus: slope failure and landslide runout with the Material Point Method

Usage:
  talus mesh  SCENE.toml [--set KEY=VALUE]... [--out DIR]
        Mesh the scene's .geo with gmsh, seed particles, write DIR/model.h5.
  talus solve MODEL.h5 [--out DIR] [--threads N] [--ranks N] [--quiet]
              [--checkpoint-interval T] [--restart]
        Run the explicit MPM time loop; write DIR/results.h5 and results.xdmf
        (default DIR: the model's folder). Ctrl-C or SIGTERM stops after the
        current step with a checkpoint (DIR/checkpoint.h5) and the frames so far.
        Also: mpirun -n N talus solve MODEL.h5 (docs/scaling.md).
  talus post  RESULTS.h5 [--out DIR]
        Runout, failure surface, Bishop's factor of safety or the validation
        comparison (as the scene's [post] asks): metrics.json, CSV, PNG figures,
        runout.mp4 and runout.gif unless post.animate = false (default DIR: the
        results' folder).
  talus run   [SCENE.toml] [--set KEY=VALUE]... [--out DIR] [--ranks N]
        The pipeline on a scene (default geometries/slope.toml): mesh, solve, post.
  talus fos   SCENE.toml [--set KEY=VALUE]... [--out DIR] [--threads N] [--tolerance DF]
        Factor of safety by shear strength reduction (trials on N threads, bracket
        width DF, default 0.01): DIR/fos.json and fos.png (docs/fos.md).
  talus converge SCENE.toml [--levels N] [--ratio R] [--set KEY=VALUE]... [--out DIR]
              [--threads N]
        Mesh convergence: the scene run at mesh.size h0, h0/R, ... (N levels, default
        3, in [2, 6]; R > 1, default 2; h0 the scene's size) in DIR/level<k>_h<size>
        (default DIR: out/<scene name>/converge); each metric with its observed order
        and grid convergence index: DIR/converge.csv, converge.md, converge.png
        (docs/converge.md).

Options:
  --set KEY=VALUE   override a scene value by its dotted TOML path, e.g.
                    --set run.end_time=2.0  --set contact.friction=0.4
  --out DIR         output folder (default out/<scene name>/)
  --quiet, -q       no progress output
  --threads N       OpenMP threads for the solver (default: chosen from the
                    particle count and the cores, stated in the summary line)
  --ranks N         solve, run: the solve on N MPI ranks of this machine
                    (mpirun -n N --oversubscribe), each with its own threads
                    (--threads, else the cores shared out); the frames agree
                    with one rank's (docs/scaling.md)
  --checkpoint-interval T
                    solve, run: write DIR/checkpoint.h5 every T s of simulated
                    time (default 0: only when interrupted)
  --restart         solve, run: continue from DIR/checkpoint.h5 and
                    DIR/results.h5; on the same thread count the frames are
                    the same, bit for bit, as those of an uninterrupted run
  --help, -h        this text

Exit status: 0 on success, 1 on bad input or a failed run, 2 on an internal
error, 130 when stopped by SIGINT (Ctrl-C), 143 when stopped by SIGTERM.
)";

std::string require_input(const cli::Arguments& args, const char* what) {
  if (args.positional.empty()) throw Error(std::string("missing ") + what + " (see talus --help)");
  if (args.positional.size() > 1) throw Error("unexpected argument '" + args.positional[1] + "' (see talus --help)");
  return args.positional.front();
}

workflow::StageOptions stage_options(const cli::Arguments& args) {
  workflow::StageOptions options;
  options.overrides = args.overrides;
  options.out = args.out;
  options.quiet = args.quiet;
  options.threads = args.threads;
  options.ranks = args.ranks;
  // The ranks of a distributed solve other than rank 0 print nothing (rank 0 speaks for all).
  if (solver::mpi::rank() > 0) options.quiet = true;
  options.checkpoint_interval = args.checkpoint_interval.value_or(0);
  options.restart = args.restart;
  return options;
}

workflow::ConvergeOptions converge_options(const cli::Arguments& args) {
  if (args.positional.size() != 1) throw Error("converge: expected one scene file (see talus --help)");
  if (!args.flags.empty()) throw Error("converge: unknown option '" + args.flags.front() + "' (see talus --help)");
  if (args.restart || args.checkpoint_interval)
    throw Error("--checkpoint-interval and --restart belong to solve or run, not converge");
  if (args.tolerance) throw Error("--tolerance belongs to fos, not converge");
  workflow::ConvergeOptions options;
  options.scene_path = args.positional.front();
  options.overrides = args.overrides;
  options.out = args.out;
  options.threads = args.threads;
  options.quiet = args.quiet;
  if (args.levels) options.levels = *args.levels;
  if (args.ratio) options.ratio = *args.ratio;
  return options;
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
  if (!solves && args.ranks) throw Error("--ranks belongs to solve or run, not " + args.command);
  if (args.tolerance) throw Error("--tolerance belongs to fos, not " + args.command);
  if (args.levels || args.ratio) throw Error("--levels and --ratio belong to converge, not " + args.command);
}

int run_command(const cli::Arguments& args) {
  if (args.help || (args.command.empty() && args.flags.empty()) || args.command == "help") {
    std::cout << kUsage;
    return args.command.empty() && !args.help ? 1 : 0;
  }
  const bool version_flag = args.flags.size() == 1 && args.flags.front() == "--version" && args.command.empty();
  if (version_flag || args.command == "version") {
    std::cout << "talus " << TALUS_VERSION
              << (!solver::mpi::built_with_mpi() ? " (without MPI: one rank)"
                  : solver::mpi::parallel_hdf5()
                      ? " (with MPI and parallel HDF5: solve --ranks N, or mpirun -n N talus solve)"
                      : " (with MPI: solve --ranks N, or mpirun -n N talus solve)")
              << "\n";
    return 0;
  }
  if (args.command.empty()) throw Error("unknown option '" + args.flags.front() + "' (see talus --help)");
  if (solver::mpi::distributed() && args.command != "solve")
    throw SharedError("under mpirun only `talus solve MODEL.h5` runs (on every rank); for the pipeline on several "
                      "ranks use `talus run SCENE --ranks N` (see talus --help)");
  if (args.command == "mesh" || args.command == "solve" || args.command == "post" || args.command == "run")
    reject_unknown_options(args, args.command == "solve" || args.command == "run");
  if (args.command == "mesh") {
    workflow::mesh_stage(require_input(args, "scene file"), stage_options(args), std::cout);
    return 0;
  }
  if (args.command == "solve") {
    const std::string model_path = require_input(args, "model file");
    if (!args.overrides.empty()) throw Error("solve reads a model, not a scene: --set belongs to mesh or run");
    workflow::solve_stage(model_path, stage_options(args), std::cout);
    return 0;
  }
  if (args.command == "post") {
    const std::string results_path = require_input(args, "results file");
    if (!args.overrides.empty()) throw Error("post reads results, not a scene: --set belongs to mesh or run");
    return workflow::post_stage(results_path, stage_options(args), std::cout);
  }
  if (args.command == "fos") {
    if (args.levels || args.ratio) throw Error("--levels and --ratio belong to converge, not fos");
    return workflow::run_fos(fos_options(args), std::cout);
  }
  if (args.command == "converge") return workflow::run_converge(converge_options(args), std::cout);
  if (args.command == "run") {
    const std::string scene_path = args.positional.empty() ? "geometries/slope.toml" : require_input(args, "scene");
    return workflow::run_pipeline(scene_path, stage_options(args), std::cout);
  }
  throw Error("unknown command '" + args.command + "' (expected mesh, solve, post, run, fos or converge; see talus --help)");
}

// One message for the whole run: with several ranks, an error every rank meets alike
// (SharedError) and an interruption are printed by rank 0 alone and every rank exits; an error of
// one rank names it and stops them all (the others may be waiting for it).
void print_error(const std::string& message, bool name_rank) {
  const std::string who = name_rank && solver::mpi::distributed() ? " (rank " + std::to_string(solver::mpi::rank()) + ")" : "";
  // Messages echo input; whatever slipped through uncut stops at 4000 characters.
  std::cerr << "talus: error" << who << ": " << message.substr(0, 4000)
            << (message.size() > 4000 ? "... (message cut at 4000 of " + std::to_string(message.size()) + " characters)"
                                      : "")
            << std::endl;
}

int one_rank_failed(int status) {
  if (solver::mpi::distributed()) solver::mpi::abort_all(status);
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  solver::bound_openmp_spin(argv);
  solver::mpi::init(&argc, &argv);
  const bool speaks = solver::mpi::rank() == 0;
  try {
    const cli::Arguments args = cli::parse(argc, argv);
    if (args.threads > 0) omp_set_num_threads(args.threads);
    return run_command(args);
  } catch (const SharedError& e) {
    if (speaks) print_error(e.what(), false);
    return 1;
  } catch (const Error& e) {
    print_error(e.what(), true);
    return one_rank_failed(1);
  } catch (const workflow::RanksFailed& e) {
    return e.status;  // rank 0 has said why
  } catch (const solver::Interrupted& e) {
    if (speaks) std::cerr << "talus: " << e.what() << "\n";
    return 128 + e.signal;
  } catch (const postproc::FiguresInterrupted& e) {
    std::cerr << "talus: " << e.what() << "\n";
    return 128 + e.signal;
  } catch (const std::exception& e) {
    std::cerr << "talus: internal error: " << e.what() << "\n";
    return one_rank_failed(2);
  } catch (const std::string& e) {  // the gmsh API throws its messages as strings
    std::cerr << "talus: internal error: " << e << "\n";
    return 2;
  }
}
