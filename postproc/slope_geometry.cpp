#include "postproc/slope_geometry.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/geometry.hpp"

namespace talus::postproc {
namespace {

// The profile of the ground `surface` (x increasing) formed by `loops`.
SlopeProfile profile_of(Polyline surface, const std::vector<Polyline>& loops, bool level_top_runs_out);

// Height of a top (x increasing, x inside its range) approached from the left (from_left) or
// from the right: at a vertical step the first or the last of its points at that x.
double limit_height(const Polyline& top, double x, bool from_left) {
  const auto at_or_after = std::lower_bound(top.begin(), top.end(), x,
                                            [](const Eigen::Vector2d& p, double value) { return p.x() < value; });
  const auto after = std::upper_bound(top.begin(), top.end(), x,
                                      [](double value, const Eigen::Vector2d& p) { return value < p.x(); });
  if (from_left) {
    if (at_or_after->x() == x) return at_or_after->y();
    const Eigen::Vector2d& a = *(at_or_after - 1);
    const Eigen::Vector2d& b = *at_or_after;
    return a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
  }
  if ((after - 1)->x() == x) return (after - 1)->y();
  const Eigen::Vector2d& a = *(after - 1);
  const Eigen::Vector2d& b = *after;
  return a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
}

}  // namespace

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

Polyline upper_envelope(const std::vector<Polyline>& loops) {
  if (loops.empty()) throw Error("postproc: no body outline to take the ground surface from");
  if (loops.size() == 1) return upper_boundary(loops.front());
  std::vector<Polyline> tops;
  for (const auto& loop : loops) tops.push_back(upper_boundary(loop));
  // Where the highest top may change: every vertex, and every crossing of two tops' segments.
  std::vector<double> xs;
  double lo_y = INFINITY, hi_y = -INFINITY;
  for (const auto& top : tops)
    for (const auto& p : top) xs.push_back(p.x()), lo_y = std::min(lo_y, p.y()), hi_y = std::max(hi_y, p.y());
  for (std::size_t a = 0; a < tops.size(); ++a)
    for (std::size_t b = a + 1; b < tops.size(); ++b)
      for (std::size_t i = 1; i < tops[a].size(); ++i)
        for (std::size_t j = 1; j < tops[b].size(); ++j) {
          const Eigen::Vector2d p = tops[a][i - 1], r = tops[a][i] - p;
          const Eigen::Vector2d q = tops[b][j - 1], s = tops[b][j] - q;
          const double cross = r.x() * s.y() - r.y() * s.x();
          if (cross == 0) continue;
          const Eigen::Vector2d qp = q - p;
          const double t = (qp.x() * s.y() - qp.y() * s.x()) / cross;
          const double u = (qp.x() * r.y() - qp.y() * r.x()) / cross;
          if (t > 0 && t < 1 && u > 0 && u < 1) xs.push_back(p.x() + t * r.x());
        }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  const double tolerance = 1e-12 * std::max(1.0, hi_y - lo_y);
  // The highest of the tops that reach x from the left (or from the right).
  const auto highest = [&](double x, bool from_left) {
    double y = -INFINITY;
    for (const auto& top : tops) {
      const bool covers = from_left ? top.front().x() < x && x <= top.back().x()
                                    : top.front().x() <= x && x < top.back().x();
      if (covers) y = std::max(y, limit_height(top, x, from_left));
    }
    return y;
  };
  Polyline envelope;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const double x = xs[k];
    if (k + 1 < xs.size() && highest(0.5 * (x + xs[k + 1]), true) == -INFINITY)
      throw Error("postproc: the analysed bodies leave a gap in the ground between x = " + std::to_string(x) +
                  " and " + std::to_string(xs[k + 1]) + " m; list touching bodies in post.bodies");
    const double left = k > 0 ? highest(x, true) : -INFINITY;
    const double right = k + 1 < xs.size() ? highest(x, false) : -INFINITY;
    if (k == 0) envelope.emplace_back(x, right);
    else if (k + 1 == xs.size() || std::abs(left - right) <= tolerance) envelope.emplace_back(x, left);
    else envelope.emplace_back(x, left), envelope.emplace_back(x, right);
  }
  return envelope;
}

const Polyline& outer_loop(const std::vector<Polyline>& loops) {
  if (loops.empty()) throw Error("postproc: the analysed body has no outline loops");
  return *std::max_element(loops.begin(), loops.end(), [](const Polyline& a, const Polyline& b) {
    return std::abs(signed_area(a)) < std::abs(signed_area(b));
  });
}

namespace {

bool surface_descends_to_left(const Polyline& top, double motion_x) {
  if (top.front().y() == top.back().y()) return motion_x < 0;
  return top.front().y() < top.back().y();
}

}  // namespace

bool descends_to_left(const Polyline& loop, double motion_x) {
  return surface_descends_to_left(upper_boundary(loop), motion_x);
}

bool descends_to_left(const std::vector<Polyline>& loops, double motion_x) {
  return surface_descends_to_left(upper_envelope(loops), motion_x);
}

SlopeProfile slope_profile(const Polyline& loop, bool level_top_runs_out) {
  return profile_of(upper_boundary(loop), {loop}, level_top_runs_out);
}

SlopeProfile slope_profile(const std::vector<Polyline>& loops, bool level_top_runs_out) {
  if (loops.size() == 1) return slope_profile(loops.front(), level_top_runs_out);
  return profile_of(upper_envelope(loops), loops, level_top_runs_out);
}

namespace {

SlopeProfile profile_of(Polyline surface, const std::vector<Polyline>& loops, bool level_top_runs_out) {
  SlopeProfile profile;
  profile.surface = std::move(surface);
  Polyline& s = profile.surface;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (s[i].x() < s[i - 1].x())
      throw Error("postproc: the ground surface of the analysed body overhangs near (" + std::to_string(s[i].x()) +
                  ", " + std::to_string(s[i].y()) + "); the slope metrics need a surface without overhangs");
  profile.base_y = INFINITY;
  for (const auto& loop : loops)
    profile.base_y = std::min(profile.base_y, std::min_element(loop.begin(), loop.end(), [](const auto& a, const auto& b) {
                                                return a.y() < b.y();
                                              })->y());
  // A level-topped body (a column, a block) that ran out has no slope on its top: its downhill
  // face is the side it ran out from, down to the lowest point of the loop on that side.
  const double x_end = s.back().x();
  double foot_y = s.back().y();
  for (const auto& loop : loops)
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

}  // namespace

bool has_vertical_face(const Polyline& surface) {
  for (std::size_t i = 1; i < surface.size(); ++i)
    if (surface[i].x() == surface[i - 1].x()) return true;
  return false;
}

// At a vertical step (two points at one x) the height just downhill of it counts.
double surface_height(const Polyline& surface, double x) { return polyline_height(surface, x); }

Polyline Mirror::polyline(const Polyline& line) const {
  if (!active) return line;
  Polyline out;
  out.reserve(line.size());
  for (auto it = line.rbegin(); it != line.rend(); ++it) out.push_back(point(*it));
  return out;
}

}  // namespace talus::postproc
