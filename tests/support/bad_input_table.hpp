// The bad-input table's machinery, shared by the test files that hold rows: a small valid
// scene and .geo to change one piece of, and the check every row must pass (exit status 1,
// the row's key words in the message, no internal error, no output left behind).
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "common/h5.hpp"
#include "support/test_support.hpp"

namespace talus::testing {

// A valid .geo (block.geo: a 2 x 1 block, its base, a tiny triangle "speck") and a valid scene
// naming it.
extern const char* const kGeo;
extern const char* const kScene;

// One row: prepares its input files in `dir` and returns the talus arguments (the output
// folder is always dir/out).
struct Row {
  std::string what;
  std::function<std::string(const std::filesystem::path& dir)> prepare;
  std::vector<std::string> words;
};

std::string write_file(const std::filesystem::path& path, const std::string& text);
// `text` with the first `from` replaced by `to` (a test failure if there is none).
std::string replaced(std::string text, const std::string& from, const std::string& to);
// Writes block.geo and block.toml (`scene`) and returns "mesh block.toml EXTRA".
std::string scene_row(const std::filesystem::path& dir, const std::string& scene, const std::string& extra = "");
std::string scene_change(const std::filesystem::path& dir, const std::string& from, const std::string& to);
// `scene` (the base scene by default) with `geo` for its .geo, as evil.geo beside it.
std::string geo_row(const std::filesystem::path& dir, const std::string& geo, const std::string& scene = kScene);
// The base scene meshed by talus into DIR/m, its model.h5 changed by `change`: returns
// "solve DIR/m/model.h5 OPTIONS".
std::string meshed_model_row(const std::filesystem::path& dir, const std::function<void(const h5::File&)>& change,
                             const std::string& options = "");
// The base scene meshed and solved by talus into DIR/m, its results.h5 changed by `change`:
// returns "post DIR/m/results.h5".
std::string solved_results_row(const std::filesystem::path& dir, const std::function<void(const h5::File&)>& change);

// `talus ARGS` through sh under `ulimit LIMIT` ("-f 100": files of at most 100 blocks of 512
// bytes; "-v 150000": an address space of 150,000 kB).
CommandResult talus_with_limit(const std::string& limit, const std::string& args);

// Runs every row through the binary in a scratch folder of its own and checks it.
void expect_rows_fail_cleanly(const std::vector<Row>& rows);

}  // namespace talus::testing
