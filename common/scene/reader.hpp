// Reading a scene's TOML (common/scene/scene.hpp, docs/scenes.md), inside common/ only: the typed,
// checked reader of one table that every table's reader shares, the --set overrides, and one
// reader per top-level table. load_scene (common/scene/scene.cpp) parses the file, applies the
// overrides and calls the readers in the order of the format, so the first mistake in that
// order is the one reported.
#pragma once
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <toml++/toml.h>
#include <vector>

#include "common/scene/scene.hpp"

namespace talus::scene_reader {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// The candidate closest to `key` by edit distance, or "" when none is close.
std::string nearest(const std::string& key, const std::vector<std::string>& candidates);

// Reads one TOML table, remembering which keys were read, so that whatever is left over is
// reported as unknown with the nearest valid key. Every failure throws talus::Error located at
// the scene file and the dotted key ("materials.sand.cohesion").
class TableReader {
 public:
  // `table` may be null (an absent table: every key takes its fallback). `file` and
  // `overridden` (the keys set by --set) must outlive the reader.
  TableReader(const toml::table* table, std::string prefix, const std::string& file,
              const std::set<std::string>& overridden)
      : table_(table), prefix_(std::move(prefix)), file_(file), overridden_(overridden) {}

  // A reader of a table below this one, for the same file.
  TableReader child(const toml::table* table, std::string prefix) const {
    return TableReader(table, std::move(prefix), file_, overridden_);
  }

  bool has(const std::string& key);

  // A finite number in [min, max] (either end open on request); no fallback: required.
  double number(const std::string& key, std::optional<double> fallback, double min, double max,
                bool min_inclusive = true, bool max_inclusive = true);
  // A number of any value, infinite or NaN too, for a caller that checks it (materials).
  double any_number(const std::string& key, std::optional<double> fallback);
  long integer(const std::string& key, long fallback, long min, long max);
  std::string text(const std::string& key, std::optional<std::string> fallback);
  bool boolean(const std::string& key, bool fallback);
  Eigen::Vector2d vector2(const std::string& key, std::optional<Eigen::Vector2d> fallback);
  std::vector<std::string> strings(const std::string& key);
  // A sub-table, or null when absent.
  const toml::table* table(const std::string& key);
  // An array, or null when absent; `expected` is the message when the value is not an array.
  const toml::array* array(const std::string& key, const std::string& expected);

  // Every key of this table that was not read is a mistake.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& message) const;

  const std::string& prefix() const { return prefix_; }
  const std::string& file() const { return file_; }

 private:
  std::optional<double> given_number(const std::string& key);  // nullopt when absent

  const toml::table* table_;
  std::string prefix_;
  const std::string& file_;
  const std::set<std::string>& overridden_;
  std::vector<std::string> known_;
};

// Input quoted in a message: control characters as \xNN, cut after 80 characters with the
// length said (a 1 MB key is not echoed as a 1 MB message).
std::string echoed(const std::string& text);

// Applies one --set "dotted.key=value" to the parsed file and records the key in `overridden`.
void apply_override(toml::table& root, const std::string& assignment, const std::string& file,
                    std::set<std::string>& overridden);

// Body and material names become HDF5 group names: plain words, at most 64, not "names".
void check_name(const std::string& name, const std::string& item, const std::string& file);

// One reader per top-level table, each given the reader of the file's root (common/scene/*.cpp).
void read_scene_table(TableReader& top, Scene& scene);  // [scene]: name, geometry
void read_mesh(TableReader& top, Scene& scene);         // [mesh]
void read_run(TableReader& top, Scene& scene);          // [run]
void read_materials(TableReader& top, Scene& scene);    // [materials.NAME]
void read_bodies(TableReader& top, Scene& scene);       // [bodies.NAME], after the materials
void read_boundaries(TableReader& top, Scene& scene);   // [boundaries.NAME]
void read_loads(TableReader& top, Scene& scene);       // [loads.NAME]
void read_contact(TableReader& top, Scene& scene);      // [contact], [[contact.pairs]], after the bodies
void read_post(TableReader& top, Scene& scene);         // [post], after the bodies
void read_water(TableReader& top, Scene& scene);        // [water] (common/scene/water.cpp)
void read_random(TableReader& top, Scene& scene);       // [random.NAME], after the materials (common/scene/random.cpp)
void read_seismic(TableReader& top, Scene& scene);      // [seismic] (common/scene/seismic.cpp)
void read_base_motion(TableReader& top, Scene& scene);  // [base_motion], after the bodies and boundaries (seismic.cpp)
void read_absorbing(TableReader& r, const Scene& scene, Boundary& boundary);  // an absorbing boundary's keys (seismic.cpp)

}  // namespace talus::scene_reader
