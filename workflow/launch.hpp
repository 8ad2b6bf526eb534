// `--ranks N` (solve, run): the solve on N MPI ranks of this machine, without typing mpirun.
// This process, which holds the output folder's lock, starts
//   mpirun -n N --oversubscribe --bind-to none --quiet talus solve MODEL --out DIR ...
// with TALUS_RANKS_CHILD=1 in the ranks' environment (they leave the lock and the stamps to this
// process), and waits. Ctrl-C and SIGTERM here reach the ranks as OpenMPI forwards them: as
// SIGUSR1 and SIGUSR2, which a distributed solve takes for SIGINT and SIGTERM (it stops after
// the step with a checkpoint); a second one stops mpirun at once. Rank 0 prints the progress,
// the summary and any error; this process exits with the ranks' status, and adds a message
// only when a rank was killed by a signal (128 + its number, as mpirun reports it).
// The ranks hold the output folder's lock with this process, and stop when it is gone
// (workflow/ranks_link.hpp): a `kill -9` of this process leaves no rank writing unlocked.
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "workflow/pipeline.hpp"

namespace talus::workflow {

// The variable a `--ranks` parent sets for the ranks it starts.
constexpr const char* kRanksChildVariable = "TALUS_RANKS_CHILD";

// This process is a rank that a `--ranks` parent started.
bool launched_by_ranks_parent();

// The ranks stopped with a non-zero status: the driver exits with it. Rank 0 has said why, or,
// when a rank was killed by a signal (which no rank can report), `message` says which.
struct RanksFailed {
  int status;
  std::string message;
};

// Solves `model_path` into `folder` on options.ranks ranks under mpirun. Throws talus::Error when
// mpirun cannot be started (this talus built without MPI, openmpi-bin missing) and RanksFailed
// when the ranks fail or are stopped.
void solve_on_ranks(const std::string& model_path, const std::string& folder, const StageOptions& options,
                    std::ostream& log);

// What a `--ranks` command runs: `ranks` copies of this program with `arguments` (the command and
// its options) under mpirun, writing into `folder`, whose lock this process holds. `doing` is
// said before they start ("solving"), unless `quiet`; `kept` ends the message of a rank killed by
// a signal (what the folder keeps). Throws as solve_on_ranks does.
struct RanksCommand {
  int ranks = 2;
  std::vector<std::string> arguments;
  std::string folder;
  bool quiet = false;
  std::string doing;
  std::string kept;
};
void run_on_ranks(const RanksCommand& command, std::ostream& log);

// On a rank that a `--ranks` driver started: takes the folder's lock from the driver
// (ranks_link.hpp). Collective; throws SharedError, on every rank, when a rank could not.
void take_lock_from_ranks_driver(const std::string& folder);

}  // namespace talus::workflow
