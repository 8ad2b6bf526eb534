// Frictional contact after Bardenhagen, Brackbill and Sulsky (2000), "The material-point method
// for granular materials", CMAME 187, as summarised in the seed's appendix B and design.md,
// with contact detected from the particles' surfaces rather than from shared nodes alone
// (docs/contact.md).
//
// A "body" below is a velocity field: one body, or a group of bodies bonded by
// [[contact.pairs]] bonded = true that share one field (Grids::field_index, docs/contact.md
// "Bonded pairs"). Contact acts between fields; inside a group nothing slides or separates.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "solver/contact/contact.hpp"
#include "solver/parallel/domain.hpp"

namespace talus::solver {
namespace {

// Against a fixed support, a moving body's normal is the support's face normal where two
// tests hold, else zero (the node is then no contact node for that body):
// - the node lies at the support's surface: the support's mass gradient, times the node's
//   element size, is at least kSurfaceGradient of its mass there. Inside a filled body the
//   gradients cancel (measured 0.02-0.04 at interior nodes, 2.3 at surface nodes and more
//   past them, box_incline_level with CPDI at 0.025 m) and what is left is the particles'
//   scatter, a normal in no particular direction;
// - with a stencil wider than the particle's element (B-splines, CPDI), the moving body's own
//   outward normal there (its mass gradient) is within 45 degrees of the face normal. A body
//   resting on a face has its own normal along the face's, tilted by up to 45 degrees at its
//   own right-angled corners. More than that, and the node lies round a corner of the support,
//   where the support's gradient turns to the corner's other face, which the body does not
//   press on: its sliding would read as approach there. Linear triangles put a body's mass
//   only on the nodes of the elements it lies in, whose shapes alone tilt its normal at its
//   corners by more than 45 degrees on Delaunay meshes (the test would drop those nodes and
//   raise the box's early error at mu = 0.4 from 1.3 to 2.2 %), and do not reach round the
//   support's corners (docs/contact.md, "Rigid support").
constexpr double kSurfaceGradient = 0.25;
constexpr double kCornerCosine = 0.7071067811865476;  // cos 45 degrees

// The outward unit normal of every moving body at node i (zero for fixed bodies, where the
// gradients cancel, and against a fixed support where the tests above fail), written to
// normal[b].
//
// sum_p m_p grad N_ip points from a body's particles towards the node: the body's outward
// normal. One consistent normal per pair: b's outward normal minus the others' (which point
// into b), so that the pair's two normals are opposite. Against a fixed support its face gives
// the normal alone: a moving body's own normal tilts at its corners, where tangential sliding
// would otherwise read as approach.
void outward_normals(const ContactRules& rules, const Grids& grids, int32_t i, Vec2* normal) {
  const std::size_t bodies = grids.fields.size();
  bool rigid = false;
  double rigid_mass = 0;
  Vec2 gradient_sum = Vec2::Zero(), rigid_gradient = Vec2::Zero();
  for (std::size_t b = 0; b < bodies; ++b) {
    const Grid& grid = grids.fields[b];
    if (grid.m[i] <= 0) continue;
    rigid = rigid || rules.field_fixed[b];
    if (rules.field_fixed[b]) rigid_gradient += grid.mass_gradient[i], rigid_mass += grid.m[i];
    gradient_sum += grid.mass_gradient[i];
  }
  const bool at_surface = !rigid || rigid_gradient.norm() * rules.node_length[i] >= kSurfaceGradient * rigid_mass;
  for (std::size_t b = 0; b < bodies; ++b) {
    const Grid& grid = grids.fields[b];
    normal[b].setZero();
    if (grid.m[i] <= 0 || rules.field_fixed[b] || !at_surface) continue;
    const Vec2 n = rigid ? Vec2(-rigid_gradient) : Vec2(grid.mass_gradient[i] - (gradient_sum - grid.mass_gradient[i]));
    const double length = n.norm();
    if (length <= 0) continue;
    const Vec2& own = grid.mass_gradient[i];
    if (rigid && rules.wide_stencil && own.dot(n) < kCornerCosine * own.norm() * length) continue;  // round a corner
    normal[b] = n / length;
  }
}

// Corrects the velocities `velocity(b)` of the bodies touching at the k-th contact node i
// against the reference (their centre of mass, or zero where a fixed body is among them).
// `on_change(b, delta)` receives each body's correction, already stripped of any component
// the node's constraint forbids.
template <class Velocity, class OnChange>
void correct_node(const ContactRules& rules, const ContactScratch& contact, const Grids& grids, std::size_t k,
                  int32_t i, Velocity velocity, OnChange on_change) {
  const std::size_t bodies = grids.fields.size();
  const uint8_t* touching = &contact.touching[k * bodies];
  const Vec2* normal = &contact.normal[k * bodies];
  bool rigid = false;
  double m = 0;
  Vec2 momentum = Vec2::Zero();
  for (std::size_t b = 0; b < bodies; ++b) {
    if (!touching[b]) continue;
    if (rules.field_fixed[b]) {
      rigid = true;
      continue;
    }
    const Grid& grid = grids.fields[b];
    m += grid.m[i];
    momentum += grid.m[i] * velocity(b);
  }
  const Vec2 reference = rigid ? Vec2::Zero() : Vec2(momentum / m);

  for (std::size_t b = 0; b < bodies; ++b) {
    if (!touching[b] || rules.field_fixed[b]) continue;
    const Vec2 dv = velocity(b) - reference;
    const double approach = dv.dot(normal[b]);
    if (approach <= 0) continue;  // separating: free
    // Friction against the first other body touching at the node (pairs are per scene).
    double mu = 0;
    for (std::size_t c = 0; c < bodies; ++c)
      if (c != b && touching[c]) {
        mu = rules.pair_friction[b][c];
        break;
      }
    const Vec2 tangential = dv - approach * normal[b];
    const double slip = tangential.norm();
    Vec2 delta;
    if (slip <= mu * approach) delta = -dv;  // stick: move with the reference
    else delta = -approach * normal[b] - mu * approach * tangential / slip;  // slide, Coulomb-limited
    // The velocity before the correction obeys the node's constraint; the correction must too,
    // or contact would push a body through a fixed or roller boundary.
    constrain_change(rules.constraints, i, delta);
    on_change(b, delta);
  }
}

}  // namespace

void find_contact_nodes(const ContactRules& rules, const Particles& P, const Stencil& S, const Grids& grids,
                        ContactScratch& contact, int threads, Domain* domain) {
  const std::size_t bodies = grids.fields.size();
  std::vector<int32_t>& contact_nodes = contact.nodes;
  // Candidates: the nodes where two or more bodies have mass (serial: one look at each active
  // node's body masses is small beside P2G).
  contact_nodes.clear();
  for (int32_t i : grids.active) {
    int present = 0;
    for (std::size_t b = 0; b < bodies && present < 2; ++b) present += grids.fields[b].m[i] > 0;
    if (present >= 2) contact_nodes.push_back(i);
  }
  const std::size_t candidates = contact_nodes.size();
  if (candidates == 0 && !domain) return;  // bodies apart: no particle pass (ranks still swap extents)

  auto& slot = contact.slot;
  if (slot.size() != grids.fields[0].m.size()) slot.assign(grids.fields[0].m.size(), -1);
  contact.normal.resize(candidates * bodies);
  for (std::size_t k = 0; k < candidates; ++k) {
    slot[contact_nodes[k]] = static_cast<int32_t>(k);
    outward_normals(rules, grids, contact_nodes[k], &contact.normal[k * bodies]);
  }

  // Each body's extent along each moving body's normal at the candidates: how far body b
  // reaches towards the others (its front, [b][b]), and where each other body c begins
  // ([b][c]). A particle reaches half its size, sqrt(V_p) / 2, beyond its centre. Maxima and
  // minima do not depend on the order of the threads.
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const std::size_t width = candidates * bodies * bodies;
  contact.extents.resize(static_cast<std::size_t>(threads));
  auto& runs = contact.fixed_runs;
  if (runs.empty() || runs.back() != P.size() || runs.front() != P.moving_count) {
    runs.clear();
    for (std::size_t p = P.moving_count; p < P.size(); ++p)
      if (p == P.moving_count || S.row[p] != S.row[p - 1]) runs.push_back(p);
    runs.push_back(P.size());
  }
  const long moving = static_cast<long>(P.moving_count), fixed_runs = static_cast<long>(runs.size()) - 1;
  with_width(S, [&](auto W) {
    auto touches = [&](std::size_t p) {  // does p's stencil hold a candidate?
      const int32_t* nodes = S.nodes(p);
      bool any = false;
      for (int j = 0; j < W; ++j) any = any || slot[nodes[j]] >= 0;
      return any;
    };
    auto extend = [&](std::size_t p, std::vector<double>& extent) {
      const int32_t* nodes = S.nodes(p);
      const std::size_t c = static_cast<std::size_t>(grids.field_of(P.body[p]));
      const double reach = 0.5 * std::sqrt(P.volume[p]);
      for (int j = 0; j < W; ++j) {
        const int32_t k = slot[nodes[j]];
        if (k < 0) continue;
        for (std::size_t b = 0; b < bodies; ++b) {
          const Vec2& normal = contact.normal[k * bodies + b];
          if (normal.isZero()) continue;
          const double along = P.x[p].dot(normal);
          double& e = extent[(k * bodies + b) * bodies + c];
          e = b == c ? std::max(e, along + reach) : std::min(e, along - reach);
        }
      }
    };
#pragma omp parallel num_threads(threads)
  {
    std::vector<double>& extent = contact.extents[omp_get_thread_num()];
    extent.resize(width);
    for (std::size_t e = 0; e < width; e += bodies)
      for (std::size_t c = 0; c < bodies; ++c) extent[e + c] = (e / bodies) % bodies == c ? -kInfinity : kInfinity;
    int32_t last_row = -1;  // particles sorted by element mostly share their row with the one before
    bool row_touches = false;
#pragma omp for schedule(static) nowait
    for (long p = 0; p < moving; ++p) {
      if (S.row[p] != last_row) {
        last_row = S.row[p];
        row_touches = touches(p);
      }
      if (row_touches) extend(p, extent);
    }
#pragma omp for schedule(static)
    for (long r = 0; r < fixed_runs; ++r)
      if (touches(runs[r]))
        for (std::size_t p = runs[r]; p < runs[r + 1]; ++p) extend(p, extent);
  }
  });

  if (domain) exchange_contact_extents(*domain, contact_nodes, bodies, contact);

  // Body b touches body c at a node when c begins before b's front ends along b's normal.
  // A fixed body takes part where a moving body touches it.
  contact.touching.assign(candidates * bodies, 0);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < candidates; ++k) {
    slot[contact_nodes[k]] = -1;
    uint8_t* touching = &contact.touching[kept * bodies];
    bool any = false;
    for (std::size_t b = 0; b < bodies; ++b) {
      if (contact.normal[k * bodies + b].isZero()) continue;
      const std::size_t row = (k * bodies + b) * bodies;
      double front = -kInfinity;
      for (const auto& extent : contact.extents) front = std::max(front, extent[row + b]);
      for (std::size_t c = 0; c < bodies; ++c) {
        if (c == b) continue;
        double begins = kInfinity;
        for (const auto& extent : contact.extents) begins = std::min(begins, extent[row + c]);
        if (begins <= front) touching[b] = touching[c] = 1, any = true;
      }
    }
    if (!any) {
      std::fill(touching, touching + bodies, 0);
      continue;
    }
    for (std::size_t b = 0; b < bodies; ++b)
      contact.normal[kept * bodies + b] = contact.normal[k * bodies + b];
    contact_nodes[kept++] = contact_nodes[k];
  }
  contact_nodes.resize(kept);
  contact.touching.resize(kept * bodies);
}

void apply_contact(const ContactRules& rules, double dt, const ContactScratch& contact, Grids& grids, int threads) {
  const std::vector<int32_t>& nodes = contact.nodes;
  const long count = static_cast<long>(nodes.size());
  if (count == 0) return;  // bodies apart: not even a thread team
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    const int32_t i = nodes[k];
    auto trial_velocity = [&](std::size_t b) -> Vec2 {
      const Grid& grid = grids.fields[b];
      return grid.p[i] / grid.m[i] + dt * grid.a[i];
    };
    correct_node(rules, contact, grids, static_cast<std::size_t>(k), i, trial_velocity,
                 [&](std::size_t b, const Vec2& delta) { grids.fields[b].a[i] += delta / dt; });
  }
}

void apply_contact_velocities(const ContactRules& rules, const ContactScratch& contact, Grids& grids, int threads) {
  const std::vector<int32_t>& nodes = contact.nodes;
  const long count = static_cast<long>(nodes.size());
  if (count == 0) return;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long k = 0; k < count; ++k) {
    const int32_t i = nodes[k];
    correct_node(rules, contact, grids, static_cast<std::size_t>(k), i,
                 [&](std::size_t b) -> Vec2 { return grids.fields[b].v[i]; },
                 [&](std::size_t b, const Vec2& delta) { grids.fields[b].v[i] += delta; });
  }
}

std::vector<double> element_lengths_at_nodes(const Mesh& mesh) {
  std::vector<double> area(mesh.node_count(), 0.0);
  std::vector<int> count(mesh.node_count(), 0);
  for (std::size_t e = 0; e < mesh.element_count(); ++e)
    for (int32_t i : mesh.triangles[e]) area[i] += mesh.area[e], ++count[i];
  for (std::size_t i = 0; i < area.size(); ++i) area[i] = count[i] > 0 ? std::sqrt(2 * area[i] / count[i]) : 0.0;
  return area;
}

}  // namespace talus::solver
