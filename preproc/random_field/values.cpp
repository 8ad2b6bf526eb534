// Random fields (random_field.hpp): the marginal transforms, the values at points and the
// scene's fields drawn together. The generator itself: random_field.cpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/error.hpp"
#include "common/materials/materials.hpp"
#include "preproc/random_field/random_field.hpp"

namespace talus::preproc {

double Marginal::operator()(double g) const {
  double value = 0;
  switch (distribution) {
    case RandomDistribution::Lognormal: {
      const double sigma2 = std::log1p(cov * cov);
      value = std::exp(std::log(mean) - sigma2 / 2 + std::sqrt(sigma2) * g);
      break;
    }
    case RandomDistribution::Normal: value = mean * (1 + cov * g); break;
    case RandomDistribution::Uniform: {
      const double half_width = std::sqrt(3.0) * cov * mean, a = mean - half_width, b = mean + half_width;
      value = a + (b - a) * 0.5 * std::erfc(-g / std::numbers::sqrt2);  // Phi(g)
      break;
    }
  }
  return std::clamp(value, lo, hi);
}

Marginal marginal(const RandomField& field, const Material& material) {
  const NumberRange range = find_parameter(material, field.parameter)->range;  // the scene checked the key
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Marginal m;
  m.distribution = field.distribution;
  m.mean = field.mean;
  m.cov = field.cov;
  // An open end is clipped to the nearest number inside it (an infinite one is no bound).
  m.lo = range.min_inclusive || std::isinf(range.min) ? range.min : std::nextafter(range.min, kInf);
  m.hi = range.max_inclusive || std::isinf(range.max) ? range.max : std::nextafter(range.max, -kInf);
  return m;
}

std::vector<double> gaussian_at(const FieldGrid& grid, Correlation form, const Eigen::Vector2d& theta,
                                const std::vector<double>& g, const std::vector<Eigen::Vector2d>& points) {
  if (g.size() != grid.size()) throw Error("internal error: a random field of another grid");
  // The correlations between a cell's nodes: along x, along y and across the diagonal.
  const double rho_x = correlation(form, theta, grid.spacing.x(), 0);
  const double rho_y = correlation(form, theta, 0, grid.spacing.y());
  const double rho_d = correlation(form, theta, grid.spacing.x(), grid.spacing.y());
  // The cell (i, i + 1) holding coordinate u (in spacings) and the fraction s across it.
  auto locate = [](double u, int n, int& i, double& s) {
    if (n == 1) {
      i = 0, s = 0;
      return;
    }
    i = std::clamp(static_cast<int>(std::floor(u)), 0, n - 2);
    s = std::clamp(u - i, 0.0, 1.0);
  };
  std::vector<double> out(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Eigen::Vector2d u = (points[p] - grid.origin).cwiseQuotient(grid.spacing);
    int i, j;
    double s, t;
    locate(u.x(), grid.nx, i, s);
    locate(u.y(), grid.ny, j, t);
    const int i1 = std::min(i + 1, grid.nx - 1), j1 = std::min(j + 1, grid.ny - 1);
    const double value = (1 - s) * (1 - t) * g[grid.index(i, j)] + s * (1 - t) * g[grid.index(i1, j)] +
                         (1 - s) * t * g[grid.index(i, j1)] + s * t * g[grid.index(i1, j1)];
    // Var(sum w_i G_i) = sum_ij w_i w_j rho_ij for the bilinear weights, grouped by pair.
    const double a_s = (1 - s) * (1 - s) + s * s, a_t = (1 - t) * (1 - t) + t * t;
    const double variance = a_s * a_t + 2 * s * (1 - s) * a_t * rho_x + 2 * t * (1 - t) * a_s * rho_y +
                            4 * s * (1 - s) * t * (1 - t) * rho_d;
    out[p] = value / std::sqrt(variance);
  }
  return out;
}

RandomFields::RandomFields(const Scene& scene, const FieldGrid& grid) : grid_(grid), fields_(scene.random) {
  for (const RandomField& field : fields_) {
    const int m = scene.material_index(field.material);
    if (m < 0) throw Error("internal error: random." + field.name + " names no material");
    marginals_.push_back(marginal(field, scene.materials[m]));
    int partner = -1;
    for (std::size_t k = 0; k < fields_.size(); ++k)
      if (!field.cross_with.empty() && fields_[k].name == field.cross_with) partner = static_cast<int>(k);
    if (!field.cross_with.empty() && (partner < 0 || !fields_[partner].cross_with.empty()))
      throw Error("internal error: random." + field.name + " is correlated with no primary field");
    partner_.push_back(partner);
    auto same = [&](const GaussianFieldGenerator& g) {
      return g.form() == field.correlation && g.theta() == field.correlation_length;
    };
    const auto found = std::find_if(generators_.begin(), generators_.end(), same);
    generator_of_.push_back(static_cast<std::size_t>(found - generators_.begin()));
    if (found != generators_.end()) continue;
    try {
      generators_.emplace_back(grid, field.correlation, field.correlation_length);
    } catch (const Error& e) {
      throw Error(located(scene.path, "random." + field.name + ".correlation_length", e.what()));
    }
  }
}

std::vector<std::vector<double>> RandomFields::gaussian(std::uint64_t seed) const {
  std::vector<std::vector<double>> g(fields_.size());
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    std::mt19937_64 stream(field_stream_seed(seed, fields_[k].name));
    g[k] = generators_[generator_of_[k]].draw(stream);
  }
  // G = rho G_partner + sqrt(1 - rho^2) Z; the partner has no partner, so its G is its Z.
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    if (partner_[k] < 0) continue;
    const double rho = fields_[k].cross_rho, own = std::sqrt(1 - rho * rho);
    const std::vector<double>& primary = g[partner_[k]];
    for (std::size_t n = 0; n < g[k].size(); ++n) g[k][n] = rho * primary[n] + own * g[k][n];
  }
  return g;
}

std::vector<double> RandomFields::values_at(std::size_t k, const std::vector<double>& gaussian,
                                            const std::vector<Eigen::Vector2d>& points) const {
  const RandomField& field = fields_.at(k);
  std::vector<double> values = gaussian_at(grid_, field.correlation, field.correlation_length, gaussian, points);
  for (double& v : values) v = marginals_[k](v);
  return values;
}

}  // namespace talus::preproc
