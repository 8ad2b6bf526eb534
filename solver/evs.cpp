// Enhanced volumetric strain against the volumetric locking of linear triangles (Detournay and
// Dzik 2006; seed section 4; design.md): the volumetric strain increment of each cell
// (volume-weighted over its particles) -> nodes (area-weighted over the cells with particles)
// -> back to each particle as the mean over its stencil's nodes (for linear triangles: its
// cell's three nodes) -> replaces the volumetric part of the particle's increment.
#include <omp.h>

#include "solver/step.hpp"

#include <cstdlib>

namespace talus::solver {

namespace {
// EXPERIMENT (issue 13, item 6; reverted by the next commit; docs/slope.md's table names this
// commit). TALUS_EVS_MODE selects a variant of the smoothing, serial and for one thread:
//   0 or unset: the EVS of main; 4: the same through the serial code (bit-identical, a check)
//   1, 5: the volumetric strain smoothed cells -> nodes -> cells -> nodes (2 passes), 3 passes
//   7: TALUS_EVS_PASSES passes (1, 4, 16 at h = 0.5, 0.25, 0.125: a fixed smoothing length)
//   2: one pass, the particle's value interpolated with N_ip instead of its cell's node mean
//   3: the whole in-plane strain increment smoothed (one pass); 6: the same, TALUS_EVS_PASSES
//   8: EVS and the particles' mean stress smoothed the same way (cells -> nodes -> particle)
int experiment_mode() {
  static const int mode = std::getenv("TALUS_EVS_MODE") ? std::atoi(std::getenv("TALUS_EVS_MODE")) : 0;
  return mode;
}

// Serial experiment: smooth components [0, count) of a per-particle quantity over node patches.
void smooth_components(const Mesh& mesh, const Particles& P, const Stencil& S, std::vector<Vec4>& d_eps,
                       int passes, bool interpolate, bool full) {
  const long moving = static_cast<long>(P.moving_count);
  const std::size_t elements = mesh.element_count(), nodes = mesh.nodes.size();
  static std::vector<Vec4> e_val, n_val;
  static std::vector<double> e_vol, n_area;
  e_val.assign(elements, Vec4::Zero());
  e_vol.assign(elements, 0);
  for (long p = 0; p < moving; ++p) {
    const int32_t e = P.element[p];
    const double V = P.volume[p];
    const Vec4& d = d_eps[p];
    e_val[e] += V * (full ? d : Vec4(d[0] + d[1], 0, 0, 0));
    e_vol[e] += V;
  }
  for (std::size_t e = 0; e < elements; ++e)
    if (e_vol[e] > 0) e_val[e] /= e_vol[e];
  for (int pass = 0; pass < passes; ++pass) {
    n_val.assign(nodes, Vec4::Zero());
    n_area.assign(nodes, 0);
    for (std::size_t e = 0; e < elements; ++e) {
      if (e_vol[e] <= 0) continue;
      for (int32_t i : mesh.triangles[e]) {
        n_val[i] += mesh.area[e] * e_val[e];
        n_area[i] += mesh.area[e];
      }
    }
    for (std::size_t i = 0; i < nodes; ++i)
      if (n_area[i] > 0) n_val[i] /= n_area[i];
    if (pass + 1 < passes)
      for (std::size_t e = 0; e < elements; ++e) {
        if (e_vol[e] <= 0) continue;
        Vec4 m = Vec4::Zero();
        for (int32_t i : mesh.triangles[e]) m += n_val[i] / 3.0;
        e_val[e] = m;
      }
  }
  const int W = S.width;
  for (long p = 0; p < moving; ++p) {
    const int32_t* nd = S.nodes(p);
    const double* N = S.weights(p);
    Vec4 sm = Vec4::Zero();
    for (int k = 0; k < W; ++k) sm += (interpolate ? N[k] : 1.0 / W) * n_val[nd[k]];
    Vec4& d = d_eps[p];
    if (full) {
      d = sm;
    } else {
      const double correction = 0.5 * (sm[0] - (d[0] + d[1]));
      d[0] += correction;
      d[1] += correction;
    }
  }
}
}  // namespace

void enhance_volumetric_strain(const Mesh& mesh, const Particles& P, const Stencil& S,
                               const std::vector<int32_t>& active, EvsScratch& evs, std::vector<Vec4>& d_eps,
                               int threads) {
  switch (experiment_mode()) {
    case 1: return smooth_components(mesh, P, S, d_eps, 2, false, false);
    case 2: return smooth_components(mesh, P, S, d_eps, 1, true, false);
    case 3: return smooth_components(mesh, P, S, d_eps, 1, false, true);
    case 5: return smooth_components(mesh, P, S, d_eps, 3, false, false);
    case 6: return smooth_components(mesh, P, S, d_eps, std::atoi(std::getenv("TALUS_EVS_PASSES")), false, true);
    case 7: return smooth_components(mesh, P, S, d_eps, std::atoi(std::getenv("TALUS_EVS_PASSES")), false, false);
    case 8: {
      smooth_components(mesh, P, S, d_eps, 1, false, false);
      // Pressure smoothing of the current stress: the mean in-plane+zz stress over node patches.
      Particles& Q = const_cast<Particles&>(P);
      const long moving = static_cast<long>(P.moving_count);
      std::vector<Vec4> pressure(moving);
      for (long p = 0; p < moving; ++p) pressure[p] = Vec4((P.sigma[p][0] + P.sigma[p][1] + P.sigma[p][2]) / 3, 0, 0, 0);
      std::vector<Vec4> copy = pressure;
      // reuse: smooth_components "full" replaces the vector by its node-smoothed value
      smooth_components(mesh, P, S, copy, 1, false, true);
      for (long p = 0; p < moving; ++p) {
        const double shift = copy[p][0] - pressure[p][0];
        Q.sigma[p][0] += shift; Q.sigma[p][1] += shift; Q.sigma[p][2] += shift;
      }
      return;
    }
    case 4: return smooth_components(mesh, P, S, d_eps, 1, false, false);
    default: break;
  }
  const long moving = static_cast<long>(P.moving_count);
  const long elements = static_cast<long>(mesh.element_count());
  // Cell sums: each thread into its own arrays, then added in thread order (deterministic).
#pragma omp parallel num_threads(threads)
  {
    std::vector<double>& strain = evs.element_strain[omp_get_thread_num()];
    std::vector<double>& volume = evs.element_volume[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long p = 0; p < moving; ++p) {
      const int32_t e = P.element[p];
      const double V = P.volume[p];
      strain[e] += V * (d_eps[p][0] + d_eps[p][1]);
      volume[e] += V;
    }
    const std::size_t team = evs.element_strain.size();
#pragma omp for schedule(static)
    for (long e = 0; e < elements; ++e) {
      double strain_sum = 0, volume_sum = 0;
      for (std::size_t t = 0; t < team; ++t) {
        strain_sum += evs.element_strain[t][e];
        volume_sum += evs.element_volume[t][e];
        evs.element_strain[t][e] = evs.element_volume[t][e] = 0;
      }
      evs.strain[e] = strain_sum;
      evs.volume[e] = volume_sum;
    }
  }
  for (int32_t i : active) evs.node_strain[i] = evs.node_area[i] = 0;
  for (long e = 0; e < elements; ++e) {
    if (evs.volume[e] <= 0) continue;
    const double strain = evs.strain[e] / evs.volume[e];
    for (int32_t i : mesh.triangles[e]) {
      evs.node_strain[i] += mesh.area[e] * strain;
      evs.node_area[i] += mesh.area[e];
    }
  }
  const int W = S.width;
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long p = 0; p < moving; ++p) {
    const int32_t* nodes = S.nodes(p);
    double smoothed = 0;
    for (int k = 0; k < W; ++k) smoothed += evs.node_strain[nodes[k]] / evs.node_area[nodes[k]];
    smoothed /= W;
    Vec4& d = d_eps[p];
    const double correction = 0.5 * (smoothed - (d[0] + d[1]));  // in-plane, so d_eps_zz stays 0
    d[0] += correction;
    d[1] += correction;
  }
}

}  // namespace talus::solver
