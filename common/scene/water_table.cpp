// The water table of a scene (common/scene/scene.hpp, WaterSettings): its height, rise and checks.
#include <algorithm>
#include <cmath>
#include <string>

#include "common/geometry.hpp"
#include "common/scene/scene.hpp"

namespace talus {
namespace {

// Linear interpolation in a polyline of (x, y) points with x increasing, held level beyond its
// ends; 0 for no points.
double interpolate(const std::vector<Eigen::Vector2d>& points, double x) {
  return points.empty() ? 0 : polyline_height(points, x);
}

std::string increasing_problem(const std::vector<Eigen::Vector2d>& points, const char* what, const char* axis) {
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!std::isfinite(points[k].x()) || !std::isfinite(points[k].y()))
      return std::string(what) + " point " + std::to_string(k + 1) + " is not finite";
    if (k > 0 && !(points[k].x() > points[k - 1].x()))
      return std::string(what) + " point " + std::to_string(k + 1) + " does not follow point " + std::to_string(k) +
             ": " + axis + " must increase strictly";
  }
  return "";
}

}  // namespace

const char* water_mode_name(WaterMode mode) { return mode == WaterMode::Undrained ? "undrained" : "drained"; }

double WaterSettings::rise_at(double t) const { return interpolate(rise, t); }

double WaterSettings::height(double x, double t) const {
  return interpolate(table, x) + (rise.empty() ? 0.0 : rise_at(t));
}

std::string water_problem(const WaterSettings& water) {
  if (water.table.size() < 2) return "the table needs at least two [x, y] points";
  if (std::string problem = increasing_problem(water.table, "table", "x"); !problem.empty()) return problem;
  if (std::string problem = increasing_problem(water.rise, "rise", "time"); !problem.empty()) return problem;
  if (!(water.unit_weight > 0) || !std::isfinite(water.unit_weight)) return "unit_weight must be a finite number > 0";
  if (!(water.bulk_modulus > 0) || !std::isfinite(water.bulk_modulus)) return "bulk_modulus must be a finite number > 0";
  return "";
}

}  // namespace talus
