#include <algorithm>
#include <cmath>
#include <limits>

#include "postproc/slice_model.hpp"

namespace talus::postproc {
namespace {

// The intervals [lo, hi] of the vertical line at x inside the loops (odd-even rule), y increasing.
// An edge counts for lo.x <= x < hi.x, so a vertex is crossed once and a vertical edge never.
void intervals_at(const std::vector<std::vector<Eigen::Vector2d>>& loops, double x,
                  std::vector<double>& crossings, std::vector<std::pair<double, double>>& out) {
  crossings.clear();
  out.clear();
  for (const auto& loop : loops)
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const Eigen::Vector2d& a = loop[i];
      const Eigen::Vector2d& b = loop[(i + 1) % loop.size()];
      if ((a.x() <= x && x < b.x()) || (b.x() <= x && x < a.x()))
        crossings.push_back(a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x()));
    }
  std::sort(crossings.begin(), crossings.end());
  for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) out.emplace_back(crossings[k], crossings[k + 1]);
}

}  // namespace

LayeredGround::LayeredGround(std::vector<GroundLayer> layers, std::vector<SurfaceForce> loads, double load_width,
                             double water_unit_weight, std::function<double(double)> table)
    : layers_(std::move(layers)), loads_(std::move(loads)), load_width_(load_width), water_(water_unit_weight),
      table_(std::move(table)) {
  for (const auto& layer : layers_) tan_phi_.push_back(std::tan(layer.soil.friction_angle * M_PI / 180.0));
  std::sort(loads_.begin(), loads_.end(), [](const SurfaceForce& a, const SurfaceForce& b) { return a.x < b.x; });
}

SliceForces LayeredGround::forces(const Slice& s) const {
  const double h = table_ ? table_(s.x) : -std::numeric_limits<double>::infinity();
  thread_local std::vector<double> crossings;
  thread_local std::vector<std::pair<double, double>> inside;
  double column = 0;  // the column's weight per unit width
  int base = -1;      // the layer whose strength holds at the base
  double base_distance = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < layers_.size(); ++k) {
    const GroundLayer& layer = layers_[k];
    const double wet = table_ ? (layer.saturated_unit_weight > 0 ? layer.saturated_unit_weight : layer.soil.unit_weight)
                              : layer.soil.unit_weight;
    intervals_at(layer.loops, s.x, crossings, inside);
    for (const auto& [lo, hi] : inside) {
      const double a = std::max(lo, s.bottom), b = std::min(hi, s.top);
      if (b > a) {
        const double split = std::clamp(h, a, b);  // below it saturated
        column += wet * (split - a) + layer.soil.unit_weight * (b - split);
      }
      // The base: in [lo, hi) (the upper body where two meet), else the nearest along the vertical.
      const double distance = s.bottom < lo ? lo - s.bottom : s.bottom >= hi ? s.bottom - hi + 1e-300 : 0.0;
      if (distance < base_distance) base_distance = distance, base = static_cast<int>(k);
    }
  }
  double load = 0;
  if (!loads_.empty() && load_width_ > 0) {
    const double left = s.x - 0.5 * s.width, right = s.x + 0.5 * s.width;
    const auto first = std::lower_bound(loads_.begin(), loads_.end(), left - load_width_,
                                        [](const SurfaceForce& f, double value) { return f.x < value; });
    for (auto f = first; f != loads_.end() && f->x - 0.5 * load_width_ < right; ++f) {
      const double overlap = std::min(right, f->x + 0.5 * load_width_) - std::max(left, f->x - 0.5 * load_width_);
      if (overlap > 0) load += f->downward * overlap / load_width_;
    }
  }
  SliceForces out;
  out.weight = s.width * column + load;
  if (base >= 0) out.cohesion = layers_[base].soil.cohesion, out.tan_phi = tan_phi_[base];
  out.pore_pressure = table_ ? water_ * std::max(0.0, h - s.bottom) : 0.0;
  return out;
}

}  // namespace talus::postproc
