// The bad inputs of issue 43 through the binary, checked like the other bad-input tables
// (support/bad_input_table.hpp): exit status 1, a message naming the file and the item, no
// internal error, nothing left behind. Each row failed otherwise on the landed build (2d3cee5):
// a crash, a message that named something else, or no message at all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::kGeo;
using testing::replaced;
using testing::Row;
using testing::write_file;

// The block scene without [mesh] size (the .geo's own sizes rule), meshing `geo` as evil.geo.
std::string unsized_geo_row(const fs::path& dir, const std::string& geo) {
  return testing::geo_row(dir, geo, replaced(testing::kScene, "[mesh]\nsize = 0.25\n", ""));
}

// The block's .geo with its body drawn as a closed physical curve `outline` (points 11 to 14,
// lines 11 to 14 joining them in order), beside a domain with `hole` (x0, y0, x1, y1) cut out
// when given.
std::string outline_row(const fs::path& dir, const std::string& outline, const std::string& hole = "") {
  std::string geo = "lc = 0.25;\n"
                    "Point(1) = {0, 0, 0, lc}; Point(2) = {2, 0, 0, lc}; Point(3) = {2, 1, 0, lc}; Point(4) = {0, 1, 0, lc};\n"
                    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4};\n";
  if (hole.empty()) {
    geo += "Plane Surface(1) = {1};\n";
  } else {
    geo += hole + "Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};\n"
                  "Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(1) = {1, 2};\n";
  }
  geo += "Physical Surface(\"domain\") = {1};\nPhysical Curve(\"base\") = {1};\n" + outline +
         "Line(11) = {11, 12}; Line(12) = {12, 13}; Line(13) = {13, 14}; Line(14) = {14, 11};\n"
         "Physical Curve(\"outline\") = {11, 12, 13, 14};\n";
  return testing::geo_row(dir, geo, replaced(testing::kScene, "[bodies.block]\n", "[bodies.block]\ngroup = \"outline\"\n"));
}

// The first value of dataset `path` in the file set to `value` (the rest as they were).
void set_first(const h5::File& file, const std::string& path, double value) {
  h5::Dims dims;
  std::vector<double> values = h5::read_doubles(file, path, &dims);
  values.at(0) = value;
  h5::write(file, path, values, dims);
}

std::vector<Row> rows() {
  return {
      // gmsh throws its errors as std::string from OpenMP regions, where nothing can catch
      // them: std::terminate, SIGABRT, status 134.
      {"Mesh.MeshSizeMax = 0 without [mesh] size",
       [](auto d) { return unsized_geo_row(d, std::string(kGeo) + "Mesh.MeshSizeMax = 0;\n"); },
       {"evil.geo: Mesh.MeshSizeMax: got 0 (also set as Mesh.CharacteristicLengthMax)",
        "the largest element size must be positive", "set [mesh] size"}},
      {"Mesh.CharacteristicLengthMax < 0 without [mesh] size",
       [](auto d) { return unsized_geo_row(d, std::string(kGeo) + "Mesh.CharacteristicLengthMax = -1;\n"); },
       {"evil.geo: Mesh.MeshSizeMax: got -1"}},
      {"a negative point size without [mesh] size",
       [](auto d) { return unsized_geo_row(d, replaced(kGeo, "lc = 0.25;", "lc = -1;")); },
       {"evil.geo: gmsh could not mesh the geometry: Error: Wrong mesh element size lc = 0", "more errors)"}},
      {"a background field of size 0",
       [](auto d) {
         return unsized_geo_row(d, std::string(kGeo) + "Field[1] = MathEval;\nField[1].F = \"0\";\nBackground Field = 1;\n");
       },
       {"evil.geo: gmsh could not mesh the geometry: Error: Wrong mesh element size"}},
      // Outlines that bound no region, or reach where there is no mesh, were seeded as if whole.
      {"a bow-tie body outline",
       [](auto d) {
         return outline_row(d, "Point(11) = {0.5, 0.2, 0, lc}; Point(12) = {1.5, 0.8, 0, lc}; "
                               "Point(13) = {1.5, 0.2, 0, lc}; Point(14) = {0.5, 0.8, 0, lc};\n");
       },
       {"block.toml: bodies.block: the outline of the body crosses itself at (1, 0.5)", "bow-tie"}},
      {"a body outline across a hole of the domain",
       [](auto d) {
         return outline_row(d,
                            "Point(11) = {0.3, 0.3, 0, lc}; Point(12) = {0.95, 0.3, 0, lc}; "
                            "Point(13) = {0.95, 0.7, 0, lc}; Point(14) = {0.3, 0.7, 0, lc};\n",
                            "Point(5) = {0.8, 0.55, 0, lc}; Point(6) = {1.2, 0.55, 0, lc}; "
                            "Point(7) = {1.2, 0.65, 0, lc}; Point(8) = {0.8, 0.65, 0, lc};\n");
       },
       {"block.toml: bodies.block: the outline of the body crosses the edge of the domain (physical surface "
        "\"domain\" of ",
        "into a hole of the domain or out of it"}},
      // --set takes one TOML value: before, a line break ended it silently and a malformed value
      // became a string.
      {"--set with a table after the value",
       [](auto d) { return testing::scene_row(d, testing::kScene, "--set \"$(printf 'run.end_time=0.2\\n[run]\\ncfl=0.9')\""); },
       {"block.toml: --set run.end_time=0.2\\x0a[run]\\x0acfl=0.9: expected one value on one line"}},
      {"--set with more after the value",
       [](auto d) { return testing::scene_row(d, testing::kScene, "--set 'run.end_time=0.2 # cfl=0.9'"); },
       {"--set run.end_time=0.2 # cfl=0.9: expected one value, got more after it"}},
      {"--set of a malformed number",
       [](auto d) { return testing::scene_row(d, testing::kScene, "--set run.end_time=1.0.0"); },
       {"--set run.end_time=1.0.0: the value is not valid TOML", "needs quotes"}},
      // A newline in a --set string was printed raw where the file or the item came from input.
      {"a newline in the geometry's name",
       [](auto d) { return testing::scene_row(d, testing::kScene, "--set 'scene.geometry=\"a\\nb.geo\"'"); },
       {"a\\x0ab.geo: no such geometry file"}},
      {"a newline in a body's group",
       [](auto d) { return testing::scene_row(d, testing::kScene, "--set 'bodies.block.group=\"a\\nb\"'"); },
       {"block.geo: physical surface or closed curve \"a\\x0ab\": named by bodies.block"}},
      // The scene path: a folder gave "run.end_time: missing".
      {"a folder for the scene",
       [](auto d) {
         fs::create_directories(d / "scene.toml");
         return "mesh " + (d / "scene.toml").string();
       },
       {"scene.toml: is a folder, not a scene file"}},
      // Absurd initial states failed at step 0 or 1 ("non-finite time step", "try a smaller
      // run.cfl") without naming the input.
      {"an initial velocity of 1e308",
       [](auto d) { return testing::scene_row(d, testing::kScene, "--set 'bodies.block.initial_velocity=[1e308, 0.0]'"); },
       {"block.toml: bodies.block.initial_velocity: a speed of 1e+308 m/s"}},
      {"an initial velocity of 1e308 with run.max_steps",
       [](auto d) {
         return testing::scene_row(d, testing::kScene,
                                   "--set 'bodies.block.initial_velocity=[1e308, 0.0]' --set run.max_steps=10");
       },
       {"block.toml: bodies.block.initial_velocity: particle 0 moves at 1e+308 m/s: its CFL time step",
        "too small for the time to pass run.end_time = 0.01 s"}},
      {"an initial stress of 1e308 (its surface)",
       [](auto d) {
         return testing::scene_row(d, testing::kScene, "--set 'bodies.block.initial_stress={k0 = 0.5, surface = 1e308}'");
       },
       {"block.toml: bodies.block.initial_stress: particle 0 starts with a stress of", "elastic strain"}},
      {"a velocity of 1e308 in a model",
       [](auto d) { return testing::meshed_model_row(d, [](auto& f) { set_first(f, "particles/velocity", 1e308); }); },
       {"model.h5: particles/velocity: particle 0 moves at 1e+308 m/s"}},
      {"a stress of 1e308 in a model",
       [](auto d) { return testing::meshed_model_row(d, [](auto& f) { set_first(f, "particles/stress", -1e308); }); },
       {"model.h5: particles/stress: particle 0 starts with a stress of 1e+308 Pa, 1e+301 times the Young's modulus"}},
      // Results that talus post took as they came: the figures script then crashed on them.
      {"NaN in the energy history",
       [](auto d) {
         return testing::solved_results_row(d, [](auto& f) { set_first(f, "history/kinetic_energy", NAN); });
       },
       {"results.h5: history/kinetic_energy: non-finite value at row 0"}},
      {"a frame position of 1e308",
       [](auto d) { return testing::solved_results_row(d, [](auto& f) { set_first(f, "frames/position", 1e308); }); },
       {"results.h5: frames/position: particle 0 of frame 0 is at (1e+308, ", "times that extent"}},
      // fos ran every trial of 100 rounds (21 s) before "no bracket within 100 rounds".
      {"fos --tolerance 1e-300",
       [](auto d) { return "fos " + testing::scene_row(d, testing::kScene).substr(5) + " --tolerance 1e-300"; },
       {"--tolerance: got 1e-300, below 1.78e-13, the narrowest bracket the search can resolve"}},
      // converge ran every level before it looked at post.metrics.
      {"converge of a scene without runout or failure surface",
       [](auto d) { return "converge " + testing::scene_row(d, testing::kScene).substr(5); },
       {"block.toml: post.metrics: converge follows runout", "add \"runout\" or \"failure_surface\""}},
  };
}

TEST(BadInputFaults, EveryRowStopsWithOneClearMessageAndLeavesNothing) { testing::expect_rows_fail_cleanly(rows()); }

// A FIFO for the scene blocked talus (toml++ opened it to read); now it is refused without
// being opened. `timeout` keeps a regression from hanging the suite.
TEST(BadInputFaults, AFifoForTheSceneIsRefusedWithoutBlocking) {
  const testing::ScratchDir dir("fifo-scene");
  const std::string fifo = dir.file("scene.toml");
  ASSERT_EQ(testing::run_shell("mkfifo " + fifo).status, 0);
  const auto result = testing::run_shell("timeout 20 " + std::string(TALUS_BINARY) + " mesh " + fifo + " --out " +
                                         dir.file("out"));
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find(fifo + ": is not a regular file (a FIFO, a device or a socket): expected a scene file"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir.file("out")));
}

// Input echoed in a message is one line: a newline in a --set string is shown as \x0a wherever
// it lands (in a file name or an item, before only the values of the scene's own checks).
TEST(BadInputFaults, ANewlineInASetStringIsEscapedInEveryMessage) {
  const testing::ScratchDir dir("newline");
  for (const char* set : {"scene.geometry=\"a\\nb.geo\"", "bodies.block.group=\"a\\nb\"", "mesh.domain=\"a\\nb\"",
                          "scene.name=\"a\\nb\"", "materials.rock.model=\"a\\nb\""}) {
    SCOPED_TRACE(set);
    const auto result =
        testing::run_talus(testing::scene_row(dir.path(), testing::kScene) + " --set '" + set + "' --out " + dir.file("out"));
    EXPECT_EQ(result.status, 1) << result.output;
    EXPECT_NE(result.output.find("a\\x0ab"), std::string::npos) << result.output;
    EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  }
}

// results.h5 without its `complete` attribute (a run cut short before it was written, or a
// damaged file) was reported as run_complete: true.
TEST(BadInputFaults, ResultsWithoutTheirCompleteAttributeAreNotComplete) {
  const testing::ScratchDir dir("no-complete");
  const std::string post = testing::solved_results_row(dir.path(), [](const h5::File& f) { H5Adelete(f.id(), "complete"); });
  const auto result = testing::run_talus(post + " -q --out " + dir.file("out"));
  ASSERT_EQ(result.status, 0) << result.output;
  const std::string metrics = testing::read_text(dir.file("out/metrics.json"));
  EXPECT_NE(metrics.find("\"run_complete\": false"), std::string::npos) << metrics;
}

}  // namespace
}  // namespace talus
