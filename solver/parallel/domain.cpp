#include "solver/parallel/domain.hpp"
#include "solver/parallel/packing.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>

#include "common/error.hpp"

#ifdef TALUS_WITH_MPI
#include <metis.h>
#endif

namespace talus::solver {
namespace {

// The per-particle scratch and stencil sized for the particles now held, the stencil filled
// for the fixed particles (and the moving ones too with `all`), and the fixed particles' runs
// to be rebuilt.
void particles_changed(Simulation& sim, bool all = true) {
  Particles& P = sim.particles;
  const auto& fixed = sim.config.body_fixed;
  P.moving_count = 0;
  while (P.moving_count < P.size() && !fixed[P.body[P.moving_count]]) ++P.moving_count;
  Scratch& s = sim.scratch;
  resize_rows(s.stencil, P.size());
  compute_stencil(sim.config.mesh, P, all ? 0 : P.moving_count, P.size(), s.stencil, sim.config.threads);
  s.d_eps.resize(P.size(), Vec4::Zero());
  s.contact.fixed_runs.clear();
}

// Replaces the particles by Q (moving ones first) and updates what depends on them.
void replace_particles(Simulation& sim, Particles&& Q) {
  Q.history_width = sim.particles.history_width;
  sim.particles = std::move(Q);
  particles_changed(sim);
}

// ---- Partition -------------------------------------------------------------------------------

// The owner rank of every element: METIS's k-way partition of the element graph (elements
// joined across their edges), each element weighted by 1 + 8 x its particles so that the ranks
// share the particles and empty elements still count a little. Every rank computes it from the
// same counts, and METIS with a fixed seed gives the same partition on each.
std::vector<int32_t> partition_elements(const Mesh& mesh, const std::vector<double>& particles_per_element,
                                        int parts) {
  const std::size_t elements = mesh.element_count();
  std::vector<int32_t> owner(elements, 0);
  if (parts <= 1) return owner;
#ifdef TALUS_WITH_MPI
  if (elements < static_cast<std::size_t>(parts))
    throw SharedError("mpi: " + std::to_string(parts) + " ranks for a mesh of " + std::to_string(elements) +
                      " elements: use fewer ranks");
  std::vector<idx_t> xadj(elements + 1, 0), adjncy, weight(elements), part(elements, 0);
  adjncy.reserve(elements * 3);
  for (std::size_t e = 0; e < elements; ++e) {
    for (int32_t n : mesh.neighbours[e])
      if (n >= 0) adjncy.push_back(n);
    xadj[e + 1] = static_cast<idx_t>(adjncy.size());
    weight[e] = static_cast<idx_t>(1 + 8 * particles_per_element[e]);
  }
  idx_t vertices = static_cast<idx_t>(elements), constraints = 1, nparts = parts, cut = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_SEED] = 7;
  options[METIS_OPTION_NUMBERING] = 0;
  const int status = METIS_PartGraphKway(&vertices, &constraints, xadj.data(), adjncy.data(), weight.data(), nullptr,
                                         nullptr, &nparts, nullptr, nullptr, options, &cut, part.data());
  if (status != METIS_OK) throw SharedError("mpi: METIS could not partition the mesh (status " + std::to_string(status) + ")");
  for (std::size_t e = 0; e < elements; ++e) owner[e] = static_cast<int32_t>(part[e]);
#else
  throw SharedError("mpi: this talus was built without MPI");
#endif
  return owner;
}

// The shared nodes of this rank: nodes that particles in its elements can reach and particles in
// another rank's elements too. For linear triangles those are the element's corners; B-splines
// reach the 4 x 4 lattice nodes around the element's cell, ghosts included (lattice.hpp); CPDI
// the nodes of every element that shares a node with it (its domains' corners stay in those,
// stencil.hpp, fill_cpdi).
void set_up_halo(Domain& d, const Mesh& mesh, const Stencil& stencil) {
  std::vector<std::pair<int32_t, int32_t>> node_rank;  // (node, rank) of every node an element reaches
  node_rank.reserve(mesh.element_count() * (stencil.rows_per_particle() ? 16 : 3));
  std::vector<int32_t> reach;
  EvsScratch around;  // CPDI: the elements around each node (evs_adjacency)
  if (stencil.family == ShapeFamily::LinearCpdi) evs_adjacency(mesh, around);
  for (std::size_t e = 0; e < mesh.element_count(); ++e) {
    if (stencil.family == ShapeFamily::QuadraticBspline) {
      reachable_nodes(stencil.lattice, mesh, static_cast<int32_t>(e), reach);
    } else if (stencil.family == ShapeFamily::LinearCpdi) {
      reach.clear();
      for (int32_t i : mesh.triangles[e])
        for (int32_t j = around.node_first[i]; j < around.node_first[i + 1]; ++j) {
          const auto& t = mesh.triangles[around.node_elements[j]];
          reach.insert(reach.end(), t.begin(), t.end());
        }
      std::sort(reach.begin(), reach.end());
      reach.erase(std::unique(reach.begin(), reach.end()), reach.end());
    } else {
      reach.assign(mesh.triangles[e].begin(), mesh.triangles[e].end());
    }
    for (int32_t i : reach) node_rank.emplace_back(i, d.element_owner[e]);
  }
  std::sort(node_rank.begin(), node_rank.end());
  node_rank.erase(std::unique(node_rank.begin(), node_rank.end()), node_rank.end());
  std::vector<std::vector<int32_t>> by_rank(static_cast<std::size_t>(d.ranks));
  d.halo_nodes.clear();
  d.halo_slot.assign(mesh.node_count(), -1);
  for (std::size_t a = 0; a < node_rank.size();) {
    std::size_t b = a;
    bool mine = false;
    for (; b < node_rank.size() && node_rank[b].first == node_rank[a].first; ++b) mine = mine || node_rank[b].second == d.rank;
    if (mine && b - a > 1) {
      const int32_t node = node_rank[a].first;
      d.halo_slot[node] = static_cast<int32_t>(d.halo_nodes.size());
      d.halo_nodes.push_back(node);
      for (std::size_t c = a; c < b; ++c)
        if (node_rank[c].second != d.rank) by_rank[node_rank[c].second].push_back(node);
    }
    a = b;
  }
  d.neighbours.clear();
  d.shared.clear();
  for (int r = 0; r < d.ranks; ++r)
    if (!by_rank[r].empty()) {
      d.neighbours.push_back(r);
      d.shared.push_back(std::move(by_rank[r]));
    }
  d.send.assign(d.neighbours.size(), {});
  d.receive.assign(d.neighbours.size(), {});
  d.counting_rank.assign(d.halo_nodes.size(), -1);
}

std::vector<double> particles_per_element(const Simulation& sim, bool all_ranks) {
  std::vector<double> count(sim.config.mesh.element_count(), 0.0);
  for (int32_t e : sim.particles.element) count[e] += 1;
  if (all_ranks) mpi::sum_in_rank_order(count.data(), count.size());
  return count;
}

// Sends every particle (moving or fixed) whose element another rank owns to it, and rebuilds
// this rank's particles as: kept moving, received moving, kept fixed, received fixed.
void redistribute_all(Simulation& sim, const std::vector<std::size_t>& widths) {
  const Domain& d = sim.domain;
  const Particles& P = sim.particles;
  std::vector<std::string> send(static_cast<std::size_t>(d.ranks));
  std::vector<uint8_t> leaves(P.size(), 0);
  for (std::size_t p = 0; p < P.size(); ++p) {
    const int32_t owner = d.element_owner[P.element[p]];
    if (owner == d.rank) continue;
    leaves[p] = 1;
    pack(P, widths, p, send[owner]);
  }
  long sent = 0;
  for (const auto& bytes : send) sent += static_cast<long>(bytes.size());
  sim.domain.migration_bytes += static_cast<double>(sent);
  const std::vector<std::string> received = mpi::all_to_all(send);
  Particles arrived;
  for (const auto& bytes : received) unpack_all(bytes.data(), bytes.data() + bytes.size(), widths, arrived);
  const auto& fixed = sim.config.body_fixed;
  Particles Q;
  for (int pass = 0; pass < 2; ++pass) {  // moving, then fixed
    std::vector<std::size_t> kept, came;
    for (std::size_t p = 0; p < P.size(); ++p)
      if (!leaves[p] && fixed[P.body[p]] == pass) kept.push_back(p);
    for (std::size_t p = 0; p < arrived.size(); ++p)
      if (fixed[arrived.body[p]] == pass) came.push_back(p);
    append_particles(P, widths, kept, Q);
    append_particles(arrived, widths, came, Q);
  }
  replace_particles(sim, std::move(Q));
}

}  // namespace

void distribute(Simulation& sim) {
  Domain& d = sim.domain;
  d = Domain{};
  d.rank = mpi::rank();
  d.ranks = mpi::size();
  if (d.ranks == 1) return;
  if (sim.config.transfer == Transfer::Xpic && sim.config.xpic_order > 1)
    throw SharedError("mpi: run.transfer = \"xpic\" with run.xpic_order > 1 runs on one rank only (use flip, "
                      "pic_blend or apic with --ranks)");
  // Mixed integration reads the fill of the cells across each cell's edges, which another rank
  // may hold.
  if (sim.config.full_cell_fill > 0)
    throw SharedError("mpi: run.integration = \"mixed\" runs on one rank only (use material_points with --ranks)");
  d.field_width = field_widths(sim.particles);
  d.element_owner = partition_elements(sim.config.mesh, particles_per_element(sim, false), d.ranks);
  // Every rank holds every particle here: keep this rank's, in their order.
  const Particles& P = sim.particles;
  Particles Q;
  const auto& fixed = sim.config.body_fixed;
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::size_t> kept;
    for (std::size_t p = 0; p < P.size(); ++p)
      if (d.element_owner[P.element[p]] == d.rank && fixed[P.body[p]] == pass) kept.push_back(p);
    append_particles(P, d.field_width, kept, Q);
  }
  replace_particles(sim, std::move(Q));
  set_up_halo(d, sim.config.mesh, sim.scratch.stencil);
}

bool rebalance(Simulation& sim) {
  Domain& d = sim.domain;
  if (!d.distributed()) return false;
  const long mine = static_cast<long>(sim.particles.size());
  const long most = mpi::max(mine), total = mpi::sum(mine);
  if (total == 0 || static_cast<double>(most) * d.ranks <= kRepartitionImbalance * static_cast<double>(total))
    return false;
  d.element_owner = partition_elements(sim.config.mesh, particles_per_element(sim, true), d.ranks);
  redistribute_all(sim, d.field_width);
  set_up_halo(d, sim.config.mesh, sim.scratch.stencil);
  ++d.repartitions;
  return true;
}

void migrate_particles(Simulation& sim) {
  Domain& d = sim.domain;
  if (!d.distributed()) return;
  Particles& P = sim.particles;
  std::vector<std::size_t> widths = d.field_width;
  // A frame's velocities travel with their particles (every rank keeps them at the same steps).
  if (sim.scratch.keep_step_velocity) set_width(widths, "step_velocity", 1);
  const std::size_t moving = P.moving_count, n = P.size();
  std::vector<std::string> send(static_cast<std::size_t>(d.ranks));
  std::vector<std::size_t> holes;
  for (std::size_t p = 0; p < moving; ++p) {
    const int32_t owner = d.element_owner[P.element[p]];
    if (owner == d.rank) continue;
    holes.push_back(p);
    pack(P, widths, p, send[owner]);
  }
  double sent = 0;
  for (const auto& bytes : send) sent += static_cast<double>(bytes.size());
  d.migration_bytes += sent;
  d.migrated += static_cast<long>(holes.size());
  const std::vector<std::string> received = mpi::all_to_all(send);
  Particles arrived;
  for (const auto& bytes : received) unpack_all(bytes.data(), bytes.data() + bytes.size(), widths, arrived);
  const std::size_t A = arrived.size(), H = holes.size();
  if (A == 0 && H == 0) return;

  // In place, touching only the particles that move: arrivals fill the holes; more arrivals
  // than holes take the first fixed particles' places (those go to the end); fewer, and the
  // moving particles at the end of the moving range fill the remaining holes, and the last
  // fixed particles close the gap. The fixed particles' order may change; nothing depends on it.
  std::vector<std::pair<std::size_t, std::size_t>> moves;  // (to, from) within P, in order
  std::vector<std::size_t> arrival_slot;                   // where arrival j goes
  const std::size_t F = n - moving;
  std::size_t new_n = n;
  if (A >= H) {
    const std::size_t E = A - H;
    arrival_slot.assign(holes.begin(), holes.end());
    for (std::size_t j = 0; j < E; ++j) arrival_slot.push_back(moving + j);
    if (E >= F) {
      for (std::size_t j = 0; j < F; ++j) moves.emplace_back(moving + E + j, moving + j);
    } else {
      for (std::size_t j = 0; j < E; ++j) moves.emplace_back(n + j, moving + j);
    }
    new_n = n + E;
  } else {
    const std::size_t D = H - A, new_moving = moving - D;
    // The holes below new_moving take the arrivals first, then the kept particles of
    // [new_moving, moving): there are as many of those as holes left.
    std::vector<std::size_t> low;
    std::vector<uint8_t> is_hole(D, 0);
    for (std::size_t h : holes) {
      if (h < new_moving) low.push_back(h);
      else is_hole[h - new_moving] = 1;
    }
    arrival_slot.assign(low.begin(), low.begin() + static_cast<long>(A));
    std::size_t next = A;
    for (std::size_t q = new_moving; q < moving && next < low.size(); ++q)
      if (!is_hole[q - new_moving]) moves.emplace_back(low[next++], q);
    if (D >= F) {
      for (std::size_t j = 0; j < F; ++j) moves.emplace_back(new_moving + j, moving + j);
    } else {
      for (std::size_t j = 0; j < D; ++j) moves.emplace_back(new_moving + j, n - D + j);
    }
    new_n = n - D;
  }
  std::size_t f = 0;
  P.for_each_field_with(arrived, [&](const FieldInfo&, auto& column, const auto& source) {
    const std::size_t w = widths[f++];
    if (w == 0) return;
    if (new_n > n) column.resize(new_n * w);
    for (const auto& [to, from] : moves)
      std::copy_n(column.begin() + static_cast<long>(from * w), w, column.begin() + static_cast<long>(to * w));
    for (std::size_t j = 0; j < A; ++j)
      std::copy_n(source.begin() + static_cast<long>(j * w), w, column.begin() + static_cast<long>(arrival_slot[j] * w));
    if (new_n < n) column.resize(new_n * w);
  });
  particles_changed(sim, false);  // the step fills the moving particles' stencil next
}

// ---- Gathering on rank 0 ---------------------------------------------------------------------

Particles gather_particles(const Simulation& sim, const std::vector<Vec2>* extra, std::vector<Vec2>* extra_all) {
  const Domain& d = sim.domain;
  const Particles& P = sim.particles;
  const std::vector<std::size_t>& widths = d.field_width;
  // [moving count][count] then the packed particles, then the extra values.
  std::string bytes;
  const int64_t header[2] = {static_cast<int64_t>(P.moving_count), static_cast<int64_t>(P.size())};
  bytes.append(reinterpret_cast<const char*>(header), sizeof header);
  bytes.reserve(sizeof header + P.size() * (packed_size(widths) + sizeof(Vec2)));
  for (std::size_t p = 0; p < P.size(); ++p) pack(P, widths, p, bytes);
  if (extra) bytes.append(reinterpret_cast<const char*>(extra->data()), extra->size() * sizeof(Vec2));
  const std::vector<std::string> all = mpi::gather(bytes);
  Particles Q;
  Q.history_width = P.history_width;
  if (d.rank != 0) return Q;
  const std::size_t size = packed_size(widths);
  std::vector<Particles> parts(all.size());
  std::vector<std::vector<Vec2>> extras(all.size());
  std::vector<std::size_t> moving(all.size());
  for (std::size_t r = 0; r < all.size(); ++r) {
    int64_t h[2];
    std::memcpy(h, all[r].data(), sizeof h);
    const char* begin = all[r].data() + sizeof h;
    const std::size_t count = static_cast<std::size_t>(h[1]);
    moving[r] = static_cast<std::size_t>(h[0]);
    unpack_all(begin, begin + count * size, widths, parts[r]);
    if (extra) {
      extras[r].resize(count);
      std::memcpy(static_cast<void*>(extras[r].data()), begin + count * size, count * sizeof(Vec2));
    }
  }
  if (extra_all) extra_all->clear();
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t r = 0; r < all.size(); ++r) {
      const std::size_t from = pass == 0 ? 0 : moving[r], to = pass == 0 ? moving[r] : parts[r].size();
      std::vector<std::size_t> which(to - from);
      std::iota(which.begin(), which.end(), from);
      append_particles(parts[r], widths, which, Q);
      if (extra && extra_all) extra_all->insert(extra_all->end(), extras[r].begin() + from, extras[r].begin() + to);
    }
  Q.moving_count = 0;
  for (std::size_t r = 0; r < all.size(); ++r) Q.moving_count += moving[r];
  return Q;
}

}  // namespace talus::solver
