#include "workflow/ensemble_statistics.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"

namespace talus::workflow {

Interval wilson_interval(std::size_t successes, std::size_t trials, double z) {
  if (trials == 0 || successes > trials) throw Error("internal error: a Wilson interval of no trials");
  const double n = static_cast<double>(trials), p = static_cast<double>(successes) / n, z2 = z * z;
  const double denominator = 1 + z2 / n;
  const double centre = (p + z2 / (2 * n)) / denominator;
  const double half = z * std::sqrt(p * (1 - p) / n + z2 / (4 * n * n)) / denominator;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) throw Error("internal error: a quantile of no values");
  std::sort(values.begin(), values.end());
  const double h = (static_cast<double>(values.size()) - 1) * std::clamp(q, 0.0, 1.0);
  const std::size_t below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (h - static_cast<double>(below)) * (values[above] - values[below]);
}

namespace {

// The curve from a count at each point.
template <class Count>
Curve counted(const std::vector<double>& at, std::size_t trials, Count&& count) {
  Curve curve;
  curve.at = at;
  for (double r : at) {
    const std::size_t k = count(r);
    const Interval band = wilson_interval(k, trials);
    curve.probability.push_back(static_cast<double>(k) / static_cast<double>(trials));
    curve.lower.push_back(band.lower);
    curve.upper.push_back(band.upper);
  }
  return curve;
}

}  // namespace

Curve exceedance(const std::vector<double>& values, const std::vector<double>& at) {
  return counted(at, values.size(), [&](double r) {
    return static_cast<std::size_t>(std::count_if(values.begin(), values.end(), [r](double v) { return v > r; }));
  });
}

Curve reach(const std::vector<RealisationRow>& rows, const std::vector<double>& at) {
  return counted(at, rows.size(), [&](double x) {
    return static_cast<std::size_t>(std::count_if(rows.begin(), rows.end(), [x](const RealisationRow& row) {
      return row.failed && std::min(row.crown_x, row.tip_x) <= x && x <= std::max(row.crown_x, row.tip_x);
    }));
  });
}

std::vector<double> evenly(double lo, double hi, std::size_t count) {
  std::vector<double> out(count);
  for (std::size_t i = 0; i < count; ++i)
    out[i] = i + 1 == count ? hi : lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(count - 1);
  return out;
}

}  // namespace talus::workflow
