// Hostile input through the talus binary: inputs written to make talus do harm (run commands,
// write files outside its folders) or never finish. One table, checked like the bad-input
// table: exit status 1, a message naming the file and the item, nothing left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "common/h5.hpp"
#include "solver/solve_observers.hpp"
#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::kGeo;
using testing::replaced;
using testing::Row;
using testing::scene_change;
using testing::ScratchDir;
using testing::write_file;
using testing::geo_row;
using testing::meshed_model_row;
using testing::solved_results_row;


std::vector<Row> rows() {
  return {
      // .geo files are programs: gmsh runs them as it parses them.
      {"System in a .geo", [](auto d) { return geo_row(d, std::string(kGeo) + "System \"touch ran\";\n"); },
       {"evil.geo:11:", "statement 'System' is not allowed in a Talus .geo", "shell command", "docs/scenes.md"}},
      {"SystemCall in a .geo", [](auto d) { return geo_row(d, "lc = 1;\nSystemCall 'touch ran';\n"); },
       {"evil.geo:2:", "'SystemCall'"}},
      {"Printf to a file",
       [](auto d) { return geo_row(d, "lc = 1;\n/* a comment */ Printf(\"lc = %g\", lc) >> \"/tmp/leak\";\n"); },
       {"evil.geo:2:", "'Printf(...) >>'", "writes a file"}},
      {"Save in a .geo", [](auto d) { return geo_row(d, std::string(kGeo) + "Mesh 2;\nSave \"copy.msh\";\n"); },
       {"evil.geo:12:", "'Save'", "writes a file"}},
      {"Exit in a .geo", [](auto d) { return geo_row(d, "Exit;\n"); }, {"evil.geo:1:", "'Exit'", "ends the process"}},
      {"General option in a .geo", [](auto d) { return geo_row(d, "General.SaveOptions = 1;\n"); },
       {"evil.geo:1:", "'General.SaveOptions'", "only Mesh.* and Geometry.* options"}},
      {"Merge of another file", [](auto d) { return geo_row(d, "Merge \"/etc/passwd\";\n"); },
       {"evil.geo:1:", "'Merge'", "reads another file"}},
      {"refused statement in an included file",
       [](auto d) {
         write_file(d / "parts" / "inner.geo", "// nothing yet\n\nSleep 1e9;\n");
         return geo_row(d, "Include \"parts/inner.geo\";\n");
       },
       {"inner.geo:3:", "'Sleep'"}},
      {"Include reaching outside the folder",
       [](auto d) {
         write_file(d / "block.geo", kGeo);
         write_file(d / "scene" / "evil.geo", "Include \"../block.geo\";\n");
         return "mesh " + write_file(d / "scene.toml", replaced(testing::kScene, "block.geo", "scene/evil.geo"));
       },
       {"evil.geo:1:", "Include \"../block.geo\"", "outside the .geo's folder"}},
      {"Include loop",
       [](auto d) {
         write_file(d / "again.geo", "Include \"evil.geo\";\n");
         return geo_row(d, "lc = 1;\nInclude \"again.geo\";\n");
       },
       {"Include loop", "evil.geo -> ", "again.geo -> "}},
      {"Include of a computed name", [](auto d) { return geo_row(d, "Include StrCat(\"ev\", \"il.geo\");\n"); },
       {"evil.geo:1:", "'Include'", "one plain string"}},
      {"Include of a missing file", [](auto d) { return geo_row(d, "\n\nInclude \"nowhere.geo\";\n"); },
       {"evil.geo:3:", "nowhere.geo", "no such file"}},
      {"System in the .geo.opt gmsh reads after the .geo",
       [](auto d) {
         write_file(d / "evil.geo.opt", "System \"touch ran\";\n");
         return geo_row(d, kGeo);
       },
       {"evil.geo.opt:1:", "'System'"}},
      // scene.name names the output folder out/NAME/: it must not lead anywhere else.
      {"scene name '..'", [](auto d) { return scene_change(d, "[scene]\n", "[scene]\nname = \"..\"\n"); },
       {"block.toml", "scene.name", "not '.' or '..'", "got '..'"}},
      {"scene name '.'", [](auto d) { return scene_change(d, "[scene]\n", "[scene]\nname = \".\"\n"); },
       {"block.toml", "scene.name", "got '.'"}},
      {"scene name with a NUL byte",
       [](auto d) { return scene_change(d, "[scene]\n", "[scene]\nname = \"ok\\u0000/../../x\"\n"); },
       {"block.toml", "scene.name", "control characters", "got 'ok\\x00/../../x'"}},
      {"scene name with a newline",
       [](auto d) { return scene_change(d, "[scene]\n", "[scene]\nname = \"a\\nb\"\n"); },
       {"block.toml", "scene.name", "got 'a\\x0ab'"}},
      {"scene name of 10000 characters",
       [](auto d) { return scene_change(d, "[scene]\n", "[scene]\nname = \"" + std::string(10000, 'n') + "\"\n"); },
       {"block.toml", "scene.name", "1 to 128 characters", "(10000 characters)"}},
      {"scene name '..' by --set", [](auto d) { return testing::scene_row(d, testing::kScene, "--set scene.name=.."); },
       {"scene.name"}},
      // A .geo that makes no mesh, or no body (Exit itself is refused above).
      {"a .geo that makes nothing", [](auto d) { return geo_row(d, "lc = 1;\n"); },
       {"evil.geo", "physical surface \"domain\"", "its named physical groups are: (none)"}},
      {"a .geo whose body group is empty",
       [](auto d) { return geo_row(d, testing::replaced(kGeo, "Physical Surface(\"block\") = {1};", "")); },
       {"evil.geo", "\"block\"", "named by bodies.block", "is not a physical group"}},
      // A geometry that is not a regular file would be read without end.
      {"geometry /dev/zero", [](auto d) { return scene_change(d, "\"block.geo\"", "\"/dev/zero\""); },
       {"block.toml", "scene.geometry", "'/dev/zero' is not a regular file"}},
      {"geometry /dev/zero through talus run",
       [](auto d) { return "run" + scene_change(d, "\"block.geo\"", "\"/dev/zero\"").substr(4); },
       {"block.toml", "scene.geometry", "not a regular file"}},
      {"geometry a folder",
       [](auto d) {
         fs::create_directories(d / "folder.geo");
         return scene_change(d, "\"block.geo\"", "\"folder.geo\"");
       },
       {"block.toml", "scene.geometry", "'folder.geo' is not a regular file"}},
      // Intervals so small that the run would write frames or checkpoints without end.
      {"output interval far below the end time",
       [](auto d) { return scene_change(d, "output_interval = 0.005", "output_interval = 1e-12"); },
       {"block.toml", "run.output_interval", "got 1e-12 s", "frames over run.end_time = 0.01 s", "at most 100000"}},
      {"output interval far below the end time in a model",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) { h5::set_attribute(f, "settings/run", "output_interval", 1e-300); });
       },
       {"model.h5", "settings/run@output_interval", "frames over run.end_time"}},
      {"checkpoint interval far below the end time",
       [](auto d) { return meshed_model_row(d, [](auto&) {}, "--checkpoint-interval 1e-300"); },
       {"--checkpoint-interval", "got 1e-300 s", "checkpoints over run.end_time = 0.01 s", "at most 100000"}},
      // Model and results data that read well one dataset at a time (issue 17, item 10).
      {"roller normal [0, 0] in a model",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) {
           h5::write(f, "boundary_conditions/roller_nodes", std::vector<int32_t>{0}, {1});
           h5::write(f, "boundary_conditions/roller_normals", std::vector<double>{0.0, 0.0}, {1, 2});
         });
       },
       {"model.h5", "boundary_conditions/roller_normals", "row 0 is [0, 0]"}},
      {"friction normal [0, 0] in a model",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) {
           h5::write(f, "boundary_conditions/friction_nodes", std::vector<int32_t>{0}, {1});
           h5::write(f, "boundary_conditions/friction_normals", std::vector<double>{0.0, 0.0}, {1, 2});
           h5::write(f, "boundary_conditions/friction_coefficients", std::vector<double>{0.5}, {1});
         });
       },
       {"model.h5", "boundary_conditions/friction_normals", "row 0 is [0, 0]"}},
      {"negative friction coefficient in a model",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) {
           h5::write(f, "boundary_conditions/friction_nodes", std::vector<int32_t>{0}, {1});
           h5::write(f, "boundary_conditions/friction_normals", std::vector<double>{0.0, -1.0}, {1, 2});
           h5::write(f, "boundary_conditions/friction_coefficients", std::vector<double>{-0.5}, {1});
         });
       },
       {"model.h5", "boundary_conditions/friction_coefficients", "finite numbers >= 0"}},
      {"triangle indices as floating-point numbers",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) {
           h5::Dims dims;
           const std::vector<int32_t> t = h5::read_ints(f, "mesh/triangles", &dims);
           h5::write(f, "mesh/triangles", std::vector<double>(t.begin(), t.end()), dims);
         });
       },
       {"model.h5", "mesh/triangles", "expected integers, got floating-point numbers"}},
      {"particle outside its element",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) {
           std::vector<int32_t> element = h5::read_ints(f, "particles/element");
           const auto triangles = static_cast<int32_t>(h5::shape(f, "mesh/triangles")[0]);
           element[0] = (element[0] + triangles / 2) % triangles;
           h5::write(f, "particles/element", element, {element.size()});
         });
       },
       {"model.h5", "particles/element", "particle 0 at (", "is not inside its element"}},
      {"particles attribute disagreeing with the data",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) { h5::set_attribute(f, "/", "particles", int64_t{7}); });
       },
       {"model.h5", "@particles", "says 7 particles", "rows"}},
      {"frame time NaN in results",
       [](auto d) {
         return solved_results_row(d, [](auto& f) {
           std::vector<double> time = h5::read_doubles(f, "frames/time");
           time[1] = std::nan("");
           h5::write(f, "frames/time", time, {time.size()});
         });
       },
       {"results.h5", "frames/time", "frame 1 has a time that is not finite"}},
      {"frame times going back in results",
       [](auto d) {
         return solved_results_row(d, [](auto& f) {
           std::vector<double> time = h5::read_doubles(f, "frames/time");
           time.back() = 0.5 * time[1];
           h5::write(f, "frames/time", time, {time.size()});
         });
       },
       {"results.h5", "frames/time", "is earlier than frame", "must not go back"}},
      {"particles attribute disagreeing with the results",
       [](auto d) {
         return solved_results_row(d, [](auto& f) { h5::set_attribute(f, "/", "particles", int64_t{7}); });
       },
       {"results.h5", "@particles", "says 7 particles"}},
      // Values that passed the scene check and failed later (issue 17, item 11).
      {"gravity 1e308", [](auto d) { return scene_change(d, "gravity = [0.0, -9.81]", "gravity = [0.0, -1e308]"); },
       {"block.toml", "run.gravity", "a magnitude of 1e+308 m/s^2, expected at most 1000"}},
      {"gravity 1e308 in a model",
       [](auto d) {
         return meshed_model_row(
             d, [](auto& f) { h5::set_attribute(f, "settings/run", "gravity", std::vector<double>{0.0, -1e308}); });
       },
       {"model.h5", "settings/run@gravity", "at most 1000 m/s^2"}},
      {"k0 1e308",
       [](auto d) {
         return scene_change(d, "particles_per_cell = 4\n", "particles_per_cell = 4\ninitial_stress = { k0 = 1e308 }\n");
       },
       {"block.toml", "bodies.block.initial_stress.k0", "got 1e+308", "[0, 10]"}},
      {"Young's modulus 1e308: a time step of 1e-153 s",
       [](auto d) { return scene_change(d, "youngs_modulus = 1.0e7", "youngs_modulus = 1.0e308"); },
       {"block.toml", "materials.rock.youngs_modulus", "steps over run.end_time", "set run.max_steps to run anyway"}},
      // Messages name the file and do not echo input without end (issue 17, item 12).
      {"clockwise element in a model",
       [](auto d) {
         return meshed_model_row(d, [](auto& f) {
           h5::Dims dims;
           std::vector<int32_t> t = h5::read_ints(f, "mesh/triangles", &dims);
           std::swap(t[1], t[2]);
           h5::write(f, "mesh/triangles", t, dims);
         });
       },
       {"/m/model.h5: mesh/triangles: element 0 is degenerate or clockwise"}},
      {"unknown key of a megabyte",
       [](auto d) { return scene_change(d, "[mesh]\n", "[mesh]\n" + std::string(1 << 20, 'k') + " = 1\n"); },
       {"block.toml", "mesh.kkkk", "... (1048581 characters): unknown key"}},
      {"--set of 100000 characters",
       [](auto d) { return testing::scene_row(d, testing::kScene, "--set run." + std::string(100000, 'k') + "=1"); },
       {"--set run.kkkk", "... (100004 characters): no such scene key"}},
      // Command lines.
      {"far more threads than the machine has",
       [](auto d) { return meshed_model_row(d, [](auto&) {}, "--threads 1000000"); },
       {"--threads", "got '1000000'", "at most", "hardware threads"}},
      {"threads with trailing text", [](auto d) { return meshed_model_row(d, [](auto&) {}, "--threads 4x"); },
       {"--threads", "expected a positive integer", "'4x'"}},
  };
}

TEST(BadInputHostile, EveryRowStopsWithOneClearMessageAndLeavesNothing) { testing::expect_rows_fail_cleanly(rows()); }

TEST(BadInputHostile, ARefusedGeoRunsNothing) {
  ScratchDir dir("hostile-geo");
  const std::string marker = dir.file("ran");
  const auto result = testing::run_talus(
      geo_row(dir.path(), std::string(kGeo) + "SystemCall \"touch " + marker + "\";\n") + " --out " + dir.file("out"));
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_FALSE(fs::exists(marker)) << "the .geo's command ran";
}

TEST(BadInputHostile, CommentsStringsAndIncludesInsideTheFolderAreAllowed) {
  ScratchDir dir("hostile-geo-allowed");
  const fs::path d = dir.path();
  write_file(d / "parts" / "block_body.geo", kGeo);
  const std::string geo =
      "// System \"touch ran\"; is only a comment\n/* Save \"x\"; Exit; */\n"
      "Mesh.Algorithm = 6;\nGeometry.Tolerance = 1e-8;\nPrintf(\"Print Merge Exit: %g\", 1);\nInclude \"parts/block_body.geo\";\n";
  const auto result = testing::run_talus(geo_row(d, geo) + " --out " + dir.file("out"));
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir.file("out/model.h5")));
}

// A mesh that fails leaves the folder's earlier files, but says so and forgets the folder's
// stamps: nothing there passes for this run's output.
TEST(BadInputHostile, AFailedMeshSaysTheFolderHoldsAnEarlierRun) {
  ScratchDir dir("hostile-failed-mesh");
  const fs::path d = dir.path();
  const std::string out = " --quiet --out " + dir.file("out");
  const std::string good = testing::scene_row(d, testing::kScene).substr(5);  // "mesh " dropped
  write_file(d / "evil.geo", "lc = 1;\n");
  const std::string empty = write_file(d / "evil.toml", replaced(testing::kScene, "block.geo", "evil.geo"));
  for (const std::string command : {"mesh ", "run "}) {
    SCOPED_TRACE(command);
    const auto earlier = testing::run_talus(command + good + out);
    ASSERT_EQ(earlier.status, 0) << earlier.output;
    const auto failed = testing::run_talus(command + empty + out);
    EXPECT_EQ(failed.status, 1) << failed.output;
    EXPECT_NE(failed.output.find("(nothing was written: model.h5"), std::string::npos) << failed.output;
    EXPECT_NE(failed.output.find("are from an earlier run, not from this one"), std::string::npos) << failed.output;
    EXPECT_FALSE(fs::exists(dir.file("out/.talus-stamps"))) << "the earlier run's stamps were kept";
  }
}

TEST(BadInputHostile, TheNextOutputTimeIsComputedNotSummed) {
  EXPECT_DOUBLE_EQ(solver::next_multiple_after(0.3, 0.1, 1e-12), 0.4);
  EXPECT_DOUBLE_EQ(solver::next_multiple_after(0.35, 0.1, 0), 0.4);
  EXPECT_DOUBLE_EQ(solver::next_multiple_after(0, 0.25, 0), 0.25);
  // Summed from 0, this would take 1e17 additions, and 1 + 1e-17 == 1 would never get beyond.
  EXPECT_GT(solver::next_multiple_after(1.0, 1e-17, 0), 1.0);
  EXPECT_GT(solver::next_multiple_after(1e6, 1e-300, 0), 1e6);
}

}  // namespace
}  // namespace talus
