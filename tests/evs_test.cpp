// Enhanced volumetric strain against volumetric locking (design.md, "Enhanced volumetric
// strain"; Detournay and Dzik 2006): a nearly incompressible (nu = 0.49) elastic cantilever
// under its own weight, damped to rest, against beam theory. Linear triangles lock: with
// nu -> 0.5 every element must keep its area, and a beam of them can hardly bend. EVS replaces
// each element's volumetric strain by a nodal average and so frees it.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <future>

#include "solver/step/step.hpp"
#include "support/test_support.hpp"

using namespace talus;
using namespace talus::solver;
using talus::testing::add_box_body;
using talus::testing::elastic;
using talus::testing::rectangle_mesh;
using talus::testing::set_run;

namespace {

// A cantilever of length L and depth h, clamped at x = 0, loaded by its weight q = rho g h per
// unit length (plane strain, unit thickness). L / h = 8, so shear adds only ~3 % to the
// deflection (included below). Six elements through the depth: constant-strain triangles bend
// too stiffly when coarse, locking or not (measured with EVS: four elements through the depth
// give 0.86 of beam theory at nu = 0 and 0.85 at nu = 0.49; six give 0.90), and the locking must not
// hide behind that error. Measured cost: ~6 s of one core per run.
struct Cantilever {
  double L = 4.0, h = 0.5, cell = 0.5 / 6;
  double rho = 1000, g = 10, E = 1e9, nu = 0.49;  // tip deflection ~1 cm: small displacements
  // Local damping as FLAC uses it for statics. Measured: with EVS the tip is within 1 % of its
  // value at five periods after two; without, the locked beam creeps on slowly (0.52 of beam
  // theory at two periods, 0.48 at five), stiffer either way.
  double damping = 0.8;

  double plane_strain_modulus() const { return E / (1 - nu * nu); }
  double second_moment() const { return h * h * h / 12; }
  // First bending period of a clamped-free Euler-Bernoulli beam, omega_1 = 1.8751^2
  // sqrt(E' I / (rho h L^4)) (Timoshenko, Vibration Problems in Engineering): the time scale for
  // the gravity ramp and the run.
  double first_period() const {
    const double omega = 1.8751 * 1.8751 * std::sqrt(plane_strain_modulus() * second_moment() / (rho * h * L * L * L * L));
    return 2 * M_PI / omega;
  }
};

// Deflection of the centre line at x under the uniform load q, Timoshenko beam: Euler-Bernoulli
// bending, q x^2 (6 L^2 - 4 L x + x^2) / (24 E' I) (tip: q L^4 / (8 E' I)), plus shear,
// q (L x - x^2 / 2) / (kappa G h) with kappa = 5/6 for a rectangle. Plane strain stiffens
// bending to E' = E / (1 - nu^2); the shear modulus G = E / (2 (1 + nu)) is unchanged.
double beam_deflection(const Cantilever& c, double x) {
  const double q = c.rho * c.g * c.h;
  const double G = c.E / (2 * (1 + c.nu)), kappa = 5.0 / 6.0;
  const double bending = q * x * x * (6 * c.L * c.L - 4 * c.L * x + x * x) / (24 * c.plane_strain_modulus() * c.second_moment());
  return bending + q * (c.L * x - 0.5 * x * x) / (kappa * G * c.h);
}

struct TipDeflection {
  double simulated = 0;  // mean downward displacement of the particles in the last column of cells
  double theory = 0;     // beam theory at the same particles' initial x, averaged likewise
  bool ok = false;
};

TipDeflection run_cantilever(const Cantilever& c, bool evs) {
  const int nx = static_cast<int>(std::lround(c.L / c.cell)) + 2;
  const int ny = static_cast<int>(std::lround(c.h / c.cell)) + 4;
  // Two empty rows of cells below the beam and two above, two columns beyond the tip.
  Model model = rectangle_mesh(0, -2 * c.cell, nx, ny, c.cell);
  add_box_body(model, "beam", elastic(c.rho, c.E, c.nu), 0, c.L, 0, c.h);
  for (int32_t i : model.node_sets["left"])  // clamp the root: the wall nodes the beam touches
    if (model.nodes[i].y() > -1e-9 && model.nodes[i].y() < c.h + 1e-9) model.fixed_nodes.push_back(i);
  const double period = c.first_period();
  set_run(model, 2 * period, Vec2(0, -c.g));
  model.run.gravity_ramp = period;  // loads the beam gently, so the damping has little to remove
  model.run.damping = c.damping;
  model.run.evs = evs;
  Simulation sim = make_simulation(model, 1);
  const double dt = stable_time_step(sim, 0.8);
  TipDeflection tip;
  while (sim.time < model.run.end_time)
    if (!step(sim, dt)) return tip;

  int count = 0;
  for (std::size_t p = 0; p < sim.particles.size(); ++p) {
    const Vec2 X = model.position[sim.particles.id[p]];
    if (X.x() < c.L - c.cell) continue;
    tip.simulated -= sim.particles.x[p].y() - X.y();
    tip.theory += beam_deflection(c, X.x());
    ++count;
  }
  tip.simulated /= count;
  tip.theory /= count;
  tip.ok = count > 0;
  return tip;
}

}  // namespace

TEST(EnhancedVolumetricStrain, RemovesLockingOfANearlyIncompressibleCantilever) {
  const Cantilever c;
  // The two runs side by side, one thread each: small meshes gain nothing from OpenMP.
  auto run = [&](bool evs) {
    omp_set_num_threads(1);
    return run_cantilever(c, evs);
  };
  auto with_evs = std::async(std::launch::async, run, true);
  auto without_evs = std::async(std::launch::async, run, false);
  const TipDeflection on = with_evs.get(), off = without_evs.get();
  ASSERT_TRUE(on.ok && off.ok) << "a particle left the mesh or a state became non-finite";

  const double q = c.rho * c.g * c.h;
  std::printf("beam theory at the tip particles %.4e m (Euler-Bernoulli tip q L^4 / (8 E' I) = %.4e m)\n", on.theory,
              q * std::pow(c.L, 4) / (8 * c.plane_strain_modulus() * c.second_moment()));
  std::printf("EVS on  %.4e m = %.3f of beam theory\nEVS off %.4e m = %.3f of beam theory\n", on.simulated,
              on.simulated / on.theory, off.simulated, off.simulated / off.theory);
  EXPECT_NEAR(on.simulated / on.theory, 1.0, 0.15);
  EXPECT_LT(off.simulated / off.theory, 0.85);  // locked: stiffer by more than the tolerance
  EXPECT_LT(off.simulated, 0.75 * on.simulated);
}
