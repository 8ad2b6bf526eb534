#include "postproc/bishop.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace talus::postproc {
namespace {

constexpr int kSurfaceSamples = 240;  // to find where a circle cuts the surface, then bisection

double arc_height(const Circle& circle, double x) {
  const double dx = x - circle.centre.x();
  return circle.centre.y() - std::sqrt(std::max(circle.radius * circle.radius - dx * dx, 0.0));
}

// Entry and exit of the lower arc through the ground: the one interval where the arc is below
// the surface, strictly inside both the surface's x range and [xc - R, xc + R]. A depth of at
// most `touch` counts as on the surface, so that a circle through an end of the surface (a toe
// at the body's corner) cuts it there instead of leaving through the side by a rounding error.
std::optional<std::pair<double, double>> cut_interval(const Polyline& surface, const Circle& circle, double touch) {
  const double lo = std::max(circle.centre.x() - circle.radius, surface.front().x());
  const double hi = std::min(circle.centre.x() + circle.radius, surface.back().x());
  if (!(hi > lo)) return std::nullopt;
  auto depth = [&](double x) { return surface_height(surface, x) - arc_height(circle, x); };
  auto crossing = [&](double outside, double inside) {
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (outside + inside);
      (depth(mid) > touch ? inside : outside) = mid;
    }
    return 0.5 * (outside + inside);
  };
  int runs = 0;
  double entry = 0, exit = 0;
  bool previous_inside = false;
  double previous_x = lo;
  for (int i = 0; i <= kSurfaceSamples; ++i) {
    const double x = lo + (hi - lo) * i / kSurfaceSamples;
    const bool inside = depth(x) > touch;
    if (inside && (i == 0 || i == kSurfaceSamples)) return std::nullopt;  // leaves through a side
    if (inside && !previous_inside) {
      if (++runs > 1) return std::nullopt;
      entry = crossing(previous_x, x);
    }
    if (!inside && previous_inside) exit = crossing(x, previous_x);
    previous_inside = inside;
    previous_x = x;
  }
  if (runs != 1) return std::nullopt;
  return std::make_pair(entry, exit);
}

double lowest_arc_point(const Circle& circle, double x_entry, double x_exit) {
  return (circle.centre.x() > x_entry && circle.centre.x() < x_exit)
             ? circle.centre.y() - circle.radius
             : std::min(arc_height(circle, x_entry), arc_height(circle, x_exit));
}

}  // namespace

const char* to_string(CircleKind kind) {
  switch (kind) {
    case CircleKind::Toe: return "toe";
    case CircleKind::Face: return "face";
    case CircleKind::Base: return "base";
  }
  return "?";
}

std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SliceModel& ground,
                                                    const Circle& circle, double x_entry, double x_exit,
                                                    int slices) {
  if (!(circle.radius > 0) || slices < 1 || !(x_exit > x_entry)) return std::nullopt;
  const double b = (x_exit - x_entry) / slices;
  std::vector<SliceForces> forces(slices);
  std::vector<double> sin_alpha(slices), cos_alpha(slices);
  double driving = 0;  // sum W sin(alpha): the weight's moment about the centre / R
  for (int i = 0; i < slices; ++i) {
    const double x = x_entry + (i + 0.5) * b;
    const double top = surface_height(profile.surface, x);
    forces[i] = ground.forces({x, b, top, std::min(arc_height(circle, x), top)});
    sin_alpha[i] = std::clamp((circle.centre.x() - x) / circle.radius, -1.0, 1.0);
    cos_alpha[i] = std::sqrt(1 - sin_alpha[i] * sin_alpha[i]);
    driving += forces[i].weight * sin_alpha[i];
    // A pseudo-static force k_h W towards the toe at the slice's height: its moment about the centre / R.
    if (forces[i].horizontal != 0) driving += forces[i].horizontal * (circle.centre.y() - forces[i].height) / circle.radius;
  }
  if (!(driving > 0)) return std::nullopt;

  // Start from the ordinary (Fellenius) method, then fixed-point iteration on F.
  double resisting = 0;
  for (int i = 0; i < slices; ++i) {
    const SliceForces& f = forces[i];
    const double base_length = b / std::max(cos_alpha[i], 1e-12);
    resisting += f.cohesion * base_length + (f.weight * cos_alpha[i] - f.pore_pressure * base_length) * f.tan_phi;
  }
  double fos = resisting / driving;
  if (!(fos > 0) || !std::isfinite(fos)) fos = 1;
  double smallest_m_alpha = 0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    resisting = 0;
    smallest_m_alpha = INFINITY;
    for (int i = 0; i < slices; ++i) {
      const SliceForces& f = forces[i];
      const double m_alpha = cos_alpha[i] + sin_alpha[i] * f.tan_phi / fos;
      if (sin_alpha[i] < 0) smallest_m_alpha = std::min(smallest_m_alpha, m_alpha);
      resisting += (f.cohesion * b + (f.weight - f.pore_pressure * b) * f.tan_phi) / m_alpha;
    }
    const double next = resisting / driving;
    if (!(next > 0) || !std::isfinite(next)) return std::nullopt;
    const bool converged = std::abs(next - fos) < 1e-9 * fos;
    fos = next;
    if (converged) break;
  }
  if (smallest_m_alpha <= 0.2) return std::nullopt;

  BishopResult result;
  result.circle = circle;
  result.factor_of_safety = fos;
  result.x_entry = x_entry;
  result.x_exit = x_exit;
  result.y_entry = surface_height(profile.surface, x_entry);
  result.y_exit = surface_height(profile.surface, x_exit);
  const double near = 1e-3 * std::max(profile.height, 1e-9);
  result.kind = std::abs(x_exit - profile.toe.x()) <= near ? CircleKind::Toe
                : x_exit < profile.toe.x()                  ? CircleKind::Face
                                                            : CircleKind::Base;
  result.tangent_to_base = circle.centre.x() > x_entry - near && circle.centre.x() < x_exit + near &&
                           std::abs(circle.centre.y() - circle.radius - profile.base_y) <= near;
  return result;
}

std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SliceModel& ground,
                                                    const Circle& circle, int slices) {
  if (!(circle.radius > 0) || slices < 1) return std::nullopt;
  const double scale = std::max(profile.height, 1.0);
  const auto cut = cut_interval(profile.surface, circle, 1e-9 * scale);
  if (!cut) return std::nullopt;
  const auto [x_entry, x_exit] = *cut;
  if (lowest_arc_point(circle, x_entry, x_exit) < profile.base_y - 1e-9 * scale) return std::nullopt;
  return bishop_factor_of_safety(profile, ground, circle, x_entry, x_exit, slices);
}

std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SoilStrength& soil,
                                                    const Circle& circle, int slices) {
  return bishop_factor_of_safety(profile, UniformSoil(soil), circle, slices);
}

std::optional<BishopResult> bishop_search(const SlopeProfile& profile, const SoilStrength& soil,
                                          const BishopSearchSettings& settings) {
  return bishop_search(profile, UniformSoil(soil), settings);
}

BishopResult mirrored(BishopResult result, const Mirror& mirror) {
  result.circle.centre = mirror.point(result.circle.centre);
  result.x_entry = mirror.x(result.x_entry);
  result.x_exit = mirror.x(result.x_exit);
  return result;
}

}  // namespace talus::postproc
