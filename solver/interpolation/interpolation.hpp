// Interpolation between the particles and the background grid: the mesh, the stencil that each
// shape-function family fills, the grid's fields, and the step's phases that move mass,
// momentum and force to the nodes and velocities back to the particles (seed, appendix A). Each
// phase is one loop over the particles or the active nodes, to be checked against the equation
// it cites; step() (solver/step/step.cpp) calls them in order.
#pragma once
#include <functional>
#include <vector>

#include "common/scene/scene.hpp"
#include "solver/boundary/boundary.hpp"
#include "solver/interpolation/grid.hpp"
#include "solver/interpolation/mesh.hpp"
#include "solver/interpolation/stencil.hpp"
#include "solver/step/particles.hpp"

namespace talus::solver {

// ---- The stencil: a shape-function family per scene (run.shape_functions) -------------------

// Sizes the stencil for `particles` particles of the family on `mesh` (and fills the shared
// tables where the family has them).
void reset_stencil(Stencil& stencil, ShapeFamily family, const Mesh& mesh, std::size_t particles);
// Sizes the per-particle tables for `particles` particles (after a migration), keeping the rest.
void resize_rows(Stencil& stencil, std::size_t particles);
// Fills the entries of particles [begin, end) from their positions and elements.
void compute_stencil(const Mesh& mesh, const Particles& particles, std::size_t begin, std::size_t end,
                     Stencil& stencil, int threads = 1);

// ---- The phases, in the order step() runs them ------------------------------------------------

// Marks the nodes of every particle's stencil and lists them, ascending, in grids.active.
void mark_active_nodes(const Stencil& stencil, std::size_t particles, std::vector<int32_t>& node_stamp,
                       int32_t& stamp, Grids& grids, int threads);

// Mixed integration (docs/transfer.md): the internal force (A.8) integrates over a cell with its
// particles as quadrature points, weighted by their volumes V_p. A cell inside the material is
// integrated with its own area instead: A_e sigma_e grad N, sigma_e = sum V_p sigma_p / sum V_p,
// the one-point rule of a linear triangle, so scale[e] = A_e / sum V_p; elsewhere scale[e] = 1.
// Inside: the particles of the cell and of each cell across its edges (every body's particles)
// fill at least full_fill of that cell's area (an edge on the mesh's boundary does not count).
// cell_volume: per thread, one zeroed entry per element, left zeroed.
void full_cell_scales(const Mesh& mesh, const Particles& P, double full_fill,
                      std::vector<std::vector<double>>& cell_volume, std::vector<double>& scale, int threads);

// What P2G reads. `x_i`: the node positions (APIC's affine momentum needs them). `load_factor`:
// each surface load's ramp factor now (empty: no loads). `cell_scale`: mixed integration's
// factor on V sigma per element (empty: none).
struct ToGridInput {
  const Particles& P;
  const Stencil& stencil;
  const std::vector<Vec2>& x_i;
  Vec2 gravity;
  const std::vector<double>& load_factor;
  const std::vector<double>& cell_scale;
};

// (A.6)-(A.8): mass, momentum and force of each velocity field at the active nodes; with
// contact also the mass gradients. Particles of fixed bodies lend their mass (and normals) only.
// With APIC the momentum carries each particle's affine part, m_p C_p (x_i - x_p). A particle
// that carries a surface load adds load_factor[load] x its load_force, spread like its weight.
void particles_to_grid(const ToGridInput& in, Grids& grids, ThreadBuffers& buffers, int threads);

// Nodal accelerations a_i = f_i / m_i with local damping, such that the end-of-step velocity
// satisfies the constraints. A fixed body's field (field_fixed, with contact) does not move.
void update_grid_accelerations(const Constraints& constraints, const std::vector<uint8_t>& field_fixed,
                               double damping, double dt, Grids& grids, int threads);

// XPIC and APIC only: grid.v = v_i + dt a_i, PIC's velocity (with the lumped-mass v_i = p_i / m_i
// of P2G), constrained as the accelerations are.
void lagrangian_grid_velocities(const Constraints& constraints, double dt, Grids& grids, int threads);

// Ghost nodes (boundary.hpp, Mirror). A ghost's velocity is its partner's reflected, so its shape
// function acts as the reflected part of its partner's: after P2G its mass, momentum, force and
// mass gradient are folded into the partner's (R times each vector) and it holds none; the
// grid's phases then give it the partner's acceleration and velocity, reflected (they call the
// mirrors at their end, contact's corrections again). Nothing without ghosts.
void fold_ghosts(const Constraints& constraints, Grids& grids);
void mirror_accelerations(const Constraints& constraints, Grids& grids);
void mirror_velocities(const Constraints& constraints, Grids& grids);

// XPIC(m), m > 1 (xpic.cpp; Hammerquist and Nairn 2017): adds sum_{k=1}^{m-1} (I - S+S)^k v_i
// to grid.v, with S+S v_i = sum_p m_p N_ip (sum_j N_jp v_j) / m_i, and constrains the result.
void add_xpic_terms(const Particles& P, const Stencil& stencil, const Constraints& constraints, int order,
                    Grids& grids, ThreadBuffers& buffers, int threads);

// The particle velocities from the grid (docs/transfer.md), and the momentum for the remap
// scattered in the same pass. Flip and PicBlend: (A.10), v_p += dt sum N_ip a_i. Xpic and Apic:
// v_p = sum N_ip v_i with the velocities the two phases above left in grid.v; Apic also sets
// the affine matrix C_p from them (the family's, stencil.hpp) and scatters
// m_p (v_p + C_p (x_i - x_p)).
void update_particle_velocities(Particles& P, const Stencil& stencil, const std::vector<Vec2>& x_i, Transfer transfer,
                                double dt, const Grids& grids, ThreadBuffers& buffers, int threads);

// (A.11): v_i = sum N_ip m_p v_p / m_i, constrained. On several ranks the momentum is summed over
// the ranks at their shared nodes (`exchange`, after this rank's sum is in grid.v) before it is
// divided by the mass; empty on one rank.
void remap_grid_velocities(const Constraints& constraints, const std::vector<uint8_t>& field_fixed, Grids& grids,
                           ThreadBuffers& buffers, int threads, const std::function<void()>& exchange = {});

// (A.12): x_p += dt sum N_ip v_i; the strain increment d_eps and the Jaumann rotation of the
// stress from the velocity gradient; the PIC blend of the particle velocity.
void update_particle_kinematics(Particles& P, const Stencil& stencil, const Grids& grids, double pic_fraction,
                                double dt, std::vector<Vec4>& d_eps, int threads);

// ---- CPDI's particle domains (cpdi.cpp) ---------------------------------------------------------

// Each particle's domain at the start (Particles::domain, three corners per particle): the
// triangle similar to its element, of the particle's volume, centred on the particle; for four
// particles per triangle, the seeding's midpoint sub-triangles themselves, so the domains tile
// every element (the middle particle's is the inverted one).
void initial_domains(const Mesh& mesh, Particles& P);
// After (A.12): each corner moves with the remapped grid velocity interpolated there, which is
// what moved the particle; a domain is centred again on its particle, and one that has
// flattened, turned over or stretched beyond 5 sqrt(V_p) starts again as at the start.
void move_domains(const Mesh& mesh, Particles& P, const Stencil& stencil, const Grids& grids, double dt, int threads);

// ---- The cell pass (cells.cpp) -------------------------------------------------------------------
// One sweep over the particles, by runs of one element, gives each element's particle count
// (the stress update's isolated particles) and, with EVS, the sums of enhanced volumetric strain
// (Detournay and Dzik 2006; seed section 4): each cell's volume-weighted volumetric increment,
// then at each active node the area-weighted mean of the cells around it that hold particles
// (evs.node_strain, evs.node_area). evs_node_means divides them (evs.node_mean); a distributed
// step exchanges the node sums in between. The stress update then replaces the volumetric part
// of each particle's d_eps by the mean of node_mean over its stencil's nodes.

// Enhanced volumetric strain sums: per-thread element sums (added in thread order, so the
// result does not depend on timing), their totals, and the node averages.
struct EvsScratch {
  std::vector<std::vector<double>> element_strain, element_volume;  // [thread][element]
  std::vector<double> strain, volume;                               // [element]: strain is the cell average
  std::vector<double> node_strain, node_area;                       // [node]
  std::vector<double> node_mean;                                    // [node]: node_strain / node_area
  // The elements around each node, in ascending order: those of node i are
  // node_elements[node_first[i] .. node_first[i + 1]) (built with the mesh, evs_adjacency).
  std::vector<int32_t> node_first, node_elements;
};

void sum_cells(const Mesh& mesh, const Particles& P, bool evs_on, const std::vector<int32_t>& active,
               std::vector<int32_t>& element_count, EvsScratch& evs, const std::vector<Vec4>& d_eps, int threads);
void evs_node_means(const std::vector<int32_t>& active, EvsScratch& evs, int threads);
// The elements around each node (EvsScratch::node_first, node_elements) of `mesh`.
void evs_adjacency(const Mesh& mesh, EvsScratch& evs);

// ---- Relocation (relocate.cpp) ----------------------------------------------------------------

// Finds each moving particle's element (neighbour walk) and recomputes its stencil row.
// Returns the last particle that left the domain, or -1.
long relocate_particles(const Mesh& mesh, Particles& P, Stencil& stencil, int threads);
// The element walk of relocate_particles alone (a distributed step migrates the particles
// between it and the stencil): the last particle that left the domain, -1 when none did.
long locate_particles(const Mesh& mesh, Particles& P, int threads);

}  // namespace talus::solver
