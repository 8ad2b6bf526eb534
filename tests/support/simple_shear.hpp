// Simple shear under a constant normal stress, as in a simple-shear or direct-shear apparatus:
// the horizontal strain held at zero, the vertical strain free so that sigma_yy stays at -p.
// Shared by the Mohr-Coulomb and mu(I) tests of the stress ratio a flowing sample mobilises.
#pragma once
#include <gtest/gtest.h>

#include <Eigen/Core>

namespace talus::testing {

// Applies `steps` tensor shear increments d_gamma / 2 (engineering d_gamma) to sigma through
// update(sigma, d_eps), each with the d_eps_yy that keeps sigma_yy at -p_normal (bisection);
// returns the stress after the last.
template <class Update>
Eigen::Vector4d sheared_under_normal_stress(Update&& update, Eigen::Vector4d sigma, double p_normal, double d_gamma,
                                            int steps) {
  for (int step = 1; step <= steps; ++step) {
    const auto after = [&](double d_yy) {
      Eigen::Vector4d next = sigma;
      update(next, Eigen::Vector4d(0, d_yy, 0, 0.5 * d_gamma));
      return next;
    };
    // sigma_yy falls as d_yy grows (compression negative): bisect for sigma_yy = -p.
    double low = -10 * d_gamma, high = 10 * d_gamma;
    if (!(after(low)[1] < -p_normal && after(high)[1] > -p_normal)) {
      ADD_FAILURE() << "no vertical strain in +-10 d_gamma keeps sigma_yy at -p at step " << step;
      return sigma;
    }
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (low + high);
      if (mid == low || mid == high) break;
      (after(mid)[1] < -p_normal ? low : high) = mid;
    }
    sigma = after(0.5 * (low + high));
  }
  return sigma;
}

}  // namespace talus::testing
