// The failure surface of a slope from particle data: the sliding mass (particles displaced by
// more than a scene-relative threshold), the slip surface between it and the stable mass drawn
// in the initial configuration, the failed area, and the shear band of equivalent plastic
// strain at failure onset. Rules and their reasons: docs/postproc.md.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "postproc/circle_fit.hpp"
#include "postproc/slope_geometry.hpp"

namespace talus::postproc {

// 1 for the particles whose displacement |x1 - x0| exceeds threshold (m), else 0.
std::vector<char> sliding_mask(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& x1,
                               double threshold);

// Sum of the initial areas (volumes per unit thickness, m^2) of the sliding particles.
double failed_area(const std::vector<char>& sliding, const std::vector<double>& initial_volume);

// The boundary between the sliding mass (above) and the stable mass (below), one point per
// vertical column of `column_width` of the initial configuration, x increasing. In a column,
// the particles sorted by height are split into an upper and a lower group so that as many
// sliding particles as possible are above and stable ones below (the fewest misclassified: a
// stray particle of either kind cannot move the boundary); the point is midway between the
// two particles either side of the split (the lowest particle when all are above). Columns
// whose best split leaves nothing sliding on top have no point. Smoothed by smooth_polyline.
Polyline slip_surface(const std::vector<Eigen::Vector2d>& x0, const std::vector<char>& sliding,
                      double column_width);

// The failure surface of one displacement, as `talus post` (the last frame from the initial
// one) and `talus fos` (the first failing trial from equilibrium) report it: the particles that
// moved more than `threshold` from `from` to `to` slide; their initial area, the slip surface
// drawn at the initial positions x0 in columns of `column_width`, and the circle fitted to it.
// Every position in the canonical frame; the surface and the circle come back through `mirror`
// into the scene's frame.
struct SlipSurface {
  double failed_area = 0;         // m^2
  Polyline surface;               // scene frame, x increasing
  std::optional<Circle> circle;   // scene frame; empty with fewer than 3 non-collinear points
  double circle_rms = 0;          // m, circle_rms_distance of the fit (0 without a circle)
};
SlipSurface extract_slip_surface(const std::vector<Eigen::Vector2d>& x0, const std::vector<Eigen::Vector2d>& from,
                                 const std::vector<Eigen::Vector2d>& to, const std::vector<double>& initial_volume,
                                 double threshold, double column_width, const Mirror& mirror);

// The first frame whose largest displacement from the initial positions exceeds threshold.
std::optional<std::size_t> onset_frame(const std::vector<std::vector<Eigen::Vector2d>>& positions,
                                       const std::vector<Eigen::Vector2d>& x0, double threshold);

// The shear band at onset in the initial configuration: per column, the plastic-strain-weighted
// centroid (initial positions) of the particles whose equivalent plastic strain is at least
// band_fraction x the largest one. Empty when nothing has yielded.
Polyline shear_band(const std::vector<Eigen::Vector2d>& x0, const std::vector<double>& plastic_strain,
                    double column_width, double band_fraction = 0.5);

// Three-point running mean of y (end points kept): removes the particle-scale zigzag of
// column-wise extraction without moving a smooth curve by more than its curvature x h^2 / 3.
Polyline smooth_polyline(const Polyline& line);

}  // namespace talus::postproc
