// The stress update (seed, section 4; A.13's constitutive step): each moving particle's material
// (solver/stress/material_state.hpp) applied to its strain increment, with EVS's volumetric
// part, the effective stress under water (water.hpp), the isolated-particle rule and the
// volume update: one loop with or without water.
#pragma once
#include <algorithm>
#include <array>
#include <vector>

#include "solver/interpolation/interpolation.hpp"
#include "solver/step/simulation.hpp"
#include "solver/stress/material_state.hpp"

namespace talus::solver {

// Isolated particles (docs/transfer.md, "Isolated particles"). A particle alone in its element
// is a grain in free flight, not a piece of a continuum: the nodes it shares with a wall or with
// the body it left give it strain increments that no neighbour balances, and with a frictional
// material (tension cut off at the apex, compression kept) those increments ratchet up a
// compressive stress many times the overburden that the grain later releases in one step
// (measured on the column collapse: -20 kPa in a grain that left a 0.1 m column, whose weight
// gives at most 1.5 kPa). So an isolated particle carries no stress and keeps its volume.
// "Alone" needs particles smaller than their element: with one particle per cell every particle
// is alone, so a particle is isolated only when it also fills less than half of its element.
// With B-splines a particle at a body's free surface may be alone in its (lattice) triangle
// while its neighbours hold it (the hanging bar of tests/hanging_bar_test.cpp settled 10-20 %
// too far as its surface particles dropped their stress): there a particle is isolated only
// when the elements across its element's edges are empty too (`neighbours` not null). Linear
// triangles keep the element-only test: on several ranks a rank counts only its own elements,
// so a neighbour test would make the answer depend on the partition; the B-spline family's
// halo does not cover element counts either (docs/shape-functions.md says so). CPDI adds a test
// of the node masses, which every rank holds summed (StrainIncrement::alone_on_its_nodes).
inline bool is_isolated(const int32_t* particles_in_element, const std::array<int32_t, 3>* neighbours, int32_t e,
                        double volume, double element_area) {
  if (particles_in_element[e] != 1 || !(2 * volume < element_area)) return false;
  if (neighbours)
    for (const int32_t n : neighbours[e])
      if (n >= 0 && particles_in_element[n] > 0) return false;
  return true;
}

// What the stress update takes from the cell pass, and per thread the particle's strain
// increment with EVS applied (the smoothed value is computed once per run of particles that
// share a stencil row).
struct CellSums {
  const Mesh& mesh;
  const Stencil& stencil;
  const std::vector<int32_t>& element_count;
  const double* node_mean;  // EVS's evs.node_mean; null: EVS off
  const Grids* grids = nullptr;  // this step's node masses: CPDI's isolated-particle test reads them
};
class StrainIncrement {
 public:
  // The arrays' data pointers are taken once: read through the containers, the compiler would
  // reload them after every store the stress update makes.
  StrainIncrement(const CellSums& sums, const Particles& P)
      : row_(cpdi(sums) ? P.element.data() : sums.stencil.row.data()),
        row_node_(cpdi(sums) ? sums.mesh.triangles.data()->data() : sums.stencil.row_node.data()),
        width_(cpdi(sums) ? 3 : sums.stencil.width),
        node_mean_(sums.node_mean), count_(sums.element_count.data()), area_(sums.mesh.area.data()),
        neighbours_(sums.stencil.family == ShapeFamily::QuadraticBspline ? sums.mesh.neighbours.data() : nullptr),
        element_(P.element.data()), volume_(P.volume.data()),
        grids_(cpdi(sums) ? sums.grids : nullptr), N_(sums.stencil.N.data()),
        stencil_node_(sums.stencil.row_node.data()), stencil_width_(sums.stencil.width), mass_(P.m.data()),
        body_(P.body.data()) {}
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
  // With CPDI, EVS smooths over the particle's element's nodes, as with linear triangles: a row
  // per particle's padded entries would weigh nodes twice.
  static bool cpdi(const CellSums& sums) { return sums.stencil.family == ShapeFamily::LinearCpdi; }
  bool isolated(long p) const {
    const int32_t e = element_[p];
    if (!is_isolated(count_, neighbours_, e, volume_[p], area_[e])) return false;
    return !grids_ || alone_on_its_nodes(p);
  }
  // CPDI: a particle alone in its element is isolated only when the other particles put, weighted
  // by its own weights, less than half its mass on its nodes, sum_i S_ip (m_i - m_p S_ip) <
  // m_p / 2. The domains of a coherent body tile it, so a particle at its surface shares its
  // nodes with its neighbours and keeps its stress (the hanging bar, docs/shape-functions.md); a
  // grain in free flight, or touching the body at a corner, does not. The node masses are summed
  // over the ranks, so every partition finds the same particles.
  bool alone_on_its_nodes(long p) const {
    const Grid& grid = grids_->fields[static_cast<std::size_t>(grids_->field_of(body_[p]))];
    const std::size_t first = static_cast<std::size_t>(p) * static_cast<std::size_t>(stencil_width_);
    double others = 0;
    for (int k = 0; k < stencil_width_; ++k) {
      const double S = N_[first + k];
      others += S * (grid.m[stencil_node_[first + k]] - mass_[p] * S);
    }
    return others < 0.5 * mass_[p];
  }

 private:
  const int32_t* row_;
  const int32_t* row_node_;
  int width_;
  const double* node_mean_;
  const int32_t* count_;
  const double* area_;
  const std::array<int32_t, 3>* neighbours_;
  const int32_t* element_;
  const double* volume_;
  const Grids* grids_;  // CPDI only
  const double* N_;
  const int32_t* stencil_node_;
  int stencil_width_;
  const double* mass_;
  const int32_t* body_;
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

// With APIC, an isolated particle whose stencil reaches a node that a boundary condition holds
// (or a B-spline ghost, a wall's mirror) also loses its affine velocity C_p: the only velocity
// gradient such a grain's nodes can give it is the wall's or the rough base's (its lower nodes
// held at rest under it), not its own. Kept, that gradient goes back into the next P2G as
// velocities of metres per second at its nodes, a cell from a grain at rest; with CPDI it is
// divided by a D_p that a domain shrunk against the base makes small. The rods at a = 2 and 4
// with CPDI blew up so (t = 0.62 s at a = 2: grains sliding ahead of the front at 1-3 m/s with
// |C_p| ~ 2e3 1/s; docs/transfer.md, "APIC with CPDI on every shipped scene"). A lone grain away
// from the walls keeps C_p: its own P2G and G2P carry an affine field exactly, its spin included.
inline bool reaches_held_node(const Constraints& constraints, const Stencil& stencil, long p) {
  const int32_t* nodes = stencil.nodes(static_cast<std::size_t>(p));
  for (int k = 0; k < stencil.width; ++k)
    if (nodes[k] >= constraints.first_ghost || constraints.kind[nodes[k]] != Constraint::Free) return true;
  return false;
}

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

// For every moving particle that is not isolated: the strain increment d_eps as EVS leaves it
// (StrainIncrement, step.hpp), the material's update over the step dt (with a water table on the
// effective stress sigma + u (1, 1, 1, 0), then the pore pressure u at time t, the end of the step,
// and the total stress sigma' - u I), and the volume V_p *= 1 + tr d_eps, capped at
// kMaxVolumeGrowth V_p(0). An isolated particle drops its stress and keeps its volume.
// Returns the last (largest index) particle whose state became non-finite or inverted, or -1.
long update_stresses(Particles& P, const std::vector<Vec4>& d_eps, const CellSums& cells, const Config& config,
                     double t, double dt, int threads);

// The elastic energy density of particle p's effective stress (energies(), diagnostics.cpp),
// with its own E and nu when it has them.
inline double elastic_energy_density(const Config& config, const Particles& P, std::size_t p) {
  const MaterialState& material = config.materials[config.material_of_body[P.body[p]]];
  if (!material.elastic_columns) return elastic_energy_density(material, effective_stress(P, p));
  const ParticleMaterial& own = material.of_particle(P.id[p]);
  return elastic_energy_density(own.shear_modulus, own.bulk_modulus, effective_stress(P, p));
}

}  // namespace talus::solver
