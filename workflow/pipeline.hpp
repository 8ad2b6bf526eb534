// The stages of `talus`: mesh (scene -> model.h5), solve (model.h5 -> results.h5), post
// (results.h5 -> metrics.json, CSV, PNG), and their chain `talus run`, which re-runs only the
// stages whose inputs changed since they last ran in the folder (workflow/stamps.hpp). A stage
// run on its own forgets the folder's stamps. Progress goes to `log` unless quiet.
#pragma once
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "common/scene/scene.hpp"

namespace talus::workflow {

struct StageOptions {
  std::vector<std::string> overrides;  // mesh, run: KEY=VALUE on the scene (--set); ignored by solve, post
  // Output folder (created). Default: out/<scene name> for mesh and run, the input's own
  // folder for solve and post.
  std::optional<std::string> out;
  bool quiet = false;
  int threads = 0;                  // solve: OpenMP threads; 0: OpenMP's default
  double checkpoint_interval = 0;   // solve: simulated s between checkpoints; 0: only when stopped
  bool restart = false;             // solve: continue from FOLDER/checkpoint.h5 (run: always solves)
  int ranks = 0;                    // solve, run: MPI ranks of the solve (--ranks; > 1: under mpirun)
};

// `out`, else out/<scene name>; created.
std::string output_folder(const std::optional<std::string>& out, const Scene& scene);

// Scene file -> FOLDER/model.h5. Returns the model's path.
std::string mesh_stage(const std::string& scene_path, const StageOptions& options, std::ostream& log);

// model.h5 -> FOLDER/results.h5 and results.xdmf.
void solve_stage(const std::string& model_path, const StageOptions& options, std::ostream& log);

// results.h5 -> FOLDER/metrics.json, CSV, PNG. Returns the exit status (1: figures failed).
int post_stage(const std::string& results_path, const StageOptions& options, std::ostream& log);

// mesh, solve and post of a scene in one folder, each skipped when its inputs are unchanged
// and its output exists. Returns the exit status (1: figures failed).
int run_pipeline(const std::string& scene_path, const StageOptions& options, std::ostream& log);

}  // namespace talus::workflow
