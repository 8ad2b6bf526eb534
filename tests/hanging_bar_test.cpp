// An elastic bar hanging under its own weight (validation.md, case 7): statics with a movement
// large enough that the particles cross cells, where the cell-crossing error of linear shape
// functions shows.
//
// The bar, L long, hangs from its fixed top, rollers on its sides, Poisson's ratio 0, so that
// it is a 1D bar. At equilibrium the Cauchy stress at a material point Z below the top carries
// the weight of the bar below it, sigma = rho_0 g (L - Z) (mass per unit width is conserved).
// The solver integrates the rate of deformation, so its strain is logarithmic and
// sigma = E ln(stretch): the stretch is exp(rho_0 g (L - Z) / E) and the displacement
// u(Z) = int_0^Z (exp(rho_0 g (L - Z') / E) - 1) dZ'
//      = (E / (rho_0 g)) exp(rho_0 g L / E) (1 - exp(-rho_0 g Z / E)) - Z,
// which for small strains is the linear u = rho g (L Z - Z^2 / 2) / E of validation.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "solver/step/step.hpp"
#include "support/test_support.hpp"

namespace talus::solver {
namespace {

using testing::add_box_body;
using testing::crossed_rectangle_mesh;
using testing::elastic;
using testing::rectangle_mesh;

constexpr double kDensity = 1000, kGravity = 10, kLength = 2.0, kCell = 0.1;

double exact_displacement(double E, double Z) {
  const double a = kDensity * kGravity / E;
  return std::exp(a * kLength) * (1 - std::exp(-a * Z)) / a - Z;
}

struct BarResult {
  double end_error = 0;   // |u_end - exact| / exact at the free end
  double max_error = 0;   // max over particles |u - exact(Z)| / exact end displacement
  long loose = 0;         // particles more than a cell below where the bar's end should be
};

BarResult hang(bool crossed, ShapeFunctions family, double end_cells, Transfer transfer = Transfer::Flip) {
  // E such that the free end moves end_cells cells (linear estimate rho g L^2 / 2E).
  const double E = kDensity * kGravity * kLength * kLength / (2 * end_cells * kCell);
  const int below = 6;  // empty cells below the bar, room to stretch into
  const int rows = static_cast<int>(std::lround(kLength / kCell)) + below;
  Model model = crossed ? crossed_rectangle_mesh(0, 0, 2, rows, kCell) : rectangle_mesh(0, 0, 2, rows, kCell);
  const double top = rows * kCell, bottom = below * kCell;
  add_box_body(model, "bar", elastic(kDensity, E, 0.0), 0, 2 * kCell, bottom, top);
  model.fixed_nodes = model.node_sets["top"];
  for (const char* side : {"left", "right"})
    for (int32_t i : model.node_sets[side]) {
      model.roller_nodes.push_back(i);
      model.roller_normals.push_back(Eigen::Vector2d(1, 0));
    }
  const double period = 4 * kLength / std::sqrt(E / kDensity);
  testing::set_run(model, 12 * period, Eigen::Vector2d(0, -kGravity));
  model.run.gravity_ramp = 4 * period;
  model.run.damping = 0.1;
  model.run.shape_functions = family;
  model.run.transfer = transfer;
  const std::vector<Eigen::Vector2d> start = model.position;
  Simulation sim = make_simulation(model, 1);
  while (sim.time < model.run.end_time)
    if (!step(sim, stable_time_step(sim, 0.5))) ADD_FAILURE() << "the step failed at t = " << sim.time;
  BarResult result;
  const double u_end = exact_displacement(E, kLength);
  double end_sum = 0, end_count = 0;
  const Particles& P = sim.particles;
  for (std::size_t p = 0; p < P.size(); ++p) {
    const Eigen::Vector2d& x0 = start[P.id[p]];
    const double Z = top - x0.y(), u = x0.y() - P.x[p].y();
    result.max_error = std::max(result.max_error, std::abs(u - exact_displacement(E, Z)) / u_end);
    if (u - exact_displacement(E, Z) > kCell) ++result.loose;
    if (Z > kLength - 0.25 * kCell) end_sum += u - exact_displacement(E, Z) + u_end, end_count += 1;
  }
  result.end_error = std::abs(end_sum / end_count - u_end) / u_end;
  if (std::getenv("BAR_PROFILE")) {
    for (std::size_t p = 0; p < P.size(); ++p) {
      const Eigen::Vector2d& x0 = start[P.id[p]];
      const double Z = top - x0.y(), u = x0.y() - P.x[p].y();
      if (x0.x() < 0.05) std::printf("  Z %.4f u %.6f exact %.6f sigma %.1f exact %.1f\n", Z, u, exact_displacement(E, Z), P.sigma[p][1], -kDensity * kGravity * (kLength - Z));
    }
  }
  return result;
}

TEST(HangingBar, Experiment) {
  for (double cells : {0.1, 0.6, 1.2}) {
    for (int variant = std::getenv("BAR_VARIANT") ? std::atoi(std::getenv("BAR_VARIANT")) : 0; variant < 3; ++variant) {
      const bool crossed = variant > 0;
      const ShapeFunctions family = variant == 2 ? ShapeFunctions::QuadraticBspline : ShapeFunctions::Linear;
      const BarResult r = hang(crossed, family, cells);
      std::printf("end %.1f cells, %s: end error %.4f, max error %.4f, loose %ld\n", cells,
                  variant == 0 ? "two triangles" : variant == 1 ? "crossed linear" : "bspline", r.end_error,
                  r.max_error, r.loose);
    }
  }
}

}  // namespace
}  // namespace talus::solver
