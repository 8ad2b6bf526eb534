#include "postproc/slope_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/geometry.hpp"

namespace talus::postproc {
namespace {

// The upper boundary of a simple polygon, x increasing. Walking a counter-clockwise loop, the
// top runs from the rightmost to the leftmost vertex; of several vertices on a vertical side,
// the highest one is where the top begins or ends.
Polyline upper_boundary(Polyline loop) {
  if (loop.size() < 3) throw Error("postproc: a body outline has fewer than 3 vertices");
  if (signed_area(loop) < 0) std::reverse(loop.begin(), loop.end());
  auto rightmost = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  };
  auto leftmost = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() > b.x() || (a.x() == b.x() && a.y() < b.y());
  };
  const std::size_t n = loop.size();
  const std::size_t right = std::max_element(loop.begin(), loop.end(), rightmost) - loop.begin();
  const std::size_t left = std::max_element(loop.begin(), loop.end(), leftmost) - loop.begin();
  Polyline top;
  for (std::size_t i = right;; i = (i + 1) % n) {
    top.push_back(loop[i]);
    if (i == left) break;
  }
  std::reverse(top.begin(), top.end());
  return top;
}

}  // namespace

const Polyline& outer_loop(const std::vector<Polyline>& loops) {
  if (loops.empty()) throw Error("postproc: the analysed body has no outline loops");
  return *std::max_element(loops.begin(), loops.end(), [](const Polyline& a, const Polyline& b) {
    return std::abs(signed_area(a)) < std::abs(signed_area(b));
  });
}

bool descends_to_left(const Polyline& loop, double motion_x) {
  const Polyline top = upper_boundary(loop);
  if (top.front().y() == top.back().y()) return motion_x < 0;
  return top.front().y() < top.back().y();
}

SlopeProfile slope_profile(const Polyline& loop, bool level_top_runs_out) {
  SlopeProfile profile;
  profile.surface = upper_boundary(loop);
  Polyline& s = profile.surface;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (s[i].x() < s[i - 1].x())
      throw Error("postproc: the ground surface of the analysed body overhangs near (" + std::to_string(s[i].x()) +
                  ", " + std::to_string(s[i].y()) + "); the slope metrics need a surface without overhangs");
  profile.base_y = std::min_element(loop.begin(), loop.end(), [](const auto& a, const auto& b) {
                     return a.y() < b.y();
                   })->y();
  // A level-topped body (a column, a block) that ran out has no slope on its top: its downhill
  // face is the side it ran out from, down to the lowest point of the loop on that side.
  const double x_end = s.back().x();
  double foot_y = s.back().y();
  for (const auto& p : loop)
    if (p.x() == x_end) foot_y = std::min(foot_y, p.y());
  const bool level_top = std::all_of(s.begin(), s.end(), [&](const auto& p) { return p.y() == s.front().y(); });
  if (level_top_runs_out && level_top && foot_y < s.back().y()) s.emplace_back(x_end, foot_y);

  double top = -INFINITY, bottom = INFINITY;
  for (const auto& p : s) top = std::max(top, p.y()), bottom = std::min(bottom, p.y());
  const double tolerance = 1e-9 * std::max(1.0, top - bottom);
  std::size_t crest = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s[i].y() >= top - tolerance) crest = i;
  std::size_t toe = s.size() - 1;
  for (std::size_t i = crest; i < s.size(); ++i)
    if (s[i].y() <= bottom + tolerance) {
      toe = i;
      break;
    }
  profile.crest = s[crest];
  profile.toe = s[toe];
  profile.height = profile.crest.y() - profile.toe.y();
  return profile;
}

bool has_vertical_face(const Polyline& surface) {
  for (std::size_t i = 1; i < surface.size(); ++i)
    if (surface[i].x() == surface[i - 1].x()) return true;
  return false;
}

double surface_height(const Polyline& surface, double x) {
  if (x <= surface.front().x()) return surface.front().y();
  if (x >= surface.back().x()) return surface.back().y();
  // At a vertical step (two points at one x) the height just downhill of it counts.
  const auto upper = std::upper_bound(surface.begin(), surface.end(), x,
                                      [](double value, const Eigen::Vector2d& p) { return value < p.x(); });
  const Eigen::Vector2d& b = *upper;
  const Eigen::Vector2d& a = *(upper - 1);
  return a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
}

Polyline Mirror::polyline(const Polyline& line) const {
  if (!active) return line;
  Polyline out;
  out.reserve(line.size());
  for (auto it = line.rbegin(); it != line.rend(); ++it) out.push_back(point(*it));
  return out;
}

}  // namespace talus::postproc
