#include "postproc/failure_surface.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace talus::postproc {
namespace {

std::map<long, std::vector<std::size_t>> columns_of(const std::vector<Eigen::Vector2d>& x0, double width) {
  std::map<long, std::vector<std::size_t>> columns;
  for (std::size_t p = 0; p < x0.size(); ++p)
    columns[static_cast<long>(std::floor(x0[p].x() / width))].push_back(p);
  return columns;
}

}  // namespace

std::vector<char> sliding_mask(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                               double threshold) {
  std::vector<char> sliding(x0.size(), 0);
  for (std::size_t p = 0; p < x0.size(); ++p) sliding[p] = (x1[p] - x0[p]).norm() > threshold;
  return sliding;
}

double failed_area(const std::vector<char>& sliding, const std::vector<double>& initial_volume) {
  double area = 0;
  for (std::size_t p = 0; p < sliding.size(); ++p)
    if (sliding[p]) area += initial_volume[p];
  return area;
}

Polyline slip_surface(const std::vector<Eigen::Vector2d>& x0, const std::vector<char>& sliding,
                      double column_width) {
  Polyline points;
  for (auto& [column, members] : columns_of(x0, column_width)) {
    std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) { return x0[a].y() > x0[b].y(); });
    // score(k) = sliding among the top k + stable among the rest; score(0) = all stable.
    long stable_total = 0;
    for (std::size_t p : members) stable_total += !sliding[p];
    long score = stable_total, best_score = stable_total;
    std::size_t best_split = 0;
    for (std::size_t k = 1; k <= members.size(); ++k) {
      score += sliding[members[k - 1]] ? 1 : -1;
      if (score > best_score) best_score = score, best_split = k;
    }
    if (best_split == 0) continue;
    const Eigen::Vector2d& above = x0[members[best_split - 1]];
    points.push_back(best_split == members.size() ? above : 0.5 * (above + x0[members[best_split]]));
  }
  return smooth_polyline(points);
}

SlipSurface extract_slip_surface(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& from,
                                 const std::vector<Eigen::Vector2d>& to, const std::vector<double>& initial_volume,
                                 double threshold, double column_width, const Mirror& mirror) {
  SlipSurface out;
  const std::vector<char> sliding = sliding_mask(from, to, threshold);
  out.failed_area = failed_area(sliding, initial_volume);
  const Polyline surface = slip_surface(x0, sliding, column_width);
  out.circle = fit_circle(surface);
  if (out.circle) {
    out.circle_rms = circle_rms_distance(*out.circle, surface);
    out.circle->centre = mirror.point(out.circle->centre);
  }
  out.surface = mirror.polyline(surface);
  return out;
}

std::optional<std::size_t> onset_frame(const std::vector<std::vector<Eigen::Vector2d>>& positions,
                                       const std::vector<Eigen::Vector2d>& x0, double threshold) {
  for (std::size_t frame = 0; frame < positions.size(); ++frame)
    for (std::size_t p = 0; p < x0.size(); ++p)
      if ((positions[frame][p] - x0[p]).norm() > threshold) return frame;
  return std::nullopt;
}

Polyline shear_band(const std::vector<Eigen::Vector2d>& x0, const std::vector<double>& plastic_strain,
                    double column_width, double band_fraction) {
  const double largest = plastic_strain.empty() ? 0 : *std::max_element(plastic_strain.begin(), plastic_strain.end());
  if (!(largest > 0)) return {};
  const double cutoff = band_fraction * largest;
  Polyline points;
  for (const auto& [column, members] : columns_of(x0, column_width)) {
    Eigen::Vector2d weighted = Eigen::Vector2d::Zero();
    double weight = 0;
    for (std::size_t p : members)
      if (plastic_strain[p] >= cutoff) weighted += plastic_strain[p] * x0[p], weight += plastic_strain[p];
    if (weight > 0) points.push_back(weighted / weight);
  }
  return smooth_polyline(points);
}

Polyline smooth_polyline(const Polyline& line) {
  Polyline smoothed = line;
  for (std::size_t i = 1; i + 1 < line.size(); ++i)
    smoothed[i].y() = (line[i - 1].y() + line[i].y() + line[i + 1].y()) / 3.0;
  return smoothed;
}

}  // namespace talus::postproc
