// Limit-equilibrium cross-check: Bishop's simplified method of slices (Bishop 1955,
// Geotechnique 5(1):7-17) for circular slip surfaces, and a global search for the critical
// circle over circles set by their entry point, exit point and depth (bishop_search.cpp).
// The ground's weight, strength and pore pressure per slice come from a SliceModel
// (slice_model.hpp); SoilStrength is the homogeneous, dry case. Canonical frame: the slope
// descends towards +x.
#pragma once
#include <optional>

#include "postproc/circle_fit.hpp"
#include "postproc/slice_model.hpp"
#include "postproc/slope_geometry.hpp"

namespace talus::postproc {

// Where a slip circle leaves the ground, against the toe (within 1e-3 H): at the toe, on the
// face uphill of it, or beyond it (through a foundation layer, below the toe).
enum class CircleKind { Toe, Face, Base };
const char* to_string(CircleKind kind);  // "toe", "face", "base"

struct BishopResult {
  Circle circle;
  double factor_of_safety = 0;
  double x_entry = 0, x_exit = 0;  // where the circle cuts the ground surface (m), entry uphill
  double y_entry = 0, y_exit = 0;  // the ground's height there (m)
  CircleKind kind = CircleKind::Toe;
  // The arc's lowest point is on profile.base_y (within 1e-3 H) with a horizontal tangent there.
  bool tangent_to_base = false;
  long circles_evaluated = 1;  // by bishop_search: how many circles Bishop's method was run on
};

// Factor of safety of one circle by
//   F = sum[(c b + (W - u b) tan phi) / m_alpha] / [sum(W sin alpha) + sum(H (y_c - y_H)) / R],
//   m_alpha = cos alpha + sin alpha tan phi / F,
// iterated from the ordinary-method value until |dF| < 1e-9 F. Slices of equal width between
// the circle's entry and exit; alpha is the base inclination, positive where the base dips
// downhill. H is a slice's pseudo-static horizontal force towards the toe at height y_H
// (SliceForces::horizontal, zero without [seismic]; pseudo_static.hpp), y_c the centre's height. Empty when the circle is not admissible: it must cut the surface once, in two
// points inside the surface's x range (a circle through an end of the surface, such as a toe
// that is the body's corner, cuts it there), stay above profile.base_y, have a positive driving
// moment, and keep m_alpha > 0.2 on the slices whose base rises downhill (alpha < 0; Whitman
// and Bailey 1967, J. Soil Mech. Found. Div. 93(SM4): below that the simplified method's base
// normal forces blow up). Where alpha > 0, m_alpha >= cos alpha + sin alpha tan phi / F stays
// positive and a small value only means a steep, narrow slice near the crown.
std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SliceModel& ground,
                                                    const Circle& circle, int slices = 60);
std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SoilStrength& soil,
                                                    const Circle& circle, int slices = 60);

// The same for a circle already known to cut the ground exactly at x_entry < x_exit, with its
// arc below the ground in between and above the base (the search builds its circles so): no
// search for the cut, only the method's own conditions (driving moment, m_alpha).
std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SliceModel& ground,
                                                    const Circle& circle, double x_entry, double x_exit,
                                                    int slices = 60);

struct BishopSearchSettings {
  // Start grid over the family of circles: entries x exits x depths (see bishop_search).
  int entries = 16;
  int exits = 16;
  int depths = 12;
  int starts = 6;  // compass searches from this many of the grid's local minima; 0: grid only
  int slices = 60;
};

// The critical (least factor of safety) circle; empty when none is admissible. Each trial
// circle is admissible by construction: it enters the ground at x_a in [front, min(x_b, toe)),
// leaves it at x_b in [crest, back] and has the half-angle theta (its arc subtends 2 theta at
// the centre) between the shallowest arc that stays below the ground between them and out of
// it beyond them and the deepest that keeps both ends on the lower half of the circle and
// stays above the base.
// Exits beyond the toe (a foundation layer) go only as far as such an arc exists. A grid over
// (entry, exit, depth), entries and exits evenly along the ground, including exits at the toe
// and at the end of the surface and arcs tangent to the base, gives the starts; from each of
// its best local minima a compass search (Kolda, Lewis and Torczon 2003, SIAM Review 45(3)) in
// the same three parameters, steps clipped to their ranges so that the toe and the base are
// reached exactly; then again from the best circle until that gains nothing.
std::optional<BishopResult> bishop_search(const SlopeProfile& profile, const SliceModel& ground,
                                          const BishopSearchSettings& settings = {});
std::optional<BishopResult> bishop_search(const SlopeProfile& profile, const SoilStrength& soil,
                                          const BishopSearchSettings& settings = {});

// A result found in the canonical frame, in the scene's frame (x -> -x when the mirror is
// active): the centre and the entry and exit move; the entry stays the uphill end.
BishopResult mirrored(BishopResult result, const Mirror& mirror);

}  // namespace talus::postproc
