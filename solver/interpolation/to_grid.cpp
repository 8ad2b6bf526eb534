// Particles to grid (seed, A.6-A.8): the nodes the particles touch this step, and the mass,
// momentum and force each velocity field gathers there.
#include <omp.h>

#include <atomic>

#include "solver/interpolation/interpolation.hpp"
#include "solver/interpolation/runs.hpp"

namespace talus::solver {

void mark_active_nodes(const Stencil& stencil, std::size_t particles, std::vector<int32_t>& node_stamp,
                       int32_t& stamp, Grids& grids, int threads) {
  ++stamp;
  const int32_t current = stamp;
  const long nodes = static_cast<long>(node_stamp.size());
  std::vector<int32_t>& offsets = grids.active_offsets;
  offsets.assign(static_cast<std::size_t>(threads) + 1, 0);
  with_width(stencil, [&](auto W) {
#pragma omp parallel num_threads(threads)
  {
    const StencilView S(stencil, W);  // and the rest the loop reads, taken once in the region
    const long n = static_cast<long>(particles);
    const int32_t mark = current;
    int32_t* const stamps = node_stamp.data();
#pragma omp for schedule(static)
    for (long p = 0; p < n; ++p) {
      // Particles sorted by element mostly share their row with the one before: its nodes are marked.
      if (p > 0 && S.row(p) == S.row(p - 1)) continue;
      const int32_t* nodes_of_p = S.nodes(p);
      for (int k = 0; k < W; ++k)
        std::atomic_ref<int32_t>(stamps[nodes_of_p[k]]).store(mark, std::memory_order_relaxed);
    }
    // The list, ascending: each thread counts the marked nodes of its own range of the node
    // numbers, then writes them from the offset the counts before its range give.
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    const long begin = nodes * t / team, end = nodes * (t + 1) / team;
    int32_t count = 0;
    for (long i = begin; i < end; ++i) count += stamps[i] == mark;
    offsets[t + 1] = count;
#pragma omp barrier
#pragma omp single
    {
      for (int k = 0; k < team; ++k) offsets[k + 1] += offsets[k];
      grids.active.resize(static_cast<std::size_t>(offsets[team]));
    }
    int32_t* out = grids.active.data() + offsets[t];
    for (long i = begin; i < end; ++i)
      if (stamps[i] == mark) *out++ = static_cast<int32_t>(i);
  }
  });
}

namespace {

// What P2G reads per particle, its arrays' data pointers taken once per thread: read through the
// containers, the compiler would reload them after every store to the buffers.
template <class Width>
struct ToGridArrays {
  ToGridArrays(const ToGridInput& in, const Grids& grids, Width W)
      : S(in.stencil, W), n(static_cast<long>(in.P.size())), moving(static_cast<long>(in.P.moving_count)),
        gravity(in.gravity), x_i(in.x_i.data()), load_factor(in.load_factor.data()),
        cell_scale(in.cell_scale.empty() ? nullptr : in.cell_scale.data()), body(in.P.body.data()),
        field_index(grids.field_index.data()), element(in.P.element.data()), m(in.P.m.data()), x(in.P.x.data()),
        v(in.P.v.data()), volume(in.P.volume.data()), sigma(in.P.sigma.data()),
        C(in.P.C.empty() ? nullptr : in.P.C.data()), load(in.P.load.empty() ? nullptr : in.P.load.data()),
        load_force(in.P.load_force.data()) {}
  // The run particle p belongs to: its stencil row, its field and whether it is fixed.
  RunKey run_of(long p) const { return RunKey{S.row(p), field_index[body[p]], p >= moving}; }

  const StencilView<Width> S;
  const long n, moving;
  const Vec2 gravity;
  const Vec2* x_i;
  const double* load_factor;
  const double* cell_scale;  // null: no mixed integration
  const int32_t *body, *field_index, *element;
  const double* m;
  const Vec2 *x, *v;
  const double* volume;
  const Vec4* sigma;
  const Vec4* C;         // null: not APIC
  const int32_t* load;   // null: no surface loads
  const Vec2* load_force;
};

}  // namespace

void particles_to_grid(const ToGridInput& in, Grids& grids, ThreadBuffers& buffers, int threads) {
  with_width(in.stencil, [&](auto W) {
#pragma omp parallel num_threads(threads)
  {
    const ToGridArrays a(in, grids, W);
    NodeBuffer* const mine = buffers[omp_get_thread_num()].data();
    // The open run's sums (runs.hpp), in locals the compiler keeps in registers: sum N_ip m_p,
    // sum N_ip m_p v_p (with APIC's affine part), sum N_ip f_load, and sum V_p sigma_p, which
    // multiplies the run's shared gradients in (A.8).
    constexpr int kEntries = entries_for<decltype(W)>();
    Runs runs;
    const int32_t* nodes = nullptr;
    const Vec2* dN = nullptr;
    int32_t run_element = -1;
    double run_mass = 0, Nm[kEntries] = {};
    Vec2 Nmv[kEntries], Nf[kEntries];
    Vec4 V_sigma = Vec4::Zero();
    const auto start_run = [&](long p) {
      nodes = a.S.nodes(p), dN = a.S.gradients(p);
      if (a.cell_scale) run_element = a.element[p];  // a row lies in one element (one per element, or per particle)
      run_mass = 0;
      V_sigma.setZero();
      for (int k = 0; k < W; ++k) Nm[k] = 0, Nmv[k].setZero(), Nf[k].setZero();
    };
    // The run's sums to its nodes: m_i (A.6), p_i, f_i = N m g (A.7) - V sigma grad N (A.8) +
    // surface loads; with contact the mass gradient, which gives the bodies' normals.
    const auto scatter_run = [&] {
      if (!runs.any()) return;
      NodeBuffer& b = mine[runs.current().field];
      if (a.cell_scale) V_sigma *= a.cell_scale[run_element];  // mixed integration (full_cell_scales)
      for (int k = 0; k < W; ++k) {
        const int32_t i = nodes[k];
        b.m[i] += Nm[k];
        if (grids.per_body) b.mass_gradient[i] += run_mass * dN[k];
        if (runs.current().fixed) continue;  // a fixed body lends its mass (and its normals) only
        const Vec2& dN_k = dN[k];
        b.p[i] += Nmv[k];
        b.f[i] += Nm[k] * a.gravity -
                  Vec2(V_sigma[0] * dN_k.x() + V_sigma[3] * dN_k.y(), V_sigma[3] * dN_k.x() + V_sigma[1] * dN_k.y()) +
                  Nf[k];
      }
    };
#pragma omp for schedule(static) nowait
    for (long p = 0; p < a.n; ++p) {
      const RunKey key = a.run_of(p);
      if (runs.starts(key)) {
        scatter_run();
        runs.open(key);
        start_run(p);
      }
      const double* N = a.S.weights(p);
      const double m = a.m[p];
      run_mass += m;
      for (int k = 0; k < W; ++k) Nm[k] += N[k] * m;  // (A.6), lumped
      if (key.fixed) continue;
      const Vec2 mv = m * a.v[p];
      V_sigma += a.volume[p] * a.sigma[p];  // (A.8), through the run's shared gradients
      for (int k = 0; k < W; ++k) Nmv[k] += N[k] * mv;
      if (a.C) {  // APIC: m_p C_p (x_i - x_p) (Jiang et al. 2015)
        const Vec4& C = a.C[p];
        for (int k = 0; k < W; ++k) {
          const Vec2 d = a.x_i[nodes[k]] - a.x[p];
          Nmv[k] += N[k] * m * Vec2(C[0] * d.x() + C[1] * d.y(), C[2] * d.x() + C[3] * d.y());
        }
      }
      if (a.load && a.load[p] >= 0) {  // a surface load, spread over the nodes like the weight (A.7)
        const Vec2 f_load = a.load_factor[a.load[p]] * a.load_force[p];
        for (int k = 0; k < W; ++k) Nf[k] += N[k] * f_load;
      }
    }
    scatter_run();
#pragma omp barrier
    // The threads' sums, in thread order, at the active nodes.
    const long count = static_cast<long>(grids.active.size());
#pragma omp for schedule(static)
    for (long k = 0; k < count; ++k) {
      const int32_t i = grids.active[k];
      for (std::size_t field = 0; field < grids.fields.size(); ++field) {
        Grid& grid = grids.fields[field];
        grid.m[i] = take_thread_sum(buffers, field, &NodeBuffer::m, i);
        grid.p[i] = take_thread_sum(buffers, field, &NodeBuffer::p, i);
        grid.f[i] = take_thread_sum(buffers, field, &NodeBuffer::f, i);
        if (grids.per_body) grid.mass_gradient[i] = take_thread_sum(buffers, field, &NodeBuffer::mass_gradient, i);
      }
    }
  }
  });
}

}  // namespace talus::solver
