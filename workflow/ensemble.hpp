// `talus ensemble SCENE`: probabilistic runout by Monte Carlo over the scene's random fields
// (docs/ensemble.md). The scene is meshed once; realisation k draws its fields from seed S + k
// onto that model, solves it in memory and measures it (workflow/ensemble_realisation.hpp);
// realisations run side by side, one thread each, `jobs` at once. Each finished realisation is
// appended to OUT/realisations.csv as it ends, so that SIGINT or SIGTERM (which stop the running
// ones after their step and drop them) lose nothing finished, and a rerun of the same command
// runs only the missing ones: every row depends on its seed alone, so the result is the one an
// uninterrupted ensemble gives. At the end realisations.csv is rewritten in seed order, and
// OUT/ensemble.json (workflow/ensemble_statistics.hpp), OUT/fields.csv and the figures are written.
#pragma once
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace talus::workflow {

// Seeds are integers from 0 to this (2^53 - 1: exact in JSON and in a double).
inline constexpr std::uint64_t kMaxSeed = (std::uint64_t{1} << 53) - 1;
inline constexpr long kMaxRealisations = 1000000;

struct EnsembleOptions {
  std::string scene_path;
  std::vector<std::string> overrides;  // KEY=VALUE on the scene (--set)
  std::optional<std::string> out;      // default out/<scene name>/ensemble
  long realisations = 100;             // N, in [1, kMaxRealisations]
  std::uint64_t seed = 1;              // S, in [0, kMaxSeed - N + 1]
  int jobs = 0;                        // realisations at once (on each rank); 0: one per core (shared out)
  int ranks = 0;                       // --ranks R: the realisations over R MPI ranks; 0, 1: this process
  bool fos = false;                    // --fos: each realisation's factor of safety too
  std::optional<double> tolerance;     // --tolerance: --fos's bracket width (default solver::SearchSettings's)
  bool quiet = false;
  bool figures = true;                 // the PNGs (postproc/ensemble_figure.py)
};

// Returns the exit status: 0, or 1 when ensemble.json was written but the figures failed.
// Throws talus::Error on bad input (before anything is written) and solver::Interrupted when
// SIGINT or SIGTERM stopped it (the finished realisations kept in realisations.csv).
//
// With --ranks R (options.ranks > 1) this process starts R ranks under mpirun (workflow/launch.hpp)
// and waits (RanksFailed when they fail or are stopped); each rank, a `talus ensemble` under
// mpirun with the same options, meshes the scene and runs every R-th of the realisations left,
// from its own rank on, `jobs` at once; every 0.2 s rank 0 collects the finished rows of all and
// appends them to realisations.csv, and at the end writes the CSV and ensemble.json as one
// process would. A signal on any rank stops every rank.
int run_ensemble(const EnsembleOptions& options, std::ostream& log);

}  // namespace talus::workflow
