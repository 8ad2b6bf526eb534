#include "postproc/bishop.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace talus::postproc {
namespace {

constexpr int kSurfaceSamples = 240;  // to find where a circle cuts the surface, then bisection

double arc_height(const Circle& circle, double x) {
  const double dx = x - circle.centre.x();
  return circle.centre.y() - std::sqrt(std::max(circle.radius * circle.radius - dx * dx, 0.0));
}

// Entry and exit of the lower arc through the ground: the one interval where the arc is below
// the surface, strictly inside both the surface's x range and [xc - R, xc + R].
std::optional<std::pair<double, double>> cut_interval(const Polyline& surface, const Circle& circle) {
  const double lo = std::max(circle.centre.x() - circle.radius, surface.front().x());
  const double hi = std::min(circle.centre.x() + circle.radius, surface.back().x());
  if (!(hi > lo)) return std::nullopt;
  auto depth = [&](double x) { return surface_height(surface, x) - arc_height(circle, x); };
  auto crossing = [&](double outside, double inside) {
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (outside + inside);
      (depth(mid) > 0 ? inside : outside) = mid;
    }
    return 0.5 * (outside + inside);
  };
  int runs = 0;
  double entry = 0, exit = 0;
  bool previous_inside = false;
  double previous_x = lo;
  for (int i = 0; i <= kSurfaceSamples; ++i) {
    const double x = lo + (hi - lo) * i / kSurfaceSamples;
    const bool inside = depth(x) > 0;
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

double distance_to_polyline(const Eigen::Vector2d& point, const Polyline& line) {
  double best = INFINITY;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Eigen::Vector2d segment = line[i + 1] - line[i];
    const double t = std::clamp((point - line[i]).dot(segment) / segment.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (point - (line[i] + t * segment)).norm());
  }
  return best;
}

}  // namespace

std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SoilStrength& soil,
                                                    const Circle& circle, int slices) {
  if (!(circle.radius > 0) || slices < 1) return std::nullopt;
  const auto cut = cut_interval(profile.surface, circle);
  if (!cut) return std::nullopt;
  const auto [x_entry, x_exit] = *cut;

  const double lowest = (circle.centre.x() > x_entry && circle.centre.x() < x_exit)
                            ? circle.centre.y() - circle.radius
                            : std::min(arc_height(circle, x_entry), arc_height(circle, x_exit));
  if (lowest < profile.base_y - 1e-9 * std::max(profile.height, 1.0)) return std::nullopt;

  const double tan_phi = std::tan(soil.friction_angle * M_PI / 180.0);
  const double b = (x_exit - x_entry) / slices;
  std::vector<double> weight(slices), sin_alpha(slices), cos_alpha(slices);
  double driving = 0;  // sum W sin(alpha): the weight's moment about the centre / R
  for (int i = 0; i < slices; ++i) {
    const double x_m = x_entry + (i + 0.5) * b;
    const double h = std::max(surface_height(profile.surface, x_m) - arc_height(circle, x_m), 0.0);
    weight[i] = soil.unit_weight * b * h;
    sin_alpha[i] = (circle.centre.x() - x_m) / circle.radius;
    cos_alpha[i] = std::sqrt(std::max(1 - sin_alpha[i] * sin_alpha[i], 0.0));
    driving += weight[i] * sin_alpha[i];
  }
  if (!(driving > 0)) return std::nullopt;

  // Start from the ordinary (Fellenius) method, then fixed-point iteration on F.
  double resisting = 0;
  for (int i = 0; i < slices; ++i)
    resisting += soil.cohesion * b / std::max(cos_alpha[i], 1e-12) + weight[i] * cos_alpha[i] * tan_phi;
  double fos = resisting / driving;
  if (!(fos > 0) || !std::isfinite(fos)) fos = 1;
  double smallest_m_alpha = 0;
  for (int iteration = 0; iteration < 200; ++iteration) {
    resisting = 0;
    smallest_m_alpha = INFINITY;
    for (int i = 0; i < slices; ++i) {
      const double m_alpha = cos_alpha[i] + sin_alpha[i] * tan_phi / fos;
      if (sin_alpha[i] < 0) smallest_m_alpha = std::min(smallest_m_alpha, m_alpha);
      resisting += (soil.cohesion * b + weight[i] * tan_phi) / m_alpha;
    }
    const double next = resisting / driving;
    if (!(next > 0) || !std::isfinite(next)) return std::nullopt;
    const bool converged = std::abs(next - fos) < 1e-9 * fos;
    fos = next;
    if (converged) break;
  }
  if (smallest_m_alpha <= 0.2) return std::nullopt;
  return BishopResult{circle, fos, x_entry, x_exit};
}

std::optional<BishopResult> bishop_search(const SlopeProfile& profile, const SoilStrength& soil,
                                          const BishopSearchSettings& settings) {
  const double h = std::max(profile.height, 1e-9);
  const double x_lo = profile.crest.x() - h, x_hi = profile.toe.x() + 0.5 * h;
  const double y_lo = profile.crest.y() - 0.25 * h, y_hi = profile.crest.y() + 2 * h;
  const double dx = (x_hi - x_lo) / std::max(settings.centres_x - 1, 1);
  const double dy = (y_hi - y_lo) / std::max(settings.centres_y - 1, 1);

  struct Candidate {
    BishopResult result;
    double radius_step;
  };
  std::vector<Candidate> found;
  for (int i = 0; i < settings.centres_x; ++i)
    for (int j = 0; j < settings.centres_y; ++j) {
      const Eigen::Vector2d centre(x_lo + i * dx, y_lo + j * dy);
      if (centre.y() <= surface_height(profile.surface, centre.x())) continue;
      const double r_touch = distance_to_polyline(centre, profile.surface);
      const double r_base = centre.y() - profile.base_y;
      if (!(r_base > r_touch)) continue;
      const double dr = (r_base - r_touch) / settings.radii;
      for (int k = 1; k <= settings.radii; ++k)
        if (auto result = bishop_factor_of_safety(profile, soil, {centre, r_touch + k * dr}, settings.slices))
          found.push_back({*result, dr});
    }
  if (found.empty()) return std::nullopt;
  const auto by_fos = [](const Candidate& a, const Candidate& b) {
    return a.result.factor_of_safety < b.result.factor_of_safety;
  };
  const std::size_t starts = std::min<std::size_t>(std::max(settings.refine_from, 0), found.size());
  std::partial_sort(found.begin(), found.begin() + std::max<std::size_t>(starts, 1), found.end(), by_fos);
  BishopResult best = found.front().result;

  // Compass search (Kolda, Lewis and Torczon 2003, SIAM Review 45(3)) in (xc, yc, R): try a step
  // along each axis both ways, take any improvement, halve the steps when none improves.
  for (std::size_t s = 0; s < starts; ++s) {
    BishopResult current = found[s].result;
    std::array<double, 3> step{dx, dy, found[s].radius_step};
    for (int evaluations = 0; evaluations < 4000 && *std::max_element(step.begin(), step.end()) > 1e-6 * h;) {
      bool improved = false;
      for (int axis = 0; axis < 3 && !improved; ++axis)
        for (double sign : {1.0, -1.0}) {
          Circle trial = current.circle;
          if (axis == 0) trial.centre.x() += sign * step[0];
          if (axis == 1) trial.centre.y() += sign * step[1];
          if (axis == 2) trial.radius += sign * step[2];
          ++evaluations;
          const auto result = bishop_factor_of_safety(profile, soil, trial, settings.slices);
          if (result && result->factor_of_safety < current.factor_of_safety) {
            current = *result;
            improved = true;
            break;
          }
        }
      if (!improved)
        for (double& value : step) value *= 0.5;
    }
    if (current.factor_of_safety < best.factor_of_safety) best = current;
  }
  return best;
}

}  // namespace talus::postproc
