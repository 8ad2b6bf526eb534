// Boundary conditions and loads, what the step takes from the scene besides the particles:
// the per-node velocity constraints of the .geo's boundaries (fixed, roller, Coulomb friction),
// applied to nodal velocities and accelerations, and the smooth ramps by which gravity and the
// surface loads rise. A new boundary-condition kind is a Constraint value, its line in
// build_constraints and its case in constrain (docs/architecture.md).
#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

#include "common/model/model.hpp"

namespace talus::solver {

using Vec2 = Eigen::Vector2d;

// Per-node boundary constraints on the velocity.
enum class Constraint : uint8_t { Free = 0, Fixed = 1, Roller = 2, Friction = 3 };

struct Constraints {
  std::vector<Constraint> kind;
  // Roller: unit normal, the velocity along it is zero. Friction: the outward unit normal.
  std::vector<Vec2> normal;
  std::vector<double> friction;  // Coulomb coefficient of a friction node, else 0
};

Constraints build_constraints(const Model& model);

// Brings node i's velocity (or acceleration) to what its constraint allows. Fixed: zero.
// Roller: no component along the normal. Friction (Coulomb, unilateral): a velocity into the
// boundary, v.n > 0 with n outward, loses that component, and its tangential part is reduced
// by at most mu (v.n), to zero if smaller; a velocity away from the boundary is left free.
// Applied to the end-of-step velocity this is the impulse of a normal force and its Coulomb
// friction over the step: a block on an incline slides at g (sin theta - mu cos theta).
inline void constrain(const Constraints& c, int32_t i, Vec2& value) {
  const Constraint kind = c.kind[i];
  if (kind == Constraint::Fixed) value.setZero();
  else if (kind == Constraint::Roller) value -= value.dot(c.normal[i]) * c.normal[i];
  else if (kind == Constraint::Friction) {
    const double into = value.dot(c.normal[i]);
    if (into <= 0) return;
    value -= into * c.normal[i];
    const double slip = value.norm();
    const double resisted = c.friction[i] * into;
    if (slip <= resisted) value.setZero();
    else value *= 1 - resisted / slip;
  }
}

// Strips from a correction `delta` of node i's velocity (contact) what would break its
// constraint, for a velocity that already obeys it: fixed, nothing; roller and friction, the
// component along the normal (friction is not applied to a correction).
inline void constrain_change(const Constraints& c, int32_t i, Vec2& delta) {
  if (c.kind[i] == Constraint::Fixed) delta.setZero();
  else if (c.kind[i] != Constraint::Free) delta -= delta.dot(c.normal[i]) * c.normal[i];
}

// The smooth ramp (1 - cos(pi t / T)) / 2 up to T, then 1 (T = 0: 1 from t = 0): gravity's
// (RunSettings::gravity_ramp), the surface loads' and the water table's pore pressures'.
inline double ramp_factor(double t, double T) {
  if (t >= T) return 1;
  return 0.5 * (1 - std::cos(M_PI * t / T));
}

// Each surface load's ramp factor at time t, into `factors` (one per load ramp).
inline void load_factors(const std::vector<double>& ramps, double t, std::vector<double>& factors) {
  factors.resize(ramps.size());
  for (std::size_t L = 0; L < factors.size(); ++L) factors[L] = ramp_factor(t, ramps[L]);
}

}  // namespace talus::solver
