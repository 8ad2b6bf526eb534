// The initial slope as the postprocessor sees it: the ground surface (the upper boundary of a
// body's outer loop), its crest and toe, and the slope height. Every metric of postproc works
// in a frame where the slope descends towards +x; a slope that descends towards -x is mirrored
// (x -> -x) on the way in and its results mirrored back on the way out (see Mirror).
#pragma once
#include <Eigen/Core>
#include <vector>

namespace talus::postproc {

using Polyline = std::vector<Eigen::Vector2d>;

// The initial front of a body, the foot of its downhill face, is the toe: the foot of a slope
// face, of a vertical cliff, or of a column's free side.
struct SlopeProfile {
  Polyline surface;          // ground surface, x increasing; two points at one x make a vertical face (m)
  Eigen::Vector2d crest{0, 0};  // downhill end of the highest part of the surface (m)
  Eigen::Vector2d toe{0, 0};    // first point at the lowest level downhill of the crest (m)
  double height = 0;         // crest.y - toe.y (m)
  double base_y = 0;         // lowest point of the outer loop (m): slip circles stay above it
};

// The loop of largest absolute area (the outer boundary of the body).
const Polyline& outer_loop(const std::vector<Polyline>& loops);

// True when the ground at the left end of the loop's upper boundary is lower than at its right
// end, i.e. the slope descends towards -x and must be mirrored into the canonical frame. A
// level top (a column, a block) has no such direction: then the body's motion decides, true
// when motion_x (its mean displacement along x, m) is negative.
bool descends_to_left(const Polyline& loop, double motion_x = 0);

// The profile of a loop whose slope descends towards +x. The upper boundary may have vertical
// faces (a cliff). With level_top_runs_out, a level-topped body (a column that ran out towards
// +x) gets its +x side as its face: the surface goes on down that side to the loop's lowest
// point there, which is the toe; without, its profile is flat (height 0). Throws talus::Error
// when the upper boundary overhangs.
SlopeProfile slope_profile(const Polyline& loop, bool level_top_runs_out = false);

// The upper boundary of a loop (a simple polygon), x increasing; see slope_profile.
Polyline upper_boundary(Polyline loop);

// The ground of several bodies together (a layered slope): at every x the highest of the
// loops' upper boundaries that reach that x, x increasing, with two points at one x where it
// steps (a cliff, or the side of a body standing on another). One loop: its upper boundary.
// Throws talus::Error where no loop covers an x between the leftmost and the rightmost point.
Polyline upper_envelope(const std::vector<Polyline>& loops);

// The profile of the ground formed by the outer loops of several bodies (upper_envelope),
// the base the lowest point of any of them. One loop: slope_profile(loop, ...) exactly.
SlopeProfile slope_profile(const std::vector<Polyline>& loops, bool level_top_runs_out = false);

// descends_to_left for the upper envelope of several loops.
bool descends_to_left(const std::vector<Polyline>& loops, double motion_x = 0);

// True when the surface has a vertical face (two points at one x): a method of slices needs
// the ground as a function of x.
bool has_vertical_face(const Polyline& surface);

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
