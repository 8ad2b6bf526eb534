#include "postproc/pseudo_static.hpp"

namespace talus::postproc {

std::optional<YieldCoefficient> yield_coefficient(const SeismicSearch& search, double tolerance, double k_max) {
  YieldCoefficient out;
  const auto at_zero = search(0);
  const auto at_max = search(k_max);
  out.searches = 2;
  if (!at_zero || !at_max || at_zero->factor_of_safety <= 1 || at_max->factor_of_safety > 1) return std::nullopt;
  double stable = 0, failed = k_max;  // F(stable) > 1 >= F(failed)
  out.circle = at_max;
  while (failed - stable > tolerance) {
    const double k = 0.5 * (stable + failed);
    const auto found = search(k);
    ++out.searches;
    if (found && found->factor_of_safety > 1) stable = k;
    else failed = k, out.circle = found;
  }
  out.k_y = 0.5 * (stable + failed);
  return out;
}

}  // namespace talus::postproc
