// The decomposition state of a simulation run on several MPI ranks (domain.hpp has the
// functions). Empty, with ranks == 1, for a run on one process.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace talus::solver {

// The particle imbalance (most particles on a rank over the mean) beyond which the elements
// are partitioned again, checked at the start of every kRebalanceInterval-th step.
inline constexpr double kRepartitionImbalance = 1.10;
inline constexpr long kRebalanceInterval = 50;

struct Domain {
  int rank = 0, ranks = 1;
  std::vector<int32_t> element_owner;          // [element] -> rank
  std::vector<std::size_t> field_width;        // [registry field]: elements per particle (0: unused)
  std::vector<int> neighbours;                 // ranks sharing nodes with this one, ascending
  std::vector<std::vector<int32_t>> shared;    // [k]: the nodes shared with neighbours[k], ascending
  std::vector<int32_t> halo_nodes;             // every shared node, ascending
  std::vector<int32_t> halo_slot;              // [node] -> index in halo_nodes, -1 when not shared
  // [halo slot]: the lowest rank where the node was active in this step's P2G, which alone
  // counts it in sums over nodes (the grid kinetic energy).
  std::vector<int32_t> counting_rank;
  std::vector<std::vector<double>> send, receive;  // [k], per exchange
  std::vector<double> combined;                    // [halo slot * width + c]
  // Statistics over the run (this rank's): bytes sent in halo exchanges and migrations,
  // exchanges, particles sent away, repartitions.
  double halo_bytes = 0, migration_bytes = 0;
  long exchanges = 0, migrated = 0, repartitions = 0;

  bool distributed() const { return ranks > 1; }
  // Counts node i in sums over nodes on this rank.
  bool counts(int32_t i) const {
    if (!distributed()) return true;
    const int32_t slot = halo_slot[i];
    return slot < 0 || counting_rank[slot] == rank;
  }
};

}  // namespace talus::solver
