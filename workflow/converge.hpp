// `talus converge SCENE`: the scene's metrics at successively finer meshes, with their observed
// order, Richardson's extrapolate and Roache's grid convergence index as a numerical error band
// (workflow/gci.hpp, docs/converge.md). With --transfers, the finest level again with each
// transfer in OUT/finest_<transfer>, and the transfers' spread beside the band. Level k (k = 0 .. levels-1) runs `talus run` with
// mesh.size = h0 / ratio^k in OUT/level<k+1>_h<size>, so a rerun recomputes only the levels
// whose inputs changed (workflow/stamps.hpp). Writes OUT/converge.csv, OUT/converge.md and the
// figure OUT/converge.png (postproc/converge_figure.py).
#pragma once
#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace talus::workflow {

inline constexpr int kMinLevels = 2, kMaxLevels = 6;

struct ConvergeOptions {
  std::string scene_path;
  std::vector<std::string> overrides;  // KEY=VALUE on the scene (--set); mesh.size sets h0
  std::optional<std::string> out;      // default out/<scene name>/converge
  int levels = 3;                      // in [kMinLevels, kMaxLevels]
  double ratio = 2;                    // > 1: h(k+1) = h(k) / ratio
  int threads = 0;                     // the solver's threads; 0: all cores
  bool quiet = false;
  // --transfers: the finest level run again with each of these transfers (flip, apic, pic_blend,
  // xpic = XPIC(5), xpicM), and their spread reported beside the mesh band. Empty: none.
  std::vector<std::string> transfers;
};

// The metrics the study follows: metrics.json key (slip_circle: its r_m), name, unit.
struct ConvergeMetric {
  std::string key, name, unit;
};
const std::vector<ConvergeMetric>& converge_metrics();

// Returns the exit status: 0, or 1 when the tables were written but the figure failed.
// Throws talus::Error on bad options, a scene without a size, a level too large for memory
// (before any level runs), or a scene whose [post] metrics give none of converge_metrics().
int run_converge(const ConvergeOptions& options, std::ostream& log);

}  // namespace talus::workflow
