#include "solver/boundary/absorbing.hpp"

#include "solver/parallel/mpi.hpp"

namespace talus::solver {

namespace {

bool active(const Scratch& s, int32_t i) { return s.node_stamp[i] == s.stamp; }

// Takes the momentum rate of the model without the absorbing nodes out of the reactions just
// recorded (apply_dashpots), and out of this step's accelerations of those nodes.
void balance_reactions(Simulation& sim) {
  const AbsorbingNodes& d = sim.config.absorbing;
  Scratch& s = sim.scratch;
  Grids& grids = s.grids;
  const std::size_t n = d.node.size(), fields = grids.fields.size();
  std::vector<uint8_t> absorbing(sim.config.mesh.nodes.size(), 0);
  for (int32_t i : d.node) absorbing[i] = 1;
  double rate[2] = {0, 0};
  for (const Grid& grid : grids.fields)
    for (int32_t i : grids.active)
      if (!absorbing[i] && grid.m[i] > 0 && sim.domain.counts(i))
        rate[0] += grid.m[i] * grid.a[i].x(), rate[1] += grid.m[i] * grid.a[i].y();
  if (sim.domain.distributed()) mpi::sum_in_rank_order(rate, 2);
  const Vec2 F(rate[0], rate[1]);
  double total = 0;
  for (double w : s.absorbing_weight) total += w;
  if (!(total > 0)) return;
  for (std::size_t field = 0; field < fields; ++field) {
    Grid& grid = grids.fields[field];
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t e = field * n + k;
      const Vec2 change = -(s.absorbing_weight[e] / total) * F;
      sim.absorbing_reaction[e] += change;
      const int32_t i = d.node[k];
      if (active(s, i) && grid.m[i] > 0) grid.a[i] += change / grid.m[i];
    }
  }
}

}  // namespace

void apply_static_reactions(Simulation& sim) {
  Config& c = sim.config;
  const AbsorbingNodes& d = c.absorbing;
  if (d.empty()) return;
  std::vector<Constraint>& kind = c.constraints.kind;
  if (sim.time < c.gravity_ramp) {  // gravity still rising: held fixed
    if (sim.absorbing_kind.empty()) {
      for (int32_t i : d.node) sim.absorbing_kind.push_back(kind[i]);
      for (int32_t i : d.node) kind[i] = Constraint::Fixed;
    }
    return;
  }
  if (!sim.absorbing_kind.empty()) {  // the switch: their own kinds back
    for (std::size_t k = 0; k < d.node.size(); ++k) kind[d.node[k]] = sim.absorbing_kind[k];
    sim.absorbing_kind.clear();
  }
  Scratch& s = sim.scratch;
  Grids& grids = s.grids;
  const std::size_t n = d.node.size(), fields = grids.fields.size();
  if (sim.absorbing_reaction.empty()) {
    // -f_i where the field has mass; on several ranks each rank that has the node active holds
    // the summed f_i, and the mean over them is the same number on every rank.
    std::vector<double> sums(3 * n * fields, 0.0);
    for (std::size_t field = 0; field < fields; ++field)
      for (std::size_t k = 0; k < n; ++k) {
        const int32_t i = d.node[k];
        const Grid& grid = grids.fields[field];
        if (!active(s, i) || !(grid.m[i] > 0)) continue;
        double* sum = &sums[3 * (field * n + k)];
        sum[0] = -grid.f[i].x(), sum[1] = -grid.f[i].y(), sum[2] = 1;
      }
    if (sim.domain.distributed()) mpi::sum_in_rank_order(sums.data(), sums.size());
    sim.absorbing_reaction.assign(n * fields, Vec2::Zero());
    s.absorbing_weight.assign(n * fields, 0.0);
    for (std::size_t e = 0; e < n * fields; ++e)
      if (sums[3 * e + 2] > 0) {
        sim.absorbing_reaction[e] = Vec2(sums[3 * e], sums[3 * e + 1]) / sums[3 * e + 2];
        s.absorbing_weight[e] = d.length[e % n];
      }
    s.absorbing_balance = true;  // apply_dashpots, this step
  }
  for (std::size_t field = 0; field < fields; ++field) {
    Grid& grid = grids.fields[field];
    for (std::size_t k = 0; k < n; ++k) {
      const int32_t i = d.node[k];
      if (active(s, i) && grid.m[i] > 0) grid.f[i] += sim.absorbing_reaction[field * n + k];
    }
  }
}

void apply_dashpots(Simulation& sim, double dt) {
  if (sim.scratch.absorbing_balance) {
    sim.scratch.absorbing_balance = false;
    balance_reactions(sim);
  }
  if (!(dt > 0) || !sim.absorbing_kind.empty()) return;  // held fixed: no dashpots yet
  const AbsorbingNodes& d = sim.config.absorbing;
  const BaseMotion& motion = sim.config.base_motion;
  const Vec2 ground = motion.compliant ? motion.ground_velocity(sim.time + dt) : Vec2::Zero();
  for (Grid& grid : sim.scratch.grids.fields)
    for (std::size_t k = 0; k < d.node.size(); ++k) {
      const int32_t i = d.node[k];
      const double m = grid.m[i];
      if (!(m > 0)) continue;
      const Vec2 n = d.normal[k], tangent(-n.y(), n.x());
      const Vec2 v = grid.p[i] / m, free = v + dt * grid.a[i];
      const Vec2 reference = d.input[k] ? ground : Vec2::Zero();
      const double c_n = d.length[k] * d.impedance[k].x(), c_t = d.length[k] * d.impedance[k].y();
      const double v_n = (m * free.dot(n) + dt * c_n * reference.dot(n)) / (m + dt * c_n);
      const double v_t = (m * free.dot(tangent) + dt * c_t * reference.dot(tangent)) / (m + dt * c_t);
      grid.a[i] = (v_n * n + v_t * tangent - v) / dt;
    }
}

}  // namespace talus::solver
