// The halo exchanges of a distributed step (domain.hpp): the nodal sums at the nodes shared
// between ranks, added in rank order so that every rank holds the same bits.
#include <algorithm>
#include <limits>

#include "solver/parallel/domain.hpp"

namespace talus::solver {

void exchange_grid_sums(Simulation& sim) {
  Domain& d = sim.domain;
  Scratch& s = sim.scratch;
  Grids& grids = s.grids;
  const bool gradients = grids.per_body;
  const int per_field = gradients ? 7 : 5;
  const int fields = static_cast<int>(grids.fields.size());
  const int width = fields * per_field + 1;
  const int32_t stamp = s.stamp;
  auto active = [&](int32_t i) { return s.node_stamp[i] == stamp; };
  halo_exchange(
      d, width,
      [&](int32_t i, double* out) {
        if (!active(i)) {
          std::fill(out, out + width, 0.0);
          return;
        }
        for (int b = 0; b < fields; ++b) {
          const Grid& g = grids.fields[b];
          double* o = out + b * per_field;
          o[0] = g.m[i];
          o[1] = g.p[i].x(), o[2] = g.p[i].y();
          o[3] = g.f[i].x(), o[4] = g.f[i].y();
          if (gradients) o[5] = g.mass_gradient[i].x(), o[6] = g.mass_gradient[i].y();
        }
        out[width - 1] = 1;
      },
      [&](int32_t i, const double* in) {
        for (int b = 0; b < fields; ++b) {
          Grid& g = grids.fields[b];
          const double* o = in + b * per_field;
          g.m[i] = o[0];
          g.p[i] = Vec2(o[1], o[2]);
          g.f[i] = Vec2(o[3], o[4]);
          if (gradients) g.mass_gradient[i] = Vec2(o[5], o[6]);
        }
      },
      active, add_in_order, width - 1);
}

void exchange_remap_momentum(Simulation& sim) {
  Domain& d = sim.domain;
  Scratch& s = sim.scratch;
  Grids& grids = s.grids;
  const int fields = static_cast<int>(grids.fields.size());
  const int32_t stamp = s.stamp;
  auto active = [&](int32_t i) { return s.node_stamp[i] == stamp; };
  halo_exchange(
      d, 2 * fields,
      [&](int32_t i, double* out) {
        for (int b = 0; b < fields; ++b) {
          const Vec2 v = active(i) ? grids.fields[b].v[i] : Vec2::Zero();
          out[2 * b] = v.x(), out[2 * b + 1] = v.y();
        }
      },
      [&](int32_t i, const double* in) {
        for (int b = 0; b < fields; ++b) grids.fields[b].v[i] = Vec2(in[2 * b], in[2 * b + 1]);
      },
      active, add_in_order);
}

void exchange_evs_sums(Simulation& sim) {
  Domain& d = sim.domain;
  Scratch& s = sim.scratch;
  EvsScratch& evs = s.evs;
  const int32_t stamp = s.stamp;
  auto active = [&](int32_t i) { return s.node_stamp[i] == stamp; };
  halo_exchange(
      d, 2,
      [&](int32_t i, double* out) {
        out[0] = active(i) ? evs.node_strain[i] : 0.0;
        out[1] = active(i) ? evs.node_area[i] : 0.0;
      },
      [&](int32_t i, const double* in) {
        evs.node_strain[i] = in[0];
        evs.node_area[i] = in[1];
      },
      active, add_in_order);
}

void exchange_contact_extents(Domain& d, const std::vector<int32_t>& candidates, std::size_t bodies,
                              ContactScratch& contact) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const std::size_t row = bodies * bodies;
  // The threads' extents into extents[0], which alone is read afterwards.
  auto& first = contact.extents[0];
  for (std::size_t t = 1; t < contact.extents.size(); ++t)
    for (std::size_t j = 0; j < candidates.size() * row; ++j) {
      const std::size_t b = (j / bodies) % bodies, c = j % bodies;
      first[j] = b == c ? std::max(first[j], contact.extents[t][j]) : std::min(first[j], contact.extents[t][j]);
    }
  contact.extents.resize(1);
  const auto& slot = contact.slot;
  halo_exchange(
      d, static_cast<int>(row),
      [&](int32_t i, double* out) {
        const int32_t k = slot[i];
        for (std::size_t j = 0; j < row; ++j)
          out[j] = k >= 0 ? first[k * row + j] : (j / bodies == j % bodies ? -kInfinity : kInfinity);
      },
      [&](int32_t i, const double* in) { std::copy_n(in, row, first.begin() + static_cast<long>(slot[i] * row)); },
      [&](int32_t i) { return slot[i] >= 0; },
      [&](double& acc, double value, int j) {
        const std::size_t b = static_cast<std::size_t>(j) / bodies, c = static_cast<std::size_t>(j) % bodies;
        acc = b == c ? std::max(acc, value) : std::min(acc, value);
      });
}

}  // namespace talus::solver
