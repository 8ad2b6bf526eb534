// The stability benchmark's granular-flow study (issue 13, item 8): the cohesionless column
// collapse at a = 0.5 and a = 3 and the default slope without cohesion, each run to rest at
// several CFL numbers. A row records whether the run completed or stopped (and how), whether a
// particle left the domain, the non-finite values in results.h5, and how far the front went.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "common/h5.hpp"
#include "stability.hpp"

namespace talus::bench::stability {
namespace {

using bench::fixed;
using bench::general;

struct GranularScene {
  std::string name, scene;
  std::vector<std::string> overrides;
  std::string note;
};

// The farthest particle's x in the first and the last frame of results.h5.
std::pair<double, double> front_positions(const std::string& results) {
  const h5::File file = h5::File::open_read(results);
  h5::Dims dims;
  const auto position = h5::read_doubles(file, "frames/position", &dims);
  const std::size_t frames = dims[0], n = dims[1];
  double first = -1e300, last = -1e300;
  for (std::size_t p = 0; p < n; ++p) {
    first = std::max(first, position[2 * p]);
    last = std::max(last, position[((frames - 1) * n + p) * 2]);
  }
  return {first, last};
}

}  // namespace

std::string granular_cases(const Options& options, std::vector<GranularRow>& rows) {
  const std::vector<GranularScene> scenes = {
      {"column a = 0.5", "column_collapse", {"mesh.size=0.01"}, "L0 = 0.2 m, mesh.size 0.01 m"},
      {"column a = 3", "column_collapse", {"mesh.parameters.a=3", "mesh.parameters.L0=0.0816", "mesh.size=0.01"},
       "L0 = 0.0816 m, mesh.size 0.01 m"},
      {"slope, c = 0", "slope", {"materials.sand.cohesion=0", "mesh.size=0.5"}, "mesh.size 0.5 m"},
  };
  const std::vector<double> cfls = options.quick ? std::vector<double>{0.5, 1.0} : std::vector<double>{0.2, 0.5, 0.8, 1.0};
  for (const GranularScene& scene : scenes) {
    const Model base = build_scene(scene.scene, scene.overrides);
    for (double cfl : cfls) {
      Model model = base;
      model.run.cfl = cfl;
      bench::Scratch scratch("stability-granular");
      std::fprintf(stderr, "granular: %s at CFL %.2g ...", scene.name.c_str(), cfl);
      std::fflush(stderr);
      GranularRow row{scene.name, scene.note, cfl, run_and_scan(model, scratch.path().string(), options.threads)};
      if (row.outcome.scan.exists && row.outcome.scan.frames > 0) {
        const auto [first, last] = front_positions(scratch.file("results.h5"));
        row.front_advance = last - first;
      }
      row.left_domain = row.outcome.kind == "left the domain";
      std::fprintf(stderr, " %s after %ld steps (%.1f s), front +%.3f m, %ld non-finite\n", row.outcome.kind.c_str(),
                   row.outcome.steps, row.outcome.wall_seconds, row.front_advance, row.outcome.scan.nonfinite);
      rows.push_back(row);
    }
  }
  std::vector<std::vector<std::string>> table;
  for (const GranularRow& r : rows)
    table.push_back({r.scene, general(r.cfl, 3), r.outcome.kind, r.left_domain ? "1" : "0",
                     std::to_string(r.outcome.scan.nonfinite), std::to_string(r.outcome.steps),
                     fixed(r.outcome.wall_seconds, 2), general(r.front_advance, 4), r.outcome.message});
  write_table((std::filesystem::path(options.out) / "stability_granular.csv").string(),
              {"scene", "cfl", "outcome", "particle_left_domain", "nonfinite_values", "steps", "wall_seconds",
               "front_advance_m", "message"},
              table);
  std::ostringstream md;
  md << "## Granular flow\n\n"
     << "The cohesionless column collapse (geometries/column_collapse.toml) at a = 0.5 and a = 3 and the default "
        "slope with cohesion 0, each run to rest (or end_time) at each CFL. `front` is the farthest particle's x "
        "at the end minus at the start. A particle leaving the domain stops the run (\"left the domain\").\n\n"
     << "| scene | CFL | outcome | particle left | non-finite values | steps | wall (s) | front (m) |\n"
     << "|---|---:|---|---|---:|---:|---:|---:|\n";
  for (const GranularRow& r : rows)
    md << "| " << r.scene << " (" << r.note << ") | " << general(r.cfl, 3) << " | " << r.outcome.kind
       << (r.outcome.message.empty() ? "" : ": " + short_message(r.outcome.message)) << " | "
       << (r.left_domain ? "**yes**" : "no") << " | " << r.outcome.scan.nonfinite << " | " << r.outcome.steps << " | "
       << fixed(r.outcome.wall_seconds, 1) << " | " << fixed(r.front_advance, 3) << " |\n";
  return md.str() + "\n";
}

}  // namespace talus::bench::stability
