// The explicit MUSL step (seed, appendix A; design.md, "The explicit step") and its phases.
// Each phase is a free function over the data it names, one loop a reader can check against
// the cited equation; `step()` calls them in order, contact included.
#pragma once
#include <algorithm>
#include <vector>

#include "solver/step/simulation.hpp"

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
// With APIC the momentum carries each particle's affine part, m_p C_p (x_i - x_p), for which
// it needs the node positions x_i. A particle that carries a surface load adds
// load_factor[load] x its load_force, spread like its weight (empty factors: no loads).
// cell_scale (empty: none) multiplies V sigma of the particles in each element: mixed
// integration's factors (full_cell_scales).
void particles_to_grid(const Particles& P, const Stencil& stencil, const std::vector<Vec2>& x_i, const Vec2& gravity,
                       const std::vector<double>& load_factor, const std::vector<double>& cell_scale, Grids& grids,
                       ThreadBuffers& buffers, int threads);

// Mixed integration (docs/transfer.md): the internal force (A.8) integrates over a cell with its
// particles as quadrature points, weighted by their volumes V_p. A cell inside the material is
// integrated with its own area instead: A_e sigma_e grad N, sigma_e = sum V_p sigma_p / sum V_p,
// the one-point rule of a linear triangle, so scale[e] = A_e / sum V_p; elsewhere scale[e] = 1.
// Inside: the particles of the cell and of each cell across its edges (every body's particles)
// fill at least full_fill of that cell's area (an edge on the mesh's boundary does not count).
// cell_volume: per thread, one zeroed entry per element, left zeroed.
void full_cell_scales(const Mesh& mesh, const Particles& P, double full_fill,
                      std::vector<std::vector<double>>& cell_volume, std::vector<double>& scale, int threads);

// Nodal accelerations a_i = f_i / m_i with local damping, such that the end-of-step velocity
// satisfies the constraints. A fixed body's field (field_fixed, with contact) does not move.
void update_grid_accelerations(const Constraints& constraints, const std::vector<uint8_t>& field_fixed,
                               double damping, double dt, Grids& grids, int threads);

// XPIC and APIC only (transfer.cpp): grid.v = v_i + dt a_i, PIC's velocity (with the
// lumped-mass v_i = p_i / m_i of P2G), constrained as the accelerations are.
void lagrangian_grid_velocities(double dt, Grids& grids, int threads);

// XPIC(m), m > 1 (transfer.cpp; Hammerquist and Nairn 2017): adds sum_{k=1}^{m-1} (I - S+S)^k v_i
// to grid.v, with S+S v_i = sum_p m_p N_ip (sum_j N_jp v_j) / m_i, and constrains the result.
void add_xpic_terms(const Particles& P, const Stencil& stencil, const Constraints& constraints, int order,
                    Grids& grids, ThreadBuffers& buffers, int threads);

// The particle velocities from the grid (docs/transfer.md), and the momentum for the remap
// scattered in the same pass. Flip and PicBlend: (A.10), v_p += dt sum N_ip a_i. Xpic and Apic:
// v_p = sum N_ip v_i with the velocities the two phases above left in grid.v; Apic also sets
// C_p = sum v_i (grad N_ip)^T from them and scatters m_p (v_p + C_p (x_i - x_p)).
void update_particle_velocities(Particles& P, const Stencil& stencil, const std::vector<Vec2>& x_i, Transfer transfer,
                                double dt, const Grids& grids, ThreadBuffers& buffers, int threads);

// (A.11): v_i = sum N_ip m_p v_p / m_i, constrained.
void remap_grid_velocities(const Constraints& constraints, const std::vector<uint8_t>& field_fixed, Grids& grids,
                           ThreadBuffers& buffers, int threads);

// (A.12): x_p += dt sum N_ip v_i; the strain increment d_eps and the Jaumann rotation of the
// stress from the velocity gradient; the PIC blend of the particle velocity.
void update_particle_kinematics(Particles& P, const Stencil& stencil, const Grids& grids, double pic_fraction,
                                double dt, std::vector<Vec4>& d_eps, int threads);

// ---- The cell pass (evs.cpp) and the stress update it feeds ----------------------------------
// One sweep over the particles, by runs of one element, gives each element's particle count
// (isolated particles, below) and, with EVS, the sums of enhanced volumetric strain (Detournay
// and Dzik 2006; seed section 4): each cell's volume-weighted volumetric increment, then at each
// active node the area-weighted mean of the cells around it that hold particles
// (evs.node_strain, evs.node_area). evs_node_means divides them (evs.node_mean); a distributed
// step exchanges the node sums in between. The stress update then replaces the volumetric part
// of each particle's d_eps by the mean of node_mean over its stencil's nodes (for linear
// triangles, its cell's three nodes).
void sum_cells(const Mesh& mesh, const Particles& P, bool evs_on, const std::vector<int32_t>& active,
               std::vector<int32_t>& element_count, EvsScratch& evs, const std::vector<Vec4>& d_eps, int threads);
void evs_node_means(const std::vector<int32_t>& active, EvsScratch& evs, int threads);
// The elements around each node (EvsScratch::node_first, node_elements) of `mesh`.
void evs_adjacency(const Mesh& mesh, EvsScratch& evs);

// Isolated particles (docs/transfer.md, "Isolated particles"). A particle alone in its element
// is a grain in free flight, not a piece of a continuum: the nodes it shares with a wall or with
// the body it left give it strain increments that no neighbour balances, and with a frictional
// material (tension cut off at the apex, compression kept) those increments ratchet up a
// compressive stress many times the overburden that the grain later releases in one step
// (measured on the column collapse: -20 kPa in a grain that left a 0.1 m column, whose weight
// gives at most 1.5 kPa). So an isolated particle carries no stress and keeps its volume.
// "Alone" needs particles smaller than their element: with one particle per cell every particle
// is alone, so a particle is isolated only when it also fills less than half of its element.
inline bool is_isolated(int32_t particles_in_element, double volume, double element_area) {
  return particles_in_element == 1 && 2 * volume < element_area;
}

// What the stress update takes from the cell pass, and per thread the particle's strain
// increment with EVS applied (the smoothed value is computed once per run of particles that
// share a stencil row).
struct CellSums {
  const Mesh& mesh;
  const Stencil& stencil;
  const std::vector<int32_t>& element_count;
  const double* node_mean;  // EVS's evs.node_mean; null: EVS off
};
class StrainIncrement {
 public:
  // The arrays' data pointers are taken once: read through the containers, the compiler would
  // reload them after every store the stress update makes.
  StrainIncrement(const CellSums& sums, const Particles& P)
      : row_(sums.stencil.row.data()), row_node_(sums.stencil.row_node.data()), width_(sums.stencil.width),
        node_mean_(sums.node_mean), count_(sums.element_count.data()), area_(sums.mesh.area.data()),
        element_(P.element.data()), volume_(P.volume.data()) {}
  Vec4 operator()(long p, const Vec4& d) {
    if (!node_mean_) return d;
    const int32_t row = row_[p];
    if (row != run_row_) {
      run_row_ = row;
      const int32_t* nodes = row_node_ + static_cast<std::size_t>(row) * width_;
      smoothed_ = 0;
      for (int k = 0; k < width_; ++k) smoothed_ += node_mean_[nodes[k]];
      smoothed_ /= width_;
    }
    const double correction = 0.5 * (smoothed_ - (d[0] + d[1]));  // in-plane, so d_eps_zz stays 0
    return Vec4(d[0] + correction, d[1] + correction, d[2], d[3]);
  }
  bool isolated(long p) const {
    const int32_t e = element_[p];
    return is_isolated(count_[e], volume_[p], area_[e]);
  }

 private:
  const int32_t* row_;
  const int32_t* row_node_;
  int width_;
  const double* node_mean_;
  const int32_t* count_;
  const double* area_;
  const int32_t* element_;
  const double* volume_;
  int32_t run_row_ = -1;
  double smoothed_ = 0;
};

// The particle arrays a stress update reads and writes, their data pointers taken once, per
// thread: read through the containers, the compiler reloads them after every store to a
// particle (14 of 152 instructions a particle, counted with cachegrind; docs/water.md, "Cost").
struct StressArrays {
  explicit StressArrays(Particles& P)
      : x(P.x.data()), v(P.v.data()), body(P.body.data()), id(P.id.data()), sigma(P.sigma.data()),
        eps_p(P.eps_p.data()), volume(P.volume.data()),
        history(P.history_width > 0 ? P.history.data() : nullptr),
        history_width(static_cast<std::size_t>(P.history_width)) {}
  // Particle p's history_width state variables (none: null).
  double* history_of(long p) const { return history ? history + static_cast<std::size_t>(p) * history_width : nullptr; }

  const Vec2* x;
  const Vec2* v;
  const int32_t* body;
  const int32_t* id;
  Vec4* sigma;
  double* eps_p;
  double* volume;
  double* history;
  std::size_t history_width;
};

// A particle's volume grows to at most this many times its initial volume. Elastic strains and
// a sand's dilation stay well below; beyond it a material pulled apart (a frictional one at the
// apex of its cone, without stress) opens gaps between its particles instead of inflating them.
// Uncapped, a grain that left the column collapse grew to 10-100 times its volume, and the next
// compression, acting through V_p sigma_p, threw it out of the mesh (docs/transfer.md).
inline constexpr double kMaxVolumeGrowth = 1.2;

// V_p (1 + trace), capped at kMaxVolumeGrowth V_p(0). The cap (a gather by the particle's id) is
// read only when the volume grows: it was under it before.
inline double grown_volume(double volume, double trace, const double* initial_volume, int32_t id) {
  return trace > 0 ? std::min(volume * (1 + trace), kMaxVolumeGrowth * initial_volume[id]) : volume * (1 + trace);
}

// Finds each moving particle's element (neighbour walk) and recomputes its stencil row.
// Returns the last particle that left the domain, or -1.
long relocate_particles(const Mesh& mesh, Particles& P, Stencil& stencil, int threads);
// The element walk of relocate_particles alone (a distributed step migrates the particles
// between it and the stencil): the last particle that left the domain, -1 when none did.
long locate_particles(const Mesh& mesh, Particles& P, int threads);
// (A.11) on several ranks: the remap's momentum summed over the ranks at the shared nodes
// before it is divided by the mass (domain.hpp).
void remap_grid_velocities_distributed(Simulation& sim);

// ---- Frictional contact (contact.cpp) -------------------------------------------------------
// Bardenhagen et al. (2000), seed appendix B: at nodes where more than one field (a body, or a
// group of bonded bodies) has mass and their particles touch (docs/contact.md, "Detection"),
// approach is removed along the normal and the tangential part follows Coulomb stick or slip.
// A fixed body is rigid: the reference velocity at a node it touches is zero. After the
// correction each node's constraints hold again (a body pushed along a roller wall by contact
// still does not cross it).

struct ContactRules {
  const std::vector<std::vector<double>>& pair_friction;  // [field][field]
  const std::vector<uint8_t>& field_fixed;
  const Constraints& constraints;
};

// Lists (ascending) in `contact_nodes` the nodes where 2+ bodies have mass and their particles
// touch along the contact normal, and records which bodies take part at each.
// On several ranks (`domain`), the extents are combined over the ranks at the shared nodes.
struct Domain;
void find_contact_nodes(const ContactRules& rules, const Particles& particles, const Stencil& stencil, Grids& grids,
                        std::vector<int32_t>& contact_nodes, int threads, Domain* domain = nullptr);

// Corrects the end-of-step trial velocities through the accelerations, so that (A.10) sees it.
void apply_contact(const ContactRules& rules, double dt, const std::vector<int32_t>& contact_nodes, Grids& grids,
                   int threads);

// Corrects the remapped velocities (A.11).
void apply_contact_velocities(const ContactRules& rules, const std::vector<int32_t>& contact_nodes, Grids& grids,
                              int threads);

}  // namespace talus::solver
