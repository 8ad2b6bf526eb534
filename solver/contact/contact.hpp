// Frictional contact between bodies (Bardenhagen, Brackbill and Sulsky 2000; seed appendix B;
// docs/contact.md): at nodes where more than one velocity field (a body, or a group of bonded
// bodies) has mass and their particles touch, approach is removed along the normal and the
// tangential part follows Coulomb stick or slip. A fixed body is rigid: the reference velocity at
// a node it touches is zero. After the correction each node's constraints hold again (a body
// pushed along a roller wall by contact still does not cross it). The step runs these three only
// when the scene has two or more fields that can meet (Config::contact).
#pragma once
#include <cstdint>
#include <vector>

#include "solver/boundary/boundary.hpp"
#include "solver/interpolation/grid.hpp"
#include "solver/interpolation/mesh.hpp"
#include "solver/interpolation/stencil.hpp"
#include "solver/step/particles.hpp"

namespace talus::solver {

struct Domain;  // solver/parallel/domain.hpp

struct ContactRules {
  const std::vector<std::vector<double>>& pair_friction;  // [field][field]
  const std::vector<uint8_t>& field_fixed;
  const Constraints& constraints;
  // [node], m: the size of the node's elements, sqrt(2 x their mean area) (h for the grid
  // pattern's right triangles); empty without a fixed field. It scales a fixed body's mass
  // gradient to tell the body's surface from its inside (docs/contact.md, "Rigid support").
  const std::vector<double>& node_length;
  // The stencil reaches beyond the particle's element (B-splines, CPDI): a body's mass lands
  // round a fixed body's corners, where contact then skips it (docs/contact.md).
  bool wide_stencil;
};

// The node_length of ContactRules for `mesh`: zero at a node no element holds (the lattice's
// ghosts).
std::vector<double> element_lengths_at_nodes(const Mesh& mesh);

// Rebuilt every step by find_contact_nodes.
struct ContactScratch {
  std::vector<int32_t> nodes;                // this step's contact nodes, ascending
  // For each listed node k and field b: whether b takes part in the contact there, and b's
  // outward unit normal (zero for a fixed field).
  std::vector<uint8_t> touching;             // [k * fields + b]
  std::vector<Vec2> normal;                  // [k * fields + b]
  // While listing: each candidate node's index (else -1), and per thread the extents of the
  // fields along each normal.
  std::vector<int32_t> slot;                 // [node]
  std::vector<std::vector<double>> extents;  // [thread][(k * fields + b) * fields + c], m
  // The fixed particles [moving_count, size) in runs that share a stencil row, each run's first
  // particle and a final end: fixed particles never move and keep their order (emptied when the
  // particles are sorted or migrate).
  std::vector<std::size_t> fixed_runs;
};

// Lists (ascending) in contact.nodes the nodes where 2+ fields have mass and their particles
// touch along the contact normal (docs/contact.md, "Detection"), and records which fields take
// part at each. On several ranks (`domain`) the extents are combined over the ranks at the
// shared nodes.
void find_contact_nodes(const ContactRules& rules, const Particles& particles, const Stencil& stencil,
                        const Grids& grids, ContactScratch& contact, int threads, Domain* domain = nullptr);

// Corrects the end-of-step trial velocities through the accelerations, so that (A.10) sees it.
void apply_contact(const ContactRules& rules, double dt, const ContactScratch& contact, Grids& grids, int threads);

// Corrects the remapped velocities (A.11).
void apply_contact_velocities(const ContactRules& rules, const ContactScratch& contact, Grids& grids, int threads);

}  // namespace talus::solver
