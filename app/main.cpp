// talus: the one executable of the pipeline. Each subcommand is one stage (mesh, solve, post),
// their chain (run) or the factor of safety (fos); see `talus --help`. This file parses the
// command line and calls the workflow library (workflow/pipeline.hpp, workflow/fos.hpp).
#include <omp.h>
#include <signal.h>
#include <unistd.h>

#include <exception>
#include <iostream>
#include <new>
#include <sstream>

#include "app/cli.hpp"
#include "common/error.hpp"
#include "postproc/figure_script.hpp"
#include "solver/parallel/parallel.hpp"
#include "solver/solver.hpp"
#include "workflow/converge.hpp"
#include "workflow/ensemble.hpp"
#include "workflow/folder_lock.hpp"
#include "workflow/fos.hpp"
#include "workflow/launch.hpp"
#include "workflow/pipeline.hpp"
#include "workflow/ranks_link.hpp"

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
              [--threads N] [--transfers LIST]
        Mesh convergence: the scene run at mesh.size h0, h0/R, ... (N levels, default
        3, in [2, 6]; R > 1, default 2; h0 the scene's size) in DIR/level<k>_h<size>
        (default DIR: out/<scene name>/converge); each metric with its observed order
        and grid convergence index: DIR/converge.csv, converge.md, converge.png
        (docs/converge.md). --transfers flip,apic,xpic also runs the finest level with
        each transfer (xpic: order 5) and reports their spread beside the band.
  talus ensemble SCENE.toml [--realisations N] [--seed S] [--jobs J] [--ranks R]
              [--fos [--tolerance DF]] [--set KEY=VALUE]... [--out DIR]
        Probabilistic runout over the scene's [random] fields: meshes once, then
        realisation k (of N, default 100) draws its fields from seed S + k (default
        S = 1), solves and measures them; J realisations at once, one thread each
        (default one per core). --ranks R: the realisations shared over R MPI ranks
        (mpirun), J at once on each (default: the cores shared out). --fos: each
        realisation's factor of safety too, by strength reduction as talus fos
        (several times the cost). Ctrl-C stops; the same command again resumes with
        the same answer. DIR/realisations.csv, ensemble.json (probability of
        failure with its 95 % interval, runout quantiles, exceedance curve, reach
        along the ground) and figures (default DIR: out/<scene name>/ensemble;
        docs/ensemble.md).

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
                    with one rank's (docs/scaling.md). ensemble: the
                    realisations over N ranks, the rows those of one process
  --checkpoint-interval T
                    solve, run: write DIR/checkpoint.h5 every T s of simulated
                    time (default 0: only when interrupted)
  --restart         solve, run: continue from DIR/checkpoint.h5 and
                    DIR/results.h5; on the same thread count the frames are
                    the same, bit for bit, as those of an uninterrupted run
  --help, -h        this text

Exit status: 0 on success, 1 on bad input or a failed run, 2 on an internal
error, 3 when memory ran out, 130 when stopped by SIGINT (Ctrl-C), 143 when
stopped by SIGTERM; with --ranks, 128 + N when a rank was killed by signal N.
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

// What the studies of a scene (converge, fos) take alike: one scene file, --set, --out,
// --threads, --quiet.
template <class Options>
Options scene_study_options(const cli::Arguments& args, const std::string& command) {
  if (args.positional.size() != 1) throw Error(command + ": expected one scene file (see talus --help)");
  if (!args.flags.empty()) throw Error(command + ": unknown option '" + args.flags.front() + "' (see talus --help)");
  Options options;
  options.scene_path = args.positional.front();
  options.overrides = args.overrides;
  options.out = args.out;
  options.threads = args.threads;
  options.quiet = args.quiet;
  return options;
}

workflow::ConvergeOptions converge_options(const cli::Arguments& args) {
  auto options = scene_study_options<workflow::ConvergeOptions>(args, "converge");
  if (args.restart || args.checkpoint_interval)
    throw Error("--checkpoint-interval and --restart belong to solve or run, not converge");
  if (args.tolerance) throw Error("--tolerance belongs to fos, not converge");
  if (args.levels) options.levels = *args.levels;
  if (args.ratio) options.ratio = *args.ratio;
  if (args.transfers) {
    std::stringstream list(*args.transfers);
    for (std::string name; std::getline(list, name, ',');) {
      try {
        transfer_overrides(name);  // an unknown name stops here, before anything runs
      } catch (const Error& error) {
        throw Error(std::string("converge: --transfers: ") + error.what());
      }
      options.transfers.push_back(name);
    }
    if (options.transfers.empty()) throw Error("--transfers: expected a comma-separated list such as flip,apic,xpic");
  }
  return options;
}

workflow::FosOptions fos_options(const cli::Arguments& args) {
  auto options = scene_study_options<workflow::FosOptions>(args, "fos");
  options.tolerance = args.tolerance;
  return options;
}

// The options a stage does not know are mistakes, not silently ignored.
// `talus ensemble`'s options; the others are mistakes here.
workflow::EnsembleOptions ensemble_options(const cli::Arguments& args) {
  if (args.positional.size() != 1) throw Error("ensemble: expected one scene file (see talus --help)");
  if (!args.flags.empty()) throw Error("ensemble: unknown option '" + args.flags.front() + "' (see talus --help)");
  if (args.threads) throw Error("--threads belongs to solve, run, fos and converge: ensemble runs each realisation on one thread, --jobs at once");
  if (args.restart || args.checkpoint_interval)
    throw Error("--checkpoint-interval and --restart belong to solve or run: ensemble resumes by itself when run again");
  if (args.levels || args.ratio || args.transfers)
    throw Error("--levels, --ratio and --transfers do not belong to ensemble");
  if (args.tolerance && !args.fos) throw Error("--tolerance: the bracket width of --fos's search; give --fos with it");
  workflow::EnsembleOptions options;
  options.scene_path = args.positional.front();
  options.overrides = args.overrides;
  options.out = args.out;
  options.quiet = args.quiet;
  if (args.realisations) options.realisations = *args.realisations;
  if (args.jobs) options.jobs = *args.jobs;
  options.ranks = args.ranks;
  options.fos = args.fos;
  options.tolerance = args.tolerance;
  if (args.seed) {
    const std::string& text = *args.seed;
    const bool digits = !text.empty() && text.size() <= 16 && text.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stoull(text) > workflow::kMaxSeed)
      throw Error("--seed: expected an integer from 0 to " + std::to_string(workflow::kMaxSeed) + ", got '" + text + "'");
    options.seed = std::stoull(text);
  }
  return options;
}

void reject_unknown_options(const cli::Arguments& args, bool solves) {
  if (!args.flags.empty())
    throw Error("unknown option '" + args.flags.front() + "' for talus " + args.command + " (see talus --help)");
  if (!solves && (args.restart || args.checkpoint_interval))
    throw Error("--checkpoint-interval and --restart belong to solve or run, not " + args.command);
  if (!solves && args.ranks) throw Error("--ranks belongs to solve, run or ensemble, not " + args.command);
  if (args.tolerance) throw Error("--tolerance belongs to fos, not " + args.command);
  if (args.levels || args.ratio || args.transfers)
    throw Error("--levels, --ratio and --transfers belong to converge, not " + args.command);
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
  // An ensemble runs under mpirun only as the ranks of `talus ensemble --ranks N`, which hold its
  // folder's lock from the process that started them.
  if (solver::mpi::distributed() && args.command != "solve" &&
      !(args.command == "ensemble" && workflow::launched_by_ranks_parent()))
    throw SharedError("under mpirun only `talus solve MODEL.h5` runs (on every rank); for the pipeline on several "
                      "ranks use `talus run SCENE --ranks N`, for an ensemble `talus ensemble SCENE --ranks N` "
                      "(see talus --help)");
  if (args.command != "ensemble" && (args.realisations || args.seed || args.jobs))
    throw Error("--realisations, --seed and --jobs belong to ensemble, not " + args.command);
  if (args.command != "ensemble" && args.fos)
    throw Error("--fos belongs to ensemble (each realisation's factor of safety), not " + args.command +
                (args.command == "fos" ? "" : "; the factor of safety of a scene is `talus fos SCENE`"));
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
    if (args.levels || args.ratio || args.transfers)
      throw Error("--levels, --ratio and --transfers belong to converge, not fos");
    return workflow::run_fos(fos_options(args), std::cout);
  }
  if (args.command == "ensemble") return workflow::run_ensemble(ensemble_options(args), std::cout);
  if (args.command == "converge") return workflow::run_converge(converge_options(args), std::cout);
  if (args.command == "run") {
    const std::string scene_path = args.positional.empty() ? "geometries/slope.toml" : require_input(args, "scene");
    return workflow::run_pipeline(scene_path, stage_options(args), std::cout);
  }
  throw Error("unknown command '" + args.command + "' (expected mesh, solve, post, run, fos, converge or ensemble; see talus --help)");
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
  workflow::tell_ranks_driver_exit(status);  // before MPI_Abort: this rank has said why
  if (solver::mpi::distributed()) solver::mpi::abort_all(status);
  return status;
}

// Memory ran out: one message, exit status 3 (docs/robustness.md).
constexpr int kOutOfMemoryStatus = 3;

std::string out_of_memory_message(const std::string& command) {
  return "out of memory" + (command.empty() ? std::string() : " in talus " + command) +
         " (std::bad_alloc): the machine, or a limit on this process (ulimit -v, a cgroup), gave less than it "
         "needs; free memory, raise the limit, or mesh coarser (a larger mesh.size)";
}

// The command being run, for the messages of a fault that no handler sees (below).
std::string running_command;

// An exception that leaves an OpenMP region (gmsh meshes in them; so does the solver) cannot be
// caught: std::terminate is called. Out of memory and gmsh's errors still get one message.
[[noreturn]] void on_terminate() {
  std::string message = "internal error: terminated";
  int status = 2;
  if (const std::exception_ptr current = std::current_exception()) {
    try {
      std::rethrow_exception(current);
    } catch (const std::bad_alloc&) {
      message = "error: " + out_of_memory_message(running_command);
      status = kOutOfMemoryStatus;
    } catch (const std::string& text) {  // gmsh 4.8's errors
      message = "error: gmsh failed in a parallel region (talus " + running_command + "): " + text;
      status = 1;
    } catch (const std::exception& e) {
      message = std::string("internal error: ") + e.what();
    } catch (...) {
    }
  }
  const std::string line = "talus: " + message.substr(0, 4000) + "\n";
  [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, line.data(), line.size());
  workflow::FolderLock::release_all_after_fatal_error();
  workflow::tell_ranks_driver_exit(status);
  _exit(status);
}

int run_main(int argc, char** argv) {
  const bool speaks = solver::mpi::rank() == 0;
  try {
    const cli::Arguments args = cli::parse(argc, argv);
    running_command = args.command;
    if (args.threads > 0) omp_set_num_threads(args.threads);
    return run_command(args);
  } catch (const solver::OutOfMemory& e) {
    print_error(e.what(), true);
    return one_rank_failed(kOutOfMemoryStatus);
  } catch (const std::bad_alloc&) {
    print_error(out_of_memory_message(running_command), true);
    return one_rank_failed(kOutOfMemoryStatus);
  } catch (const SharedError& e) {
    if (speaks) print_error(e.what(), false);
    return 1;
  } catch (const Error& e) {
    print_error(e.what(), true);
    return one_rank_failed(1);
  } catch (const workflow::RanksFailed& e) {
    if (!e.message.empty()) print_error(e.message, false);
    return e.status;  // otherwise rank 0 has said why
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

}  // namespace

int main(int argc, char** argv) {
  std::set_terminate(on_terminate);
  // A file size limit (ulimit -f) fails the write (EFBIG), which names the file and removes the
  // temporary one, instead of killing the process (SIGXFSZ).
  signal(SIGXFSZ, SIG_IGN);
  solver::bound_openmp_spin(argv);
  solver::bound_openmp_threads();
  solver::mpi::init(&argc, &argv);
  const int status = run_main(argc, argv);
  workflow::tell_ranks_driver_exit(status);
  return status;
}
