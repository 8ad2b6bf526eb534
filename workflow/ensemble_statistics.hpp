// The statistics of `talus ensemble` (docs/ensemble.md): the probability of failure with its
// Wilson score interval, the runout's quantiles, the exceedance curve P(runout > r) and, along the
// ground, the probability that the failure reaches each point. Pure functions over the
// realisations' rows, so that a test can check them on numbers it makes.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace talus::workflow {

// What one realisation gave (a row of realisations.csv).
struct RealisationRow {
  long index = 0;          // k: the realisation's seed is the ensemble's seed S + k
  unsigned long long seed = 0;
  bool solved = true;      // false: the solve stopped with an error (`message`); left out of the statistics
  bool failed = false;     // the failure criterion (ensemble.json, docs/ensemble.md)
  double runout = 0;       // m, from the initial toe; 0 when the slope did not fail
  double crest_retreat = 0;  // m
  double failed_area = 0;    // m^2: the sliding mass
  std::optional<double> travel_angle;  // deg; empty without a deposit
  std::optional<double> time_to_rest;  // s; empty when the run ended still moving
  double crown_x = 0, tip_x = 0;       // m, scene frame: the failure's head and the deposit's tip (NaN: not failed)
  long steps = 0;
  double simulated_time = 0;           // s
  // Each [random] field's mean over the particles of its material (in the parameter's unit, the
  // scene's order): one number that says how strong this realisation's soil is.
  std::vector<double> field_means;
  // --fos: the realisation's factor of safety by strength reduction (`talus fos`'s search on its
  // fields); empty without --fos or when the search found none (`message` says why).
  std::optional<double> fos;
  std::string message;                 // why the solve stopped (solved = false), or the search
};

// The two-sided 95 % Wilson score interval of a binomial proportion of `successes` in `trials`
// (Wilson 1927): centre (p + z^2 / 2n) / (1 + z^2 / n), half-width
// z sqrt(p (1 - p) / n + z^2 / 4n^2) / (1 + z^2 / n), z = 1.959964. trials > 0.
struct Interval {
  double lower = 0, upper = 0;
};
inline constexpr double kZ95 = 1.959963984540054;
Interval wilson_interval(std::size_t successes, std::size_t trials, double z = kZ95);

// The q-quantile (q in [0, 1]) of `values` by linear interpolation between order statistics
// (Hyndman and Fan 1996, type 7: h = (n - 1) q). `values` need not be sorted; not empty.
double quantile(std::vector<double> values, double q);

// P(value > r) at each r of `at`, with its pointwise Wilson interval.
struct Curve {
  std::vector<double> at, probability, lower, upper;
};
Curve exceedance(const std::vector<double>& values, const std::vector<double>& at);

// Along the ground: at each x of `at`, the fraction of realisations in which x lies between the
// failure's crown and the deposit's tip (inclusive), that is, the ground the failure took or the
// debris covered; realisations that did not fail reach nothing.
Curve reach(const std::vector<RealisationRow>& rows, const std::vector<double>& at);

// `count` points from lo to hi, ends included (count >= 2).
std::vector<double> evenly(double lo, double hi, std::size_t count);

}  // namespace talus::workflow
