// Absorbing boundaries (Lysmer and Kuhlemeyer 1969, "Finite dynamic model for infinite media",
// J. Eng. Mech. Div. 95(EM4):859-877): viscous dashpots on the nodes of a boundary, the traction
// -rho c_p (v . n) n - rho c_s (v - (v . n) n) lumped as a nodal force over each node's share of
// the boundary's length (common/scene/seismic.hpp, AbsorbingNodes). With a compliant base the
// dashpots of the input boundaries act against the ground velocity instead, -rho c (v - v_g(t)),
// which puts in the outcrop motion v_g (twice the incident wave) and lets the wave going down
// out (Joyner and Chen 1975). docs/seismic.md.
//
// Dashpots carry no static load: a body under gravity on them alone would sink. So, as the
// static stage's reaction forces are kept as loads in the dynamic one: while gravity rises
// (t < run.gravity_ramp) the absorbing nodes are held fixed; at the first step from the end of
// the ramp on the dashpots come on, and the nodes carry from then on, besides the dashpots, the
// reactions that held them then as constant nodal forces. With no ramp that is the first step:
// the reactions of the initial state.
#pragma once
#include "common/scene/seismic.hpp"
#include "solver/interpolation/grid.hpp"
#include "solver/step/simulation.hpp"

namespace talus::solver {

// After the grid sums (P2G, the ranks' sums, the ghosts), before update_grid_accelerations.
// Before run.gravity_ramp: holds the absorbing nodes fixed (constraint kind Fixed; their own
// kinds kept in Simulation::absorbing_kind). From it on: gives them their kinds back, records the
// reactions once, R_i = -f_i per field with mass at the node (Simulation::absorbing_reaction; on
// several ranks the same on every rank), and adds them to f_i.
void apply_static_reactions(Simulation& sim);

// After update_grid_accelerations. At the step that recorded the reactions, first takes out of
// them the inertia of the model at that instant: -f_i also holds whatever the rest of the model
// was accelerating by (the ramp's elastic oscillation, say), and a resultant that differs from
// the static one by dF would push the whole body over the dashpots at dF / (sum C) for ever. The
// rest's momentum rate F = sum m_j a_j over the other nodes (their accelerations do not depend on
// the absorbing nodes') is spread over the reactions in proportion to the nodes' lengths,
// R_i -= w_i F, so that the reactions' resultant is the static load's wherever no other boundary
// holds the body. Then the dashpots' force, taken implicitly over the step (stable at any
// impedance): v_end = (m (v + dt a) + dt C v_ref) / (m + dt C) per component along the normal and
// the tangent, with C = length x impedance and v_ref = v_g(t + dt) on an input node (else 0); the
// acceleration becomes (v_end - v) / dt. Nodes without mass are left alone.
void apply_dashpots(Simulation& sim, double dt);

}  // namespace talus::solver
