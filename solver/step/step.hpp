// The explicit MUSL step (seed, appendix A; design.md, "The explicit step"): step() advances a
// Simulation (simulation.hpp) by dt. step.cpp is the recipe, the phases in order with the
// equations each carries out; the phases themselves live by concern: solver/interpolation
// (the transfers, EVS, relocation), solver/contact, solver/stress. The time loop that takes the
// CFL step and calls step() with its observers is time_loop.hpp.
#pragma once
#include "solver/step/simulation.hpp"
#include "solver/step/time_loop.hpp"

namespace talus::solver {

// One step of length dt. Returns false when a particle left the domain or a state became
// non-finite (Scratch::lost_particle / bad_particle say which).
bool step(Simulation& sim, double dt);

}  // namespace talus::solver
