// The state of one MPM run and the explicit MUSL step over it (seed, appendix A; design.md,
// "The explicit step"). `step()` reads as the recipe: each phase is one free function with
// explicit inputs, one loop a reader can check against the cited equation.
#pragma once
#include <vector>

#include "common/model.hpp"
#include "solver/material.hpp"
#include "solver/state.hpp"

namespace talus::solver {

// Per-thread scatter targets for one velocity field, so that P2G needs no locks.
struct NodeBuffer {
  std::vector<double> m;
  std::vector<Vec2> p, f, mass_gradient;
};

struct Simulation {
  Mesh mesh;
  Constraints constraints;
  Particles particles;

  // Velocity fields: one for the whole system, plus one per body when the contact pass runs
  // (then fields[1 + b] belongs to body b and fields[0] is the centre of mass).
  std::vector<Grid> fields;
  bool contact = false;
  std::vector<std::vector<double>> pair_friction;  // [body][body], Coulomb coefficient
  std::vector<int32_t> contact_nodes;  // this step's nodes where 2+ bodies have mass

  std::vector<int32_t> material_of_body;
  std::vector<uint8_t> body_fixed;
  std::vector<MaterialState> materials;

  Vec2 gravity{0, -9.81};       // full gravity
  double gravity_ramp = 0;      // s; see RunSettings::gravity_ramp
  double damping = 0;  // local (Cundall) damping coefficient
  double pic_fraction = 0;  // share of the grid velocity in the particle velocity (0: FLIP)
  bool evs = false;

  double time = 0;
  long steps = 0;

  // Scratch, sized once.
  std::vector<std::vector<NodeBuffer>> buffers;  // [thread][field]
  std::vector<int32_t> node_stamp;               // == stamp: node active this step
  int32_t stamp = 0;
  std::vector<double> element_strain, element_volume, node_strain, node_area;  // EVS

  // Problems found inside parallel loops, reported after them.
  long bad_particle = -1;     // first particle with a non-finite state
  long lost_particle = -1;    // first particle that left the domain
};

// Builds the simulation from a model: mesh geometry, constraints, particles sorted by element,
// fields and scratch sized for `threads` threads.
Simulation make_simulation(const Model& model, int threads);

// Gravity at time t, with the smooth ramp of RunSettings::gravity_ramp.
Vec2 gravity_at(const Simulation& sim, double t);

// The CFL step (A.13): dt = cfl h_min / (c_d + max |v_p|).
double stable_time_step(const Simulation& sim, double cfl);

// One explicit MUSL step of length dt. Returns false when a particle left the domain or a
// state became non-finite (see Simulation::lost_particle / bad_particle).
bool step(Simulation& sim, double dt);

// Phases of the step, exposed for tests.
void mark_active_nodes(Simulation& sim);
void particles_to_grid(Simulation& sim);                // (A.6)-(A.8)
void update_grid_accelerations(Simulation& sim, double dt);
void update_particle_velocities(Simulation& sim, double dt);  // (A.10), then momentum for (A.11)
void remap_grid_velocities(Simulation& sim);            // (A.11)
void update_particle_kinematics(Simulation& sim, double dt);  // (A.12), strain increment, spin
void enhance_volumetric_strain(Simulation& sim);        // Detournay and Dzik (2006)
void update_stresses(Simulation& sim);
bool relocate_particles(Simulation& sim);

// Frictional contact (Bardenhagen et al. 2000; seed appendix B) between the body fields at
// nodes where more than one body has mass: approach is removed in the normal direction, the
// tangential part follows Coulomb stick or slip. A fixed body is rigid: the reference velocity
// at a node it touches is zero. The first corrects the end-of-step trial velocity through the
// accelerations (so (A.10) sees it), the second the remapped velocities (A.11).
// apply_contact first lists the contact nodes (Simulation::contact_nodes); both then visit only
// those, so bodies that share no node cost one pass over the active nodes' masses.
void find_contact_nodes(Simulation& sim);
void apply_contact(Simulation& sim, double dt);
void apply_contact_velocities(Simulation& sim);

// Orders particles by (fixed body last, element) for memory locality.
void sort_particles(Simulation& sim);

struct Energies {
  double kinetic = 0;       // of the particle (FLIP) velocities, J per m thickness
  double potential = 0;     // -sum m_p g . x_p
  double strain = 0;        // elastic strain energy
  double grid_kinetic = 0;  // of the grid velocity field, the one that moves the material (A.12)
};
Energies energies(const Simulation& sim);

// The grid velocity at each particle, sum N_i v_i with the last step's remapped velocities: the
// velocity that moves it (A.12), free of the FLIP components that the grid cannot see.
std::vector<Vec2> grid_velocity_at_particles(const Simulation& sim);

}  // namespace talus::solver
