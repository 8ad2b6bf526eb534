// Absorbing boundaries (Lysmer and Kuhlemeyer 1969, "Finite dynamic model for infinite media",
// J. Eng. Mech. Div. 95(EM4):859-877): viscous dashpots on the nodes of a boundary, the traction
// -rho c_p (v . n) n - rho c_s (v - (v . n) n) lumped as a nodal force over each node's share of
// the boundary's length (common/scene/seismic.hpp, AbsorbingNodes). With a compliant base the
// dashpots of the input boundaries act against the ground velocity instead, -rho c (v - v_g(t)),
// which puts in the outcrop motion v_g (twice the incident wave) and lets the wave going down
// out (Joyner and Chen 1975). docs/seismic.md.
#pragma once
#include "common/scene/seismic.hpp"
#include "solver/interpolation/grid.hpp"

namespace talus::solver {

// After update_grid_accelerations: the dashpots' force taken implicitly over the step (stable at
// any impedance), v_end = (m (v + dt a) + dt C v_ref) / (m + dt C) per component along the normal
// and the tangent, with C = length x impedance and v_ref = v_g(t + dt) on an input node (else 0);
// the acceleration becomes (v_end - v) / dt. Nodes without mass are left alone.
void apply_dashpots(const AbsorbingNodes& dashpots, const BaseMotion& motion, double t, double dt, Grids& grids);

}  // namespace talus::solver
