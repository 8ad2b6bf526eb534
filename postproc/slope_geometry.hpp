// The initial slope as the postprocessor sees it: the ground surface (the upper boundary of a
// body's outer loop), its crest and toe, and the slope height. Every metric of postproc works
// in a frame where the slope descends towards +x; a slope that descends towards -x is mirrored
// (x -> -x) on the way in and its results mirrored back on the way out (see Mirror).
#pragma once
#include <Eigen/Core>
#include <vector>

namespace talus::postproc {

using Polyline = std::vector<Eigen::Vector2d>;

struct SlopeProfile {
  Polyline surface;          // ground surface, x strictly increasing (m)
  Eigen::Vector2d crest{0, 0};  // downhill end of the highest part of the surface (m)
  Eigen::Vector2d toe{0, 0};    // first point at the lowest level downhill of the crest (m)
  double height = 0;         // crest.y - toe.y (m)
  double base_y = 0;         // lowest point of the outer loop (m): slip circles stay above it
};

// The loop of largest absolute area (the outer boundary of the body).
const Polyline& outer_loop(const std::vector<Polyline>& loops);

// True when the ground at the left end of the loop's upper boundary is lower than at its right
// end, i.e. the slope descends towards -x and must be mirrored into the canonical frame.
bool descends_to_left(const Polyline& loop);

// The profile of a loop whose slope descends towards +x. Throws talus::Error when the upper
// boundary is not a function of x (an overhang), which a method of slices cannot treat.
SlopeProfile slope_profile(const Polyline& loop);

// Height of the surface at x by linear interpolation; constant beyond either end.
double surface_height(const Polyline& surface, double x);

// x -> -x when active. Applied to every position, loop and result that has an x.
struct Mirror {
  bool active = false;
  double x(double value) const { return active ? -value : value; }
  Eigen::Vector2d point(const Eigen::Vector2d& p) const { return {x(p.x()), p.y()}; }
  Polyline polyline(const Polyline& line) const;  // reverses the order too, so x stays increasing
};

}  // namespace talus::postproc
