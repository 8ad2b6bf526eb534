// Frictional contact after Bardenhagen, Brackbill and Sulsky (2000), "The material-point method
// for granular materials", CMAME 187, as summarised in the seed's appendix B and design.md.
#include <cmath>

#include "solver/step.hpp"

namespace talus::solver {
namespace {

// Corrects the velocities `velocity(b)` of the bodies at contact node i against the reference
// (centre-of-mass, or zero where a fixed body is present). `on_change(b, delta)` receives
// each body's correction, already stripped of any component the node's constraint forbids.
template <class Velocity, class OnChange>
void correct_node(const ContactRules& rules, const Grids& grids, int32_t i, Velocity velocity, OnChange on_change) {
  const std::size_t bodies = grids.fields.size();
  bool rigid = false;
  double m = 0;
  Vec2 momentum = Vec2::Zero(), gradient_sum = Vec2::Zero(), rigid_gradient = Vec2::Zero();
  for (std::size_t b = 0; b < bodies; ++b) {
    const Grid& grid = grids.fields[b];
    if (grid.m[i] <= 0) continue;
    rigid = rigid || rules.body_fixed[b];
    if (rules.body_fixed[b]) rigid_gradient += grid.mass_gradient[i];
    m += grid.m[i];
    momentum += grid.m[i] * velocity(b);
    gradient_sum += grid.mass_gradient[i];
  }
  const Vec2 reference = rigid ? Vec2::Zero() : Vec2(momentum / m);

  for (std::size_t b = 0; b < bodies; ++b) {
    const Grid& grid = grids.fields[b];
    if (grid.m[i] <= 0 || rules.body_fixed[b]) continue;
    // sum_p m_p grad N_ip points from a body's particles towards the node: the body's outward
    // normal. One consistent normal per pair: b's outward normal minus the others' (which
    // point into b), so that the pair's two normals are opposite.
    // Against a fixed support its face gives the normal alone: a moving body's own normal tilts
    // at its corners, where tangential sliding would otherwise read as approach.
    Vec2 normal = rigid ? Vec2(-rigid_gradient) : Vec2(grid.mass_gradient[i] - (gradient_sum - grid.mass_gradient[i]));
    const double length = normal.norm();
    if (length <= 0) continue;
    normal /= length;
    const Vec2 dv = velocity(b) - reference;
    const double approach = dv.dot(normal);
    if (approach <= 0) continue;  // separating: free
    // Friction against the first other body present at the node (pairs are per scene).
    double mu = 0;
    for (std::size_t c = 0; c < bodies; ++c)
      if (c != b && grids.fields[c].m[i] > 0) {
        mu = rules.pair_friction[b][c];
        break;
      }
    const Vec2 tangential = dv - approach * normal;
    const double slip = tangential.norm();
    Vec2 delta;
    if (slip <= mu * approach) delta = -dv;  // stick: move with the reference
    else delta = -approach * normal - mu * approach * tangential / slip;  // slide, Coulomb-limited
    // The velocity before the correction obeys the node's constraint; the correction must too,
    // or contact would push a body through a fixed or roller boundary.
    constrain_change(rules.constraints, i, delta);
    on_change(b, delta);
  }
}

}  // namespace

void find_contact_nodes(const Grids& grids, std::vector<int32_t>& contact_nodes) {
  // Serial: one look at each active node's body masses is small beside P2G.
  const std::size_t bodies = grids.fields.size();
  contact_nodes.clear();
  for (int32_t i : grids.active) {
    int present = 0;
    for (std::size_t b = 0; b < bodies && present < 2; ++b) present += grids.fields[b].m[i] > 0;
    if (present >= 2) contact_nodes.push_back(i);
  }
}

void apply_contact(const ContactRules& rules, double dt, const std::vector<int32_t>& nodes, Grids& grids,
                   int threads) {
  const long count = static_cast<long>(nodes.size());
  if (count == 0) return;  // bodies apart: not even a thread team
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    const int32_t i = nodes[k];
    auto trial_velocity = [&](std::size_t b) -> Vec2 {
      const Grid& grid = grids.fields[b];
      return grid.p[i] / grid.m[i] + dt * grid.a[i];
    };
    correct_node(rules, grids, i, trial_velocity,
                 [&](std::size_t b, const Vec2& delta) { grids.fields[b].a[i] += delta / dt; });
  }
}

void apply_contact_velocities(const ContactRules& rules, const std::vector<int32_t>& nodes, Grids& grids,
                              int threads) {
  const long count = static_cast<long>(nodes.size());
  if (count == 0) return;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    const int32_t i = nodes[k];
    correct_node(rules, grids, i, [&](std::size_t b) -> Vec2 { return grids.fields[b].v[i]; },
                 [&](std::size_t b, const Vec2& delta) { grids.fields[b].v[i] += delta; });
  }
}

}  // namespace talus::solver
