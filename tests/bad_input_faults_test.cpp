// The bad inputs of issue 43 through the binary, checked like the other bad-input tables
// (support/bad_input_table.hpp): exit status 1, a message naming the file and the item, no
// internal error, nothing left behind. Each row failed otherwise on the landed build (2d3cee5):
// a crash, a message that named something else, or no message at all.
#include <gtest/gtest.h>

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
  write_file(dir / "evil.geo", geo);
  return testing::scene_row(dir, replaced(replaced(testing::kScene, "block.geo", "evil.geo"), "[mesh]\nsize = 0.25\n", ""));
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
  };
}

TEST(BadInputFaults, EveryRowStopsWithOneClearMessageAndLeavesNothing) { testing::expect_rows_fail_cleanly(rows()); }

}  // namespace
}  // namespace talus
