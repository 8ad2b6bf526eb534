// The critical-circle search of bishop.hpp. Circles are set by where they enter and leave the
// ground and by the half-angle their arc subtends at the centre, over ranges that make every
// circle admissible (see bishop_search in bishop.hpp), so that the search never has to feel
// for the edge of the admissible set: a grid over the three parameters, then compass searches
// from its best local minima with their steps clipped to the ranges, then from the best again.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "postproc/bishop.hpp"

namespace talus::postproc {
namespace {

using Vec2 = Eigen::Vector2d;
using Params = std::array<double, 3>;  // entry u, exit v, depth t, each in [0, 1]

constexpr double kNarrowestEntry = 1e-3;  // the entry stops this fraction short of its range's end
constexpr double kShallowest = 1e-3;      // t below this would be the chord itself: no sliding mass
// The arc stops this much (rad) short of a vertical tangent at its higher end: there the cut of
// the circle with the ground is ill-conditioned (a rounding error in y_c - sqrt(R^2 - dx^2) is
// magnified to its square root), and another judge of the circle could see it otherwise.
constexpr double kVerticalMargin = 1e-5;

// The circle through a and b (a.x < b.x) whose arc below the chord subtends 2 * half_angle.
Circle circle_through(const Vec2& a, const Vec2& b, double half_angle) {
  const Vec2 chord = b - a;
  const double length = chord.norm();
  const Vec2 up(-chord.y() / length, chord.x() / length);
  return {0.5 * (a + b) + 0.5 * length / std::tan(half_angle) * up, 0.5 * length / std::sin(half_angle)};
}

struct HalfAngles {
  double lo = 0, hi = 0;
  bool empty() const { return !(hi > lo); }
};

// The inclination (rad) of the ground just left or just right of x.
double ground_inclination(const Polyline& surface, double x, bool right) {
  auto next = right ? std::upper_bound(surface.begin(), surface.end(), x,
                                       [](double value, const Vec2& p) { return value < p.x(); })
                    : std::lower_bound(surface.begin(), surface.end(), x,
                                       [](const Vec2& p, double value) { return p.x() < value; });
  next = std::clamp(next, surface.begin() + 1, surface.end() - 1);
  const Vec2 segment = *next - *(next - 1);
  return std::atan2(segment.y(), segment.x());
}

// True when the lower half of the circle, outside [a.x, b.x], is nowhere below the ground (by
// more than `touch`): it cuts the ground only between a and b. On each piece of a segment of
// the ground the arc's height above it is convex; its least value is at an end of the piece or
// where the arc is parallel to the segment.
bool only_cut_between(const Polyline& surface, const Circle& circle, double x_a, double x_b, double touch) {
  const double xc = circle.centre.x(), r = circle.radius;
  const std::array<std::pair<double, double>, 2> outside{{{xc - r, x_a}, {x_b, xc + r}}};
  for (std::size_t i = 0; i + 1 < surface.size(); ++i) {
    const Vec2 &p = surface[i], &q = surface[i + 1];
    const double m = (q.y() - p.y()) / (q.x() - p.x());
    auto gap = [&](double x) {
      const double dx = std::clamp(x - xc, -r, r);
      return circle.centre.y() - std::sqrt(r * r - dx * dx) - (p.y() + m * (x - p.x()));
    };
    for (const auto& [from, to] : outside) {
      const double lo = std::max(from, p.x()), hi = std::min(to, q.x());
      if (!(hi > lo)) continue;
      const double parallel = xc + r * m / std::sqrt(1 + m * m);
      if (gap(lo) < -touch || gap(hi) < -touch) return false;
      if (parallel > lo && parallel < hi && gap(parallel) < -touch) return false;
    }
  }
  return true;
}

// The half-angles of the admissible arcs from a to b. The arcs through two points are nested,
// deeper as the half-angle grows; along the arc from a to b the tangent turns from the chord's
// inclination - theta to the chord's inclination + theta. lo: the arc must pass below every
// corner of the ground that lies below the chord (by the inscribed angle, below the corner v
// once theta exceeds pi - angle(a v b)), and it must come out of the ground at both ends
// rather than touch it there and carry on inside: at b it must climb at least as steeply as
// the ground beyond b (through a toe into a foundation layer, its centre not beyond the toe),
// at a it must fall at least as steeply as the ground before a. There is no ground before the
// surface's first point or beyond its last. hi: both ends on the lower half of the circle (the
// tangent at the higher end turns vertical at pi/2 - the chord's inclination), and the lowest
// point above the base: once the centre is between a and b (half-angle above the chord's
// inclination), y_c - R >= base_y reads h sin(theta) + (dx/2) cos(theta) >= |ab|/2 with h the
// chord's mid-height above the base. Last, the circle beyond a and b must stay out of the
// ground (a circle leaving the face just above a toe must not dip into the foundation beyond
// it): outside the chord the arcs are ordered the other way, higher as theta grows, so this
// raises lo, by bisection when the bounds so far do not already meet it.
HalfAngles half_angles(const SlopeProfile& profile, const Vec2& a, const Vec2& b) {
  const Vec2 chord = b - a;
  const double chord_angle = std::atan2(chord.y(), chord.x());
  HalfAngles range;
  const Polyline& surface = profile.surface;
  if (b.x() < surface.back().x()) range.lo = std::max(range.lo, ground_inclination(surface, b.x(), true) - chord_angle);
  if (a.x() > surface.front().x()) range.lo = std::max(range.lo, chord_angle - ground_inclination(surface, a.x(), false));
  for (const Vec2& v : profile.surface) {
    if (!(v.x() > a.x() && v.x() < b.x())) continue;
    if (v.y() >= a.y() + chord.y() * (v.x() - a.x()) / chord.x()) continue;
    const Vec2 to_a = a - v, to_b = b - v;
    const double cosine = to_a.dot(to_b) / (to_a.norm() * to_b.norm());
    range.lo = std::max(range.lo, M_PI - std::acos(std::clamp(cosine, -1.0, 1.0)));
  }
  const double inclination = std::atan2(std::abs(chord.y()), chord.x());
  const double height = 0.5 * (a.y() + b.y()) - profile.base_y;
  const double reach = std::hypot(height, 0.5 * chord.x());
  const double base = std::atan2(height, 0.5 * chord.x()) + std::acos(std::min(0.5 * chord.norm() / reach, 1.0));
  range.hi = std::min(0.5 * M_PI - inclination - kVerticalMargin, std::max(base, inclination));
  if (range.empty()) return range;

  const double touch = 1e-9 * std::max(profile.height, 1.0);
  auto stays_out = [&](double theta) {
    return only_cut_between(surface, circle_through(a, b, theta), a.x(), b.x(), touch);
  };
  if (!stays_out(std::max(range.lo, 1e-9))) {
    if (!stays_out(range.hi)) return {1, 0};
    double bad = range.lo, good = range.hi;
    for (int i = 0; i < 50; ++i) {
      const double mid = 0.5 * (bad + good);
      (stays_out(mid) ? good : bad) = mid;
    }
    range.lo = good;
  }
  return range;
}

// Entries and exits are placed by length along the ground, so that a steep face gets as many
// of them as its length deserves (by x alone a cliff would get none).
class CircleFamily {
 public:
  explicit CircleFamily(const SlopeProfile& profile) : profile_(profile), length_{0.0} {
    const Polyline& surface = profile.surface;
    for (std::size_t i = 1; i < surface.size(); ++i) length_.push_back(length_.back() + (surface[i] - surface[i - 1]).norm());
    back_ = length_.back();
    crest_ = length_at(profile.crest.x());
    toe_ = length_at(profile.toe.x());
    toe_share_ = back_ > toe_ ? (toe_ - crest_) / (back_ - crest_) : 1.0;
  }

  struct Member {
    Circle circle;
    double x_entry, x_exit;
  };

  // The exit parameter of the toe: exits uphill of it below, beyond it above.
  double toe_share() const { return toe_share_; }

  // The circle of the parameters, or empty in the degenerate corners of the family (which the
  // ranges make rare: an entry on top of its exit, a ground without room below the toe).
  std::optional<Member> operator()(const Params& p) const {
    double exit = 0, entry = 0;  // lengths along the ground
    if (p[1] <= toe_share_) {
      exit = p[1] == toe_share_ ? toe_ : crest_ + (toe_ - crest_) * p[1] / toe_share_;
      entry = entry_at(p[0], exit);
    } else {
      entry = entry_at(p[0], toe_);
      exit = std::min(toe_ + (farthest_exit(entry) - toe_) * (p[1] - toe_share_) / (1 - toe_share_), back_);
    }
    const Vec2 a = point(entry), b = point(exit);
    if (!(b.x() > a.x())) return std::nullopt;
    const HalfAngles range = half_angles(profile_, a, b);
    if (range.empty()) return std::nullopt;
    const double t = std::max(p[2], kShallowest);
    return Member{circle_through(a, b, range.lo + t * (range.hi - range.lo)), a.x(), b.x()};
  }

 private:
  // The point of the ground at `length` along it from its first point; a vertex exactly.
  Vec2 point(double length) const {
    const Polyline& surface = profile_.surface;
    if (length >= back_) return surface.back();
    const std::size_t i = std::upper_bound(length_.begin(), length_.end(), length) - length_.begin() - 1;
    return surface[i] + (length - length_[i]) / (length_[i + 1] - length_[i]) * (surface[i + 1] - surface[i]);
  }
  double length_at(double x) const {
    const Polyline& surface = profile_.surface;
    std::size_t i = 0;
    while (i + 2 < surface.size() && surface[i + 1].x() <= x) ++i;
    return length_[i] + (x - surface[i].x()) / (surface[i + 1].x() - surface[i].x()) * (length_[i + 1] - length_[i]);
  }
  double entry_at(double u, double limit) const { return u * (1 - kNarrowestEntry) * limit; }

  // Beyond the toe the arc must pass below it, and further exits need deeper arcs: the last
  // exit for which an arc from the entry still clears the toe above the base, by bisection.
  double farthest_exit(double entry) const {
    const Vec2 a = point(entry);
    if (!half_angles(profile_, a, point(back_)).empty()) return back_;
    double good = toe_, bad = back_;
    for (int i = 0; i < 50; ++i) {
      const double mid = 0.5 * (good + bad);
      (half_angles(profile_, a, point(mid)).empty() ? bad : good) = mid;
    }
    return good;
  }

  const SlopeProfile& profile_;
  std::vector<double> length_;  // along the ground to each of its points (m)
  double back_ = 0, crest_ = 0, toe_ = 0, toe_share_ = 1;
};

class Search {
 public:
  Search(const SlopeProfile& profile, const SliceModel& ground, int slices)
      : profile_(profile), ground_(ground), family_(profile), slices_(slices) {}

  // The factor of safety of the parameters' circle (infinite when it has none); keeps the best.
  double evaluate(const Params& p) {
    const auto member = family_(p);
    if (!member) return INFINITY;
    ++evaluated_;
    const auto result =
        bishop_factor_of_safety(profile_, ground_, member->circle, member->x_entry, member->x_exit, slices_);
    if (!result) return INFINITY;
    if (!found_ || result->factor_of_safety < best_.factor_of_safety) {
      best_ = *result;
      best_params_ = p;
    }
    found_ = true;
    return result->factor_of_safety;
  }

  // From p: try each parameter one step up and down (clipped to its range), move on the first
  // improvement, halve the steps when none improves, until they are below `smallest`.
  void compass(Params p, double value, Params step, double smallest, int budget) {
    const Params lower{0.0, 0.0, kShallowest};
    while (budget > 0 && *std::max_element(step.begin(), step.end()) > smallest) {
      bool improved = false;
      for (int axis = 0; axis < 3 && !improved; ++axis)
        for (double sign : {1.0, -1.0}) {
          Params trial = p;
          trial[axis] = std::clamp(p[axis] + sign * step[axis], lower[axis], 1.0);
          if (trial[axis] == p[axis]) continue;
          --budget;
          const double f = evaluate(trial);
          if (f < value) {
            p = trial;
            value = f;
            improved = true;
            break;
          }
        }
      if (!improved)
        for (double& s : step) s *= 0.5;
    }
  }

  const CircleFamily& family() const { return family_; }
  bool found() const { return found_; }
  const BishopResult& best() const { return best_; }
  const Params& best_params() const { return best_params_; }
  long evaluated() const { return evaluated_; }

 private:
  const SlopeProfile& profile_;
  const SliceModel& ground_;
  CircleFamily family_;
  int slices_;
  BishopResult best_;
  Params best_params_{};
  bool found_ = false;
  long evaluated_ = 0;
};

}  // namespace

std::optional<BishopResult> bishop_search(const SlopeProfile& profile, const SliceModel& ground,
                                          const BishopSearchSettings& settings) {
  const int nu = std::max(settings.entries, 2), nv = std::max(settings.exits, 2), nt = std::max(settings.depths, 1);
  Search search(profile, ground, settings.slices);

  // The grid: entries and exits from one end of their ranges to the other (the last exit is the
  // end of the surface, the toe when the body ends there; with a foundation layer, the exit
  // nearest the toe is moved onto it), depths from 1/nt to the deepest.
  std::vector<double> exits(nv);
  for (int j = 0; j < nv; ++j) exits[j] = double(j) / (nv - 1);
  const double toe = search.family().toe_share();
  *std::min_element(exits.begin(), exits.end(),
                    [&](double x, double y) { return std::abs(x - toe) < std::abs(y - toe); }) = toe;
  std::vector<double> grid(static_cast<std::size_t>(nu) * nv * nt);
  auto at = [&](int i, int j, int k) -> double& { return grid[(static_cast<std::size_t>(i) * nv + j) * nt + k]; };
  auto params = [&](int i, int j, int k) { return Params{double(i) / (nu - 1), exits[j], double(k + 1) / nt}; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
      for (int k = 0; k < nt; ++k) at(i, j, k) = search.evaluate(params(i, j, k));
  if (!search.found()) return std::nullopt;

  // The starts: grid points no worse than any of their (up to 26) neighbours, best first.
  struct Start {
    double value;
    int i, j, k;
  };
  std::vector<Start> minima;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
      for (int k = 0; k < nt; ++k) {
        const double value = at(i, j, k);
        bool lowest = std::isfinite(value);
        for (int di = -1; di <= 1 && lowest; ++di)
          for (int dj = -1; dj <= 1 && lowest; ++dj)
            for (int dk = -1; dk <= 1 && lowest; ++dk) {
              const int a = i + di, b = j + dj, c = k + dk;
              if (a < 0 || a >= nu || b < 0 || b >= nv || c < 0 || c >= nt) continue;
              if (at(a, b, c) < value) lowest = false;
            }
        if (lowest) minima.push_back({value, i, j, k});
      }
  std::sort(minima.begin(), minima.end(), [](const Start& x, const Start& y) { return x.value < y.value; });
  const Params step{1.0 / (nu - 1), 1.0 / (nv - 1), 1.0 / nt};
  for (std::size_t s = 0; s < std::min<std::size_t>(std::max(settings.starts, 0), minima.size()); ++s)
    search.compass(params(minima[s].i, minima[s].j, minima[s].k), minima[s].value, step, 1e-7, 4000);
  // A compass search can stop at a kink of F (where the exit passes the toe, say) short of the
  // minimum: from the best circle, with the first steps again, until that gains nothing more.
  for (int restart = 0; restart < 5 && settings.starts > 0; ++restart) {
    const double before = search.best().factor_of_safety;
    search.compass(search.best_params(), before, step, 1e-7, 4000);
    if (!(search.best().factor_of_safety < before * (1 - 1e-9))) break;
  }

  BishopResult best = search.best();
  best.circles_evaluated = search.evaluated();
  return best;
}

}  // namespace talus::postproc
