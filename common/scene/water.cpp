// The reader of the scene's [water] table (common/scene/scene.hpp, WaterSettings; docs/scenes.md).
#include <cmath>

#include "common/scene/reader.hpp"

namespace talus::scene_reader {
namespace {

// A list of [a, b] pairs of finite numbers; `what` names one pair in the messages.
std::vector<Eigen::Vector2d> pairs(TableReader& r, const std::string& key, const std::string& what) {
  std::vector<Eigen::Vector2d> points;
  const toml::array* list = r.array(key, "expected a list of " + what + " pairs");
  if (!list) return points;
  for (std::size_t k = 0; k < list->size(); ++k) {
    const toml::array* pair = (*list)[k].as_array();
    const std::string item = "point " + std::to_string(k + 1);
    if (!pair || pair->size() != 2) r.fail(key, item + ": expected two numbers " + what);
    Eigen::Vector2d point;
    for (int i = 0; i < 2; ++i) {
      const auto x = (*pair)[i].value<double>();
      if (!x) r.fail(key, item + ": expected two numbers " + what);
      if (!std::isfinite(*x)) r.fail(key, item + " is not finite");
      point[i] = *x;
    }
    points.push_back(point);
  }
  return points;
}

}  // namespace

void read_water(TableReader& top, Scene& scene) {
  const toml::table* table = top.table("water");
  if (!table) return;
  TableReader r = top.child(table, "water");
  WaterSettings& water = scene.water;
  if (!r.has("table")) r.fail("table", "missing (expected a list of [x, y] points, x increasing)");
  water.table = pairs(r, "table", "[x, y]");
  if (water.table.size() < 2) r.fail("table", "expected at least two [x, y] points");
  for (std::size_t k = 1; k < water.table.size(); ++k)
    if (!(water.table[k].x() > water.table[k - 1].x()))
      r.fail("table", "point " + std::to_string(k + 1) + " (x = " + std::to_string(water.table[k].x()) +
                          ") is not right of point " + std::to_string(k) + ": x must increase strictly");
  water.unit_weight = r.number("unit_weight", water.unit_weight, 0, kInf, false);
  water.bulk_modulus = r.number("bulk_modulus", water.bulk_modulus, 0, kInf, false);
  const std::string mode = r.text("mode", "drained");
  if (mode == "drained") water.mode = WaterMode::Drained;
  else if (mode == "undrained") water.mode = WaterMode::Undrained;
  else r.fail("mode", "unknown mode '" + echoed(mode) + "' (expected drained or undrained)");
  water.rise = pairs(r, "rise", "[time, height]");
  for (std::size_t k = 1; k < water.rise.size(); ++k)
    if (!(water.rise[k].x() > water.rise[k - 1].x()))
      r.fail("rise", "point " + std::to_string(k + 1) + " (t = " + std::to_string(water.rise[k].x()) +
                         ") is not after point " + std::to_string(k) + ": time must increase strictly");
  r.finish();
}

}  // namespace talus::scene_reader
