#include "workflow/gci.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"

namespace talus::workflow {

GridConvergence grid_convergence(double f1, double f2, double f3, double r21, double r32) {
  if (!(r21 > 1) || !(r32 > 1) || !std::isfinite(r21) || !std::isfinite(r32))
    throw Error("grid convergence: the refinement ratios must be finite and > 1");
  if (!std::isfinite(f1) || !std::isfinite(f2) || !std::isfinite(f3))
    throw Error("grid convergence: the three values must be finite");
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  GridConvergence g;
  const double e21 = f2 - f1, e32 = f3 - f2;
  g.relative_band = kNaN;
  g.order = g.observed_order = g.extrapolated = kNaN;
  if (e21 == 0) {
    g.kind = Convergence::Converged;
    g.relative_band = f1 != 0 ? 0.0 : kNaN;
    return g;
  }
  const double ratio = e32 / e21;
  if (ratio < 0) g.kind = Convergence::Oscillatory;
  else if (std::abs(e21) >= std::abs(e32)) g.kind = Convergence::Divergent;
  else g.kind = Convergence::Monotone;

  double p = 1;
  if (g.kind == Convergence::Monotone) {
    // Fixed-point iteration of Celik's eq. (3)-(5) with s = 1; q = 0 for a constant ratio.
    const double ln_r21 = std::log(r21);
    p = std::log(ratio) / ln_r21;
    for (int k = 0; k < 200; ++k) {
      const double q = std::log((std::pow(r21, p) - 1) / (std::pow(r32, p) - 1));
      const double next = std::abs(std::log(ratio) + q) / ln_r21;
      const bool done = std::abs(next - p) < 1e-12 * std::max(1.0, p);
      p = next;
      if (done) break;
    }
    g.observed_order = p;
    p = std::min(p, kFormalOrder);
    g.order = p;
    g.safety_factor = 1.25;
    g.asymptotic = true;
    const double rp = std::pow(r21, g.observed_order);
    g.extrapolated = (rp * f1 - f2) / (rp - 1);
  } else {
    g.safety_factor = 3;
  }
  g.band = g.safety_factor * std::abs(e21) / (std::pow(r21, p) - 1);
  if (f1 != 0) g.relative_band = g.band / std::abs(f1);
  return g;
}

std::string convergence_name(Convergence kind) {
  switch (kind) {
    case Convergence::Monotone: return "monotone";
    case Convergence::Oscillatory: return "oscillatory";
    case Convergence::Divergent: return "divergent";
    case Convergence::Converged: return "converged";
  }
  return "";
}

}  // namespace talus::workflow
