#include "support/bad_input_table.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "support/test_support.hpp"

namespace talus::testing {

namespace fs = std::filesystem;

const char* const kGeo = R"(lc = 0.25;
Point(1) = {0, 0, 0, lc}; Point(2) = {2, 0, 0, lc}; Point(3) = {2, 1, 0, lc}; Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("domain") = {1};
Physical Surface("block") = {1};
Physical Curve("base") = {1};
Point(5) = {0.5, 0.5, 0, lc}; Point(6) = {0.501, 0.5, 0, lc}; Point(7) = {0.501, 0.501, 0, lc};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 5};
Physical Curve("speck") = {5, 6, 7};
)";

// A valid scene; each scene row replaces one piece of it.
const char* const kScene = R"([scene]
geometry = "block.geo"

[mesh]
size = 0.25

[run]
end_time = 0.01
cfl = 0.5
output_interval = 0.005
damping = 0.0
evs = false
gravity = [0.0, -9.81]

[materials.rock]
model = "mohr_coulomb"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.25
friction_angle = 30.0
cohesion = 1000.0
dilation_angle = 0.0

[bodies.block]
material = "rock"
particles_per_cell = 4

[boundaries.base]
type = "fixed"

[contact]
friction = 0.3
)";

std::string write_file(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the base scene has no '" << from << "'";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string scene_row(const fs::path& dir, const std::string& scene, const std::string& extra) {
  write_file(dir / "block.geo", kGeo);
  return "mesh " + write_file(dir / "block.toml", scene) + " " + extra;
}

CommandResult talus_with_limit(const std::string& limit, const std::string& args) {
  return run_shell("ulimit " + limit + "; " + TALUS_BINARY + " " + args);
}

std::string scene_change(const fs::path& dir, const std::string& from, const std::string& to) {
  return scene_row(dir, replaced(kScene, from, to));
}

std::string geo_row(const fs::path& dir, const std::string& geo, const std::string& scene) {
  write_file(dir / "evil.geo", geo);
  return scene_row(dir, replaced(scene, "block.geo", "evil.geo"));
}

std::string meshed_model_row(const fs::path& dir, const std::function<void(const h5::File&)>& change,
                             const std::string& options) {
  const auto meshed = run_talus(scene_row(dir, kScene) + " --out " + (dir / "m").string());
  EXPECT_EQ(meshed.status, 0) << meshed.output;
  const std::string model = (dir / "m" / "model.h5").string();
  h5::File file = h5::File::open_write(model);
  change(file);
  file.close();
  return "solve " + model + " " + options;
}

std::string solved_results_row(const fs::path& dir, const std::function<void(const h5::File&)>& change) {
  const std::string model = meshed_model_row(dir, [](auto&) {}).substr(6);
  const auto solved = run_talus("solve " + model + " --quiet");
  EXPECT_EQ(solved.status, 0) << solved.output;
  const std::string results = (dir / "m" / "results.h5").string();
  h5::File file = h5::File::open_write(results);
  change(file);
  file.close();
  return "post " + results;
}

namespace {

std::vector<std::string> names_in(const fs::path& out) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(out)) names.push_back(entry.path().filename().string());
  return names;
}

// What the failed run left in `out`: a folder it made (it must remove it again), else the files
// it added or that look like output (the lock file of a folder that existed may stay).
std::vector<std::string> leftovers(const fs::path& out, bool existed, const std::vector<std::string>& before) {
  std::vector<std::string> found;
  if (!fs::exists(out)) return found;
  if (!existed) found.push_back(out.string() + " (the run made this folder)");
  for (const std::string& name : names_in(out)) {
    const bool added = std::find(before.begin(), before.end(), name) == before.end();
    if ((added && name != ".talus.lock") || name == "model.h5" || name == "results.h5" || name == "metrics.json" ||
        name == "checkpoint.h5" || fs::path(name).extension() == ".tmp")
      found.push_back(name);
  }
  return found;
}

}  // namespace

void expect_rows_fail_cleanly(const std::vector<Row>& rows) {
  for (const auto& row : rows) {
    SCOPED_TRACE(row.what);
    ScratchDir dir("bad-input");
    const fs::path out = dir.path() / "out";
    const std::string arguments = row.prepare(dir.path());
    const bool existed = fs::exists(out);
    const std::vector<std::string> before = existed ? names_in(out) : std::vector<std::string>{};
    const auto result = run_talus(arguments + " --out " + out.string());
    EXPECT_EQ(result.status, 1) << result.output;
    for (const auto& word : row.words)
      EXPECT_NE(result.output.find(word), std::string::npos) << "'" << word << "' not in: " << result.output;
    EXPECT_EQ(result.output.find("internal error"), std::string::npos) << result.output;
    const auto left = leftovers(out, existed, before);
    EXPECT_TRUE(left.empty()) << "left behind: " << (left.empty() ? "" : left.front());
  }
}

}  // namespace talus::testing
