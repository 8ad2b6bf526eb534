// One model across several processes (MPI ranks; docs/scaling.md). Every rank holds the whole
// background mesh and its constraints; METIS splits the mesh's elements among the ranks,
// weighted by their particles, and each rank keeps the particles of its elements. A node on the
// border of two ranks' elements is shared: each rank sums what its own particles give the node
// and the ranks swap those partial sums (the halo exchange), adding them in rank order so that
// every rank holds the same bits. A particle that moves into another rank's element migrates to
// it at the end of the step, with every field of the registry. With one rank nothing here runs.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "solver/parallel/mpi.hpp"
#include "solver/step/simulation.hpp"

namespace talus::solver {

// Splits `sim` (built whole on every rank by make_simulation, or read whole from a checkpoint)
// among the ranks of the MPI run: partitions the elements, keeps this rank's particles and sets
// up the shared nodes. With one rank it does nothing. Throws SharedError for what cannot run
// distributed.
void distribute(Simulation& sim);

// The elements partitioned again, weighted by the particles each holds now, when the particle
// imbalance passes kRepartitionImbalance; the particles migrate to their new ranks. Returns
// whether it repartitioned. Collective.
bool rebalance(Simulation& sim);

// Sends each moving particle whose element belongs to another rank to that rank, and appends
// the particles received to the moving ones; resizes the per-particle scratch. Collective.
void migrate_particles(Simulation& sim);

// The halo exchange of `width` values per node. get(i, out) writes this rank's part at shared
// node i (the caller gives neutral values where the node is not its own this step), and after
// the exchange set(i, in) receives the combination of every rank's parts, for the nodes where
// active(i). combine(acc, value, c) folds a further rank's value of component c into acc;
// ranks are folded in rank order. With `flag` >= 0, component `flag` marks where the node was
// active on a rank (1) and counting_rank records the lowest such rank.
template <class Get, class Set, class Active, class Combine>
void halo_exchange(Domain& d, int width, Get get, Set set, Active active, Combine combine, int flag = -1) {
  const std::size_t w = static_cast<std::size_t>(width);
  const std::size_t K = d.neighbours.size();
  for (std::size_t k = 0; k < K; ++k) {
    const auto& nodes = d.shared[k];
    d.send[k].resize(nodes.size() * w);
    d.receive[k].resize(nodes.size() * w);
    for (std::size_t j = 0; j < nodes.size(); ++j) get(nodes[j], &d.send[k][j * w]);
  }
  mpi::exchange(d.neighbours, d.send, d.receive);
  d.halo_bytes += static_cast<double>(w * sizeof(double)) * [&] {
    std::size_t n = 0;
    for (const auto& nodes : d.shared) n += nodes.size();
    return static_cast<double>(n);
  }();
  ++d.exchanges;
  // Fold the ranks' parts in rank order: the neighbours below this rank, this rank, those above.
  const std::size_t slots = d.halo_nodes.size();
  d.combined.resize(slots * w);
  std::vector<uint8_t> started(slots, 0);
  if (flag >= 0) d.counting_rank.assign(slots, -1);
  std::vector<double> own_values(w);
  double* own = own_values.data();
  auto fold = [&](std::size_t slot, const double* values, int from) {
    double* acc = &d.combined[slot * w];
    if (!started[slot]) {
      for (std::size_t c = 0; c < w; ++c) acc[c] = values[c];
      started[slot] = 1;
    } else {
      for (std::size_t c = 0; c < w; ++c) combine(acc[c], values[c], static_cast<int>(c));
    }
    if (flag >= 0 && d.counting_rank[slot] < 0 && values[flag] > 0) d.counting_rank[slot] = from;
  };
  auto fold_neighbour = [&](std::size_t k) {
    const auto& nodes = d.shared[k];
    for (std::size_t j = 0; j < nodes.size(); ++j)
      fold(static_cast<std::size_t>(d.halo_slot[nodes[j]]), &d.receive[k][j * w], d.neighbours[k]);
  };
  std::size_t k = 0;
  for (; k < K && d.neighbours[k] < d.rank; ++k) fold_neighbour(k);
  for (std::size_t slot = 0; slot < slots; ++slot) {
    get(d.halo_nodes[slot], own);
    fold(slot, own, d.rank);
  }
  for (; k < K; ++k) fold_neighbour(k);
  for (std::size_t slot = 0; slot < slots; ++slot)
    if (active(d.halo_nodes[slot])) set(d.halo_nodes[slot], &d.combined[slot * w]);
}

// The sum in rank order of the halo exchange.
inline void add_in_order(double& acc, double value, int) { acc += value; }

// The exchanges of the step (step.cpp calls them when distributed): after P2G, the mass,
// momentum, force (and mass gradient) of every field at the shared nodes; the remap's momentum,
// held in grid.v; the EVS node sums.
void exchange_grid_sums(Simulation& sim);
void exchange_remap_momentum(Simulation& sim);
void exchange_evs_sums(Simulation& sim);
// Contact: the extents per candidate node (contact.extents, combined over the threads into
// extents[0]): maxima of the fronts, minima of where bodies begin.
void exchange_contact_extents(Domain& d, const std::vector<int32_t>& candidates, std::size_t bodies,
                              ContactScratch& contact);
// XPIC: the projected momentum of one power of S+S, held in the fields' xpic scratch.
void exchange_xpic_momentum(Simulation& sim, std::vector<std::vector<Vec2>>& projected);

// Every rank's particles on rank 0 (moving particles of ranks 0, 1, ... then their fixed ones),
// with `extra` (one Vec2 per local particle, e.g. the grid velocity at each) gathered alike
// into extra_all; empty on the other ranks. Collective.
Particles gather_particles(const Simulation& sim, const std::vector<Vec2>* extra = nullptr,
                           std::vector<Vec2>* extra_all = nullptr);

// Runs `work` on rank 0 only and shares its outcome: an Error there becomes a SharedError on
// every rank, so that no rank waits for one that has stopped. With one rank it runs `work`.
template <class Work>
void on_root(Work&& work);

}  // namespace talus::solver

#include "solver/parallel/domain_inl.hpp"
