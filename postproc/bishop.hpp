// Limit-equilibrium cross-check: Bishop's simplified method of slices (Bishop 1955,
// Geotechnique 5(1):7-17) for circular slip surfaces in a homogeneous, dry slope, and a search
// for the critical circle (grid of centres x range of radii, then a compass search from the
// best grid circles). Canonical frame: the slope descends towards +x.
#pragma once
#include <optional>

#include "postproc/circle_fit.hpp"
#include "postproc/slope_geometry.hpp"

namespace talus::postproc {

struct SoilStrength {
  double cohesion = 0;        // c' (Pa, or any unit consistent with unit_weight x length)
  double friction_angle = 0;  // phi' (deg)
  double unit_weight = 0;     // gamma = rho g (N/m^3)
};

struct BishopResult {
  Circle circle;
  double factor_of_safety = 0;
  double x_entry = 0, x_exit = 0;  // where the circle cuts the ground surface (m), entry uphill
};

// Factor of safety of one circle by
//   F = sum[(c b + W tan phi) / m_alpha] / sum(W sin alpha),  m_alpha = cos alpha + sin alpha tan phi / F,
// iterated from the ordinary-method value until |dF| < 1e-9. Slices of equal width between the
// circle's entry and exit; alpha is the base inclination, positive where the base dips
// downhill. Empty when the circle is not admissible: it must cut the surface once, in two
// points inside the surface's x range, stay above profile.base_y, have a positive driving
// moment, and keep m_alpha > 0.2 on the slices whose base rises downhill (alpha < 0; Whitman
// and Bailey 1967, J. Soil Mech. Found. Div. 93(SM4): below that the simplified method's base
// normal forces blow up). Where alpha > 0, m_alpha >= cos alpha + sin alpha tan phi / F stays
// positive and a small value only means a steep, narrow slice near the crown.
std::optional<BishopResult> bishop_factor_of_safety(const SlopeProfile& profile, const SoilStrength& soil,
                                                    const Circle& circle, int slices = 60);

struct BishopSearchSettings {
  // Centres on a grid over x in [crest.x - H, toe.x + H/2], y in [crest.y - H/4, crest.y + 2H];
  // for each centre, radii from just cutting the surface to tangent to the base.
  int centres_x = 24;
  int centres_y = 24;
  int radii = 24;
  int refine_from = 4;  // compass search from this many of the best grid circles; 0: grid only
  int slices = 60;
};

// The critical (least factor of safety) admissible circle; empty when none is admissible.
std::optional<BishopResult> bishop_search(const SlopeProfile& profile, const SoilStrength& soil,
                                          const BishopSearchSettings& settings = {});

}  // namespace talus::postproc
