// Command-line parsing for the talus executable: one positional input, repeated --set,
// and a few flags. Kept apart from main so that the subcommands read top-down.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace talus::cli {

// --ranks is at most this (all on this machine: mpirun --oversubscribe).
constexpr int kMaxRanks = 256;

struct Arguments {
  std::string command;
  std::vector<std::string> positional;
  std::vector<std::string> overrides;  // --set KEY=VALUE
  std::optional<std::string> out;      // --out DIR
  bool quiet = false;                  // --quiet
  bool help = false;                   // --help / -h
  int threads = 0;                     // --threads N (0: all cores)
  int ranks = 0;                       // --ranks N (solve, run, ensemble: MPI ranks; 0: none asked)
  std::optional<double> checkpoint_interval;  // --checkpoint-interval T (s of simulated time)
  bool restart = false;                       // --restart
  std::optional<double> tolerance;            // --tolerance DF (fos: bracket width)
  std::optional<int> levels;                  // --levels N (converge)
  std::optional<double> ratio;                // --ratio R (converge)
  std::optional<std::string> transfers;       // --transfers LIST (converge)
  std::optional<long> realisations;           // --realisations N (ensemble)
  std::optional<std::string> seed;            // --seed S (ensemble; checked there)
  std::optional<int> jobs;                    // --jobs J (ensemble)
  bool fos = false;                           // --fos (ensemble)
  std::vector<std::string> flags;      // other --name[=value] options, for subcommands
};

// Throws talus::Error on a malformed command line.
Arguments parse(int argc, char** argv);

}  // namespace talus::cli
