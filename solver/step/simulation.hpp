// One MPM run in memory: what the step reads but never changes (Config), the state it
// advances (the particles, the time and the step count), and the scratch it reuses (Scratch).
// `step()` (step.hpp) is the recipe over them; the time loop (time_loop.hpp) drives it.
#pragma once
#include <vector>

#include "common/model/model.hpp"
#include "solver/boundary/boundary.hpp"
#include "solver/contact/contact.hpp"
#include "solver/interpolation/interpolation.hpp"
#include "solver/parallel/domain_state.hpp"
#include "solver/step/particles.hpp"
#include "solver/stress/material_state.hpp"

namespace talus::solver {

// Set up once from the model; read-only while stepping. (The strength-reduction workflow
// changes materials, damping and the gravity ramp between runs, never within a step; the
// absorbing nodes' constraint kinds are Fixed until the end of the gravity ramp, absorbing.hpp.)
struct Config {
  Mesh mesh;
  Constraints constraints;
  std::vector<MaterialState> materials;
  std::vector<int32_t> material_of_body;
  std::vector<uint8_t> body_fixed;
  // Frictional contact between the groups of bonded bodies (a velocity field per group,
  // Grids::field_index); off for one body, or when the scene bonds all bodies into one field.
  bool contact = false;
  std::vector<std::vector<double>> pair_friction;  // [field][field], Coulomb coefficient
  std::vector<uint8_t> field_fixed;                // [field]: a fixed body's (contact only)
  std::vector<double> node_length;                 // [node], m: ContactRules::node_length

  Vec2 gravity{0, -9.81};    // full gravity (m/s^2)
  double gravity_ramp = 0;   // s; see RunSettings::gravity_ramp
  double damping = 0;        // local (Cundall) damping coefficient
  Transfer transfer = Transfer::Flip;  // grid to particle velocity update (docs/transfer.md)
  double pic_fraction = 0;   // PicBlend only: share of the grid velocity in the particle velocity
  int xpic_order = 1;        // Xpic only: m
  bool evs = false;          // enhanced volumetric strain
  // Mixed integration of the internal force (docs/transfer.md, "Mixed integration"): 0 off; else
  // a cell is integrated as full where it and each cell across its edges are filled to this share.
  double full_cell_fill = 0;
  std::vector<double> initial_volume;  // m^2, by particle id: the cap on its growth (step.hpp)
  WaterSettings water;       // the water table (water.enabled(): pore pressures, pore_pressure.cpp)
  // Surface loads: per load, the time over which it rises (s, as gravity_ramp). The particles
  // carry the forces (Particles::load, load_force).
  std::vector<double> load_ramp;

  int threads = 1;  // every parallel region runs this many threads (parallel.hpp)

  // [base_motion]: the ground's acceleration; on a rigid base the model is solved in the ground's
  // frame, so every particle feels -a_g(t) besides gravity (ground_moves; common/scene/seismic.hpp),
  // on a compliant base the absorbing boundaries put the motion in. Off: no cost in the step.
  BaseMotion base_motion;
  bool ground_moves = false;
  AbsorbingNodes absorbing;  // dashpots (solver/boundary/absorbing.hpp); empty: none
};

// Wall time per phase of step(), summed over the steps: opt-in (Scratch::phase_times, set by
// the throughput benchmark); when it is null step() reads no clock.
struct PhaseTimes {
  enum Phase {
    Mark, ToGrid, GridAcceleration, Contact, GridVelocity, ParticleVelocity, Remap, Kinematics, CellSums, Stresses,
    Relocate, Count
  };
  static constexpr const char* kNames[Count] = {
      "mark_active_nodes",          "particles_to_grid", "update_grid_accelerations", "contact",
      "lagrangian/xpic velocities", "update_particle_velocities", "remap_grid_velocities",
      "update_particle_kinematics", "sum_cells",                  "update_stresses",
      "relocate_particles"};
  double seconds[Count] = {};
  long steps = 0;
};

// Reused every step; nothing in it carries over from one step to the next except the
// stencil, which always matches the particles' current positions.
struct Scratch {
  Stencil stencil;
  Grids grids;
  ThreadBuffers buffers;             // [thread][field]
  std::vector<int32_t> node_stamp;   // == stamp: node active this step
  int32_t stamp = 0;
  std::vector<Vec4> d_eps;           // this step's strain increment per particle
  std::vector<int32_t> element_count;  // particles per element this step (sum_cells)
  EvsScratch evs;
  // Mixed integration only: per thread, the particle volume of each element; then per element
  // the factor on its particles' V sigma in (A.8) (full_cell_scales).
  std::vector<std::vector<double>> cell_volume;
  std::vector<double> cell_scale;
  ContactScratch contact;             // contact only: this step's contact nodes (contact.hpp)
  std::vector<double> load_factor;     // this step's ramp factor per surface load
  // Set by the time loop when an observer wants this step's grid velocity at the particles (a
  // frame): the step then fills Particles::step_velocity before it moves on to the next stencil.
  bool keep_step_velocity = false;
  PhaseTimes* phase_times = nullptr;   // not owned; null: no timing
  // Problems found inside parallel loops, reported after them (-1: none).
  long bad_particle = -1;   // a particle with a non-finite state (the largest index)
  long lost_particle = -1;  // a particle that left the domain (the largest index)
  bool failed_elsewhere = false;  // on several ranks: the step failed on another rank
  // Absorbing boundaries, at the step that records their static reactions (absorbing.hpp): each
  // reaction's share of the model's momentum rate (its node's length; 0 without mass), and that
  // the share is still to be taken out.
  std::vector<double> absorbing_weight;
  bool absorbing_balance = false;
};

struct Simulation {
  Config config;
  Particles particles;
  double time = 0;  // s
  long steps = 0;
  long reorders = 0;  // times the particles were re-ordered (indices change then)
  Scratch scratch;
  Domain domain;  // this rank's share of a run on several MPI ranks (domain.hpp); one rank: empty
  // Absorbing boundaries (solver/boundary/absorbing.hpp). Their static reactions, per field and
  // absorbing node (field-major), recorded when the dashpots come on at the end of
  // run.gravity_ramp and applied from then on (checkpointed); empty before.
  std::vector<Vec2> absorbing_reaction;
  // While gravity rises the absorbing nodes are held fixed: their own constraint kinds, kept
  // here to be given back at the switch (empty: not held).
  std::vector<Constraint> absorbing_kind;
};

// Builds the simulation from a model: mesh geometry, constraints, materials, particles sorted
// by element, the stencil, and buffers sized for `threads` threads (at least 1).
Simulation make_simulation(const Model& model, int threads);
// The same from a model its owner gives up: the particle columns move into the simulation
// instead of being copied, and the model keeps none (release_particles), so that a large
// model and its simulation are never both in memory. Its mesh, bodies and settings stay.
Simulation make_simulation(Model&& model, int threads);
// Frees the model's per-particle columns (particle_count() becomes 0).
void release_particles(Model& model);

// Re-sizes the per-thread buffers for another thread count (a copied simulation run on one
// core, say). The physics is unchanged; sums may round differently.
void set_threads(Simulation& sim, int threads);

// Orders particles by (fixed body last, element) for memory locality, and recomputes the
// stencil rows in the new order.
void sort_particles(Simulation& sim);

// Gravity at time t, with the smooth ramp of RunSettings::gravity_ramp; with a moving ground, less
// the ground's acceleration (the body force of the ground's frame).
inline Vec2 gravity_at(const Config& config, double t) {
  Vec2 g = t >= config.gravity_ramp ? config.gravity : Vec2(ramp_factor(t, config.gravity_ramp) * config.gravity);
  if (config.ground_moves) g -= config.base_motion.ground_acceleration(t);
  return g;
}


struct Energies {
  double kinetic = 0;       // of the particle (FLIP) velocities, J per m thickness
  double potential = 0;     // -sum m_p g . x_p
  double strain = 0;        // elastic strain energy
  double grid_kinetic = 0;  // of the grid velocity field, the one that moves the material (A.12)
};
Energies energies(const Simulation& sim);

// The grid velocity at each particle, sum N_ip v_i with the last step's remapped velocities and
// stencil: the velocity that moved it (A.12), free of the FLIP components the grid cannot see.
// Particles::step_velocity when the step kept it; else (a run stopped between frames) the same
// sum with the stencil of the particle's new element, which on several ranks may reach nodes its
// rank did not sum in that step.
std::vector<Vec2> grid_velocity_at_particles(const Simulation& sim);
// The same at the solver's particle p alone (the results writer's frames, a block at a time).
Vec2 grid_velocity_at_particle(const Simulation& sim, std::size_t p);
// Fills Particles::step_velocity from the step's grid and stencil (step, before relocation).
void keep_step_velocities(Simulation& sim);

}  // namespace talus::solver
