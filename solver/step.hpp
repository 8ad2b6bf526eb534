// The explicit MUSL step (seed, appendix A; design.md, "The explicit step") and its phases.
// Each phase is a free function over the data it names, one loop a reader can check against
// the cited equation; `step()` calls them in order, contact included.
#pragma once
#include <vector>

#include "solver/simulation.hpp"

namespace talus::solver {

// One step of length dt. Returns false when a particle left the domain or a state became
// non-finite (Scratch::lost_particle / bad_particle say which).
bool step(Simulation& sim, double dt);

// ---- The phases, in the order step() runs them -----------------------------------------------

// Marks the nodes of every particle's stencil and lists them, ascending, in grids.active.
void mark_active_nodes(const Stencil& stencil, std::size_t particles, std::vector<int32_t>& node_stamp,
                       int32_t& stamp, Grids& grids, int threads);

// (A.6)-(A.8): mass, momentum and force of each velocity field at the active nodes; with
// contact also the mass gradients. Particles of fixed bodies lend their mass (and normals) only.
void particles_to_grid(const Particles& P, const Stencil& stencil, const Vec2& gravity, Grids& grids,
                       ThreadBuffers& buffers, int threads);

// Nodal accelerations a_i = f_i / m_i with local damping, such that the end-of-step velocity
// satisfies the constraints. A fixed body's field does not move.
void update_grid_accelerations(const Constraints& constraints, const std::vector<uint8_t>& body_fixed,
                               double damping, double dt, Grids& grids, int threads);

// (A.10): v_p += dt sum N_ip a_i, and the momentum for the remap scattered in the same pass.
void update_particle_velocities(Particles& P, const Stencil& stencil, double dt, const Grids& grids,
                                ThreadBuffers& buffers, int threads);

// (A.11): v_i = sum N_ip m_p v_p / m_i, constrained.
void remap_grid_velocities(const Constraints& constraints, const std::vector<uint8_t>& body_fixed, Grids& grids,
                           ThreadBuffers& buffers, int threads);

// (A.12): x_p += dt sum N_ip v_i; the strain increment d_eps and the Jaumann rotation of the
// stress from the velocity gradient; the PIC blend of the particle velocity.
void update_particle_kinematics(Particles& P, const Stencil& stencil, const Grids& grids, double pic_fraction,
                                double dt, std::vector<Vec4>& d_eps, int threads);

// Detournay and Dzik (2006): replaces the volumetric part of each d_eps by its cell average
// smoothed over the nodes (evs.cpp).
void enhance_volumetric_strain(const Mesh& mesh, const Particles& P, const Stencil& stencil,
                               const std::vector<int32_t>& active, EvsScratch& evs, std::vector<Vec4>& d_eps,
                               int threads);

// The materials' stress update and the volume update V_p *= 1 + tr d_eps. Returns the first
// particle whose state became non-finite or inverted, or -1.
long update_stresses(Particles& P, const std::vector<Vec4>& d_eps, const std::vector<MaterialState>& materials,
                     const std::vector<int32_t>& material_of_body, int threads);

// Finds each moving particle's element (neighbour walk) and recomputes its stencil row.
// Returns the first particle that left the domain, or -1.
long relocate_particles(const Mesh& mesh, Particles& P, Stencil& stencil, int threads);

// ---- Frictional contact (contact.cpp) -------------------------------------------------------
// Bardenhagen et al. (2000), seed appendix B: at nodes where more than one body has mass and
// their particles touch (docs/contact.md, "Detection"), approach is removed along the normal
// and the tangential part follows Coulomb stick or slip.
// A fixed body is rigid: the reference velocity at a node it touches is zero. After the
// correction each node's constraints hold again (a body pushed along a roller wall by contact
// still does not cross it).

struct ContactRules {
  const std::vector<std::vector<double>>& pair_friction;
  const std::vector<uint8_t>& body_fixed;
  const Constraints& constraints;
};

// Lists (ascending) in `contact_nodes` the nodes where 2+ bodies have mass and their particles
// touch along the contact normal, and records which bodies take part at each.
void find_contact_nodes(const ContactRules& rules, const Particles& particles, const Stencil& stencil, Grids& grids,
                        std::vector<int32_t>& contact_nodes, int threads);

// Corrects the end-of-step trial velocities through the accelerations, so that (A.10) sees it.
void apply_contact(const ContactRules& rules, double dt, const std::vector<int32_t>& contact_nodes, Grids& grids,
                   int threads);

// Corrects the remapped velocities (A.11).
void apply_contact_velocities(const ContactRules& rules, const std::vector<int32_t>& contact_nodes, Grids& grids,
                              int threads);

}  // namespace talus::solver
