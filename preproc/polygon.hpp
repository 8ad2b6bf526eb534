// Body outlines: chaining mesh segments into closed loops, and the even-odd region those loops
// bound (outer boundaries, holes, islands in holes, several disjoint pieces), tested with
// CGAL's exact orientation predicates.
#pragma once
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <optional>
#include <vector>

namespace talus::preproc {

using Loop = std::vector<Eigen::Vector2d>;  // closed: the last vertex joins the first
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Chains segments (pairs of node ids) into closed loops of node ids. A node where several
// loops touch is split so that every loop is simple. Repeated segments count once. Returns
// std::nullopt and sets `open_end` to a node of an open chain when the segments do not close.
std::optional<std::vector<std::vector<std::size_t>>> chain_loops(const std::vector<std::array<std::size_t, 2>>& segments,
                                                                 std::size_t* open_end = nullptr);

// The region inside an odd number of loops.
class Region {
 public:
  explicit Region(std::vector<Loop> loops);

  // Strictly inside: a point on a loop counts as outside that loop, so two bodies that share
  // an edge never both claim a point on it.
  bool contains(const Eigen::Vector2d& p) const;
  // Inside or on a loop.
  bool covers(const Eigen::Vector2d& p) const;
  // Distance from p to the nearest loop edge.
  double distance_to_boundary(const Eigen::Vector2d& p) const;
  // Area of the region (loops nested k deep count with sign (-1)^k).
  double area() const;
  const std::vector<Loop>& loops() const { return loops_; }
  double highest_y() const;
  Eigen::AlignedBox2d bounds() const;

 private:
  enum class Side { Inside, Boundary, Outside };
  Side side(std::size_t loop, const Eigen::Vector2d& p) const;

  std::vector<Loop> loops_;
  std::vector<std::vector<Kernel::Point_2>> points_;  // the loops again, for CGAL
  std::vector<Eigen::AlignedBox2d> boxes_;
};

}  // namespace talus::preproc
