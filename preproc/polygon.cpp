#include "preproc/polygon.hpp"

#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <unordered_map>

#include "common/geometry.hpp"

namespace talus::preproc {

std::optional<std::vector<std::vector<std::size_t>>> chain_loops(const std::vector<std::array<std::size_t, 2>>& segments,
                                                                 std::size_t* open_end) {
  // A curve listed twice in a group, or a segment seen from both sides, is one edge.
  std::vector<std::array<std::size_t, 2>> edges;
  std::set<std::pair<std::size_t, std::size_t>> seen;
  for (const auto& [a, b] : segments)
    if (a != b && seen.insert(std::minmax(a, b)).second) edges.push_back({a, b});

  std::unordered_map<std::size_t, std::vector<std::size_t>> incident;  // node -> edges
  for (std::size_t s = 0; s < edges.size(); ++s) {
    incident[edges[s][0]].push_back(s);
    incident[edges[s][1]].push_back(s);
  }
  std::vector<bool> used(edges.size(), false);
  auto unused_edge_at = [&](std::size_t node) -> std::ptrdiff_t {
    for (std::size_t s : incident[node])
      if (!used[s]) return static_cast<std::ptrdiff_t>(s);
    return -1;
  };

  std::vector<std::vector<std::size_t>> loops;
  for (std::size_t first = 0; first < edges.size(); ++first) {
    if (used[first]) continue;
    used[first] = true;
    // Walk edge to edge. Whenever the walk returns to a node already on the path, the part of
    // the path after that node is a simple closed loop: cut it off and walk on.
    std::vector<std::size_t> path{edges[first][0]};
    std::unordered_map<std::size_t, std::size_t> position{{edges[first][0], 0}};
    std::size_t tip = edges[first][1];
    while (true) {
      const auto found = position.find(tip);
      if (found == position.end()) {
        position[tip] = path.size();
        path.push_back(tip);
      } else {
        const std::size_t start = found->second;
        loops.emplace_back(path.begin() + static_cast<std::ptrdiff_t>(start), path.end());
        for (std::size_t j = start + 1; j < path.size(); ++j) position.erase(path[j]);
        path.resize(start + 1);
      }
      const std::ptrdiff_t next = unused_edge_at(path.back());
      if (next < 0) {
        if (path.size() == 1) break;  // every edge of this component is on a closed loop
        if (open_end) *open_end = path.back();
        return std::nullopt;
      }
      used[next] = true;
      const auto& edge = edges[next];
      tip = edge[0] == path.back() ? edge[1] : edge[0];
    }
  }
  return loops;
}

Region::Region(std::vector<Loop> loops) : loops_(std::move(loops)) {
  for (const auto& loop : loops_) {
    std::vector<Kernel::Point_2> points;
    Eigen::AlignedBox2d box;
    for (const auto& v : loop) {
      points.emplace_back(v.x(), v.y());
      box.extend(v);
    }
    points_.push_back(std::move(points));
    boxes_.push_back(box);
  }
}

Region::Side Region::side(std::size_t loop, const Eigen::Vector2d& p) const {
  if (!boxes_[loop].contains(p)) return Side::Outside;
  switch (CGAL::bounded_side_2(points_[loop].begin(), points_[loop].end(), Kernel::Point_2(p.x(), p.y()), Kernel())) {
    case CGAL::ON_BOUNDED_SIDE: return Side::Inside;
    case CGAL::ON_BOUNDARY: return Side::Boundary;
    default: return Side::Outside;
  }
}

bool Region::contains(const Eigen::Vector2d& p) const {
  int inside = 0;
  for (std::size_t k = 0; k < loops_.size(); ++k) inside += side(k, p) == Side::Inside;
  return inside % 2 == 1;
}

bool Region::covers(const Eigen::Vector2d& p) const {
  int inside = 0;
  for (std::size_t k = 0; k < loops_.size(); ++k) {
    const Side s = side(k, p);
    if (s == Side::Boundary) return true;
    inside += s == Side::Inside;
  }
  return inside % 2 == 1;
}

double Region::distance_to_boundary(const Eigen::Vector2d& p) const {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& loop : loops_)
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      const Eigen::Vector2d a = loop[i], ab = loop[(i + 1) % n] - a;
      const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
      nearest = std::min(nearest, (a + t * ab - p).norm());
    }
  return nearest;
}

double Region::area() const {
  double total = 0;
  for (std::size_t i = 0; i < loops_.size(); ++i) {
    int depth = 0;
    for (std::size_t j = 0; j < loops_.size(); ++j) {
      if (j == i) continue;
      // Loops may touch at vertices: judge nesting by the first vertex not on loop j.
      for (const auto& v : loops_[i]) {
        const Side s = side(j, v);
        if (s == Side::Boundary) continue;
        depth += s == Side::Inside;
        break;
      }
    }
    total += (depth % 2 == 0 ? 1 : -1) * std::abs(signed_area(loops_[i]));
  }
  return total;
}

double Region::highest_y() const {
  double y = -std::numeric_limits<double>::infinity();
  for (const auto& loop : loops_)
    for (const auto& v : loop) y = std::max(y, v.y());
  return y;
}

Eigen::AlignedBox2d Region::bounds() const {
  Eigen::AlignedBox2d all;
  for (const auto& box : boxes_) all.extend(box);
  return all;
}

}  // namespace talus::preproc
