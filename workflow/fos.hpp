// `talus fos SCENE`: factor of safety by shear strength reduction with MPM (docs/fos.md). The
// scene is meshed in memory, brought to equilibrium and its factor bracketed by trials run side
// by side (solver/strength_reduction.hpp); the slope, the slip surface of the smallest failing
// trial and Bishop's critical circle come from postproc (analysed_slope.hpp,
// failure_surface.hpp). Writes OUT/fos.json, OUT/fos_particles.csv and the figure OUT/fos.png.
#pragma once
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace talus::workflow {

struct FosOptions {
  std::string scene_path;
  std::vector<std::string> overrides;  // KEY=VALUE on the scene (--set)
  std::optional<std::string> out;      // output folder (created); default out/<scene name>
  int threads = 0;                     // parallel trials, one core each; 0: all cores
  std::optional<double> tolerance;     // bracket width; default solver::SearchSettings's
  bool quiet = false;                  // nothing to `log`
};

// Returns the exit status: 0, or 1 when fos.json was written but the figure failed. Throws
// talus::Error on a scene it cannot analyse (no slope, not Mohr-Coulomb, no equilibrium).
int run_fos(const FosOptions& options, std::ostream& log);

}  // namespace talus::workflow
