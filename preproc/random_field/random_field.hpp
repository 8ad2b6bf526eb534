// Spatially correlated random fields of material parameters (issue 41; the scene's
// [random.NAME] tables, common/scene/scene.hpp RandomField, docs/scenes.md).
//
// Method. A stationary standard Gaussian field (mean 0, variance 1, correlation rho(tau)) on a
// regular grid of nx x ny nodes is drawn by circulant embedding (Wood and Chan 1994, J. Comput.
// Graph. Stat. 3(4), 409-432; Dietrich and Newsam 1997, SIAM J. Sci. Comput. 18(4),
// 1088-1107). The grid's covariance matrix (block Toeplitz with Toeplitz blocks) is the corner of
// the block-circulant covariance C of a periodic Mx x My torus, Mx >= 2 (nx - 1) and
// My >= 2 (ny - 1), whose first row is rho at the torus lags min(k, M - k) times the spacing;
// C's eigenvalues lambda are that row's 2D DFT. When every lambda >= 0,
// X = F^-1 diag(sqrt(lambda)) F W, with W standard white noise on the torus, has covariance C
// exactly, so its nx x ny corner has the grid's covariance exactly. Negative eigenvalues are
// cured by a larger torus (padded 2, 4 and 8 times); beyond that the generator throws
// talus::Error naming the correlation length. A negative eigenvalue smaller in magnitude than
// 1e-10 times the largest is round-off, taken as 0.
//
// Correlation, with the lag tau = (tx, ty) and the correlation lengths theta = (theta_x,
// theta_y), horizontal and vertical (each the scale of fluctuation: the integral of rho over
// the lag along its axis):
//   markov    rho = exp(-2 sqrt((tx / theta_x)^2 + (ty / theta_y)^2)), the Markov form of
//             Fenton and Griffiths (2008, "Risk Assessment in Geotechnical Engineering", Wiley),
//             exp(-2 |tau| / theta) along each axis, made anisotropic by scaling the distance;
//   gaussian  rho = exp(-pi ((tx / theta_x)^2 + (ty / theta_y)^2)), the product of the 1D
//             forms exp(-pi (tau / theta)^2).
// A correlation length of inf makes the field constant along its axis (rho = 1 there); with
// [inf, inf] each realisation is one value of the parameter, the fully correlated limit, which
// the embedding draws exactly (its only non-zero eigenvalue is the constant mode's).
//
// Cross-correlation (a field with cross_correlation = { with = "A", rho }): the correlation rho
// applies to the underlying Gaussian fields, G_A = Z_A and G = rho G_A + sqrt(1 - rho^2) Z, the
// Cholesky factor of the 2 x 2 correlation [[1, rho], [rho, 1]] applied to independent standard
// fields of one correlation structure (the scene requires the pair to share it). Fields without
// cross_correlation are independent.
//
// Seeds. Realisation seed S and field NAME give the field's own stream,
// std::mt19937_64(splitmix64(splitmix64(S) ^ fnv1a64(NAME))), so adding, removing or reordering
// other fields never changes a field. Its standard normals are drawn by Box-Muller from that
// stream in a fixed order (not std::normal_distribution, which differs between standard
// libraries), and the FFTs use FFTW_ESTIMATE plans without SIMD codelets (which FFTW picks by
// the CPU at run time), one thread: one seed gives the same bits on any thread count, rank
// count or x86-64 machine with the same FFTW and libm.
//
// Marginals (value from the standard Gaussian g at a point), then clipped to the parameter's
// valid range (common/materials/materials.hpp, find_parameter; an open end is clipped to the nearest
// number inside it):
//   lognormal  sigma^2 = ln(1 + cov^2), mu = ln(mean) - sigma^2 / 2, value = exp(mu + sigma g);
//   normal     value = mean (1 + cov g): the clip moves the mean (and cuts the variance) when
//              the range cuts the distribution (friction_angle with cov 0.5 is clipped at 0);
//   uniform    a = mean (1 - sqrt(3) cov), b = mean (1 + sqrt(3) cov), value = a + (b - a) Phi(g),
//              Phi(g) = erfc(-g / sqrt(2)) / 2 (the scene keeps [a, b] inside the range).
//
// Values at the particles: point values. The standard field is interpolated bilinearly from
// the four grid nodes around the particle and divided by the interpolant's standard deviation
// (sqrt of sum w_i w_j rho(x_i - x_j)), so that each particle's g is exactly standard normal
// (plain interpolation would shrink the variance between nodes); then the marginal transform.
// The grid spacing is no coarser than the particle spacing nor a quarter of the correlation
// length along each axis (field_spacing), so the interpolation's error in the correlation
// between particles is small. No local averaging over the particle's area.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/scene/scene.hpp"

namespace talus::preproc {

// A regular grid: node (i, j) at origin + (i dx, j dy), i < nx, j < ny; field values are stored
// row by row, x fastest (index).
struct FieldGrid {
  Eigen::Vector2d origin{0, 0};   // m
  Eigen::Vector2d spacing{1, 1};  // (dx, dy), m, > 0
  int nx = 1, ny = 1;
  std::size_t size() const { return static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny); }
  std::size_t index(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
  Eigen::Vector2d node(int i, int j) const { return origin + Eigen::Vector2d(i * spacing.x(), j * spacing.y()); }
};

// The grid whose nodes span the box [lo, hi] (a model's bounding box), corner to corner, with
// the fewest nodes whose spacing along each axis is at most max_spacing. A side of zero length
// gets one node.
FieldGrid grid_over(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const Eigen::Vector2d& max_spacing);

// The largest spacing point values need along each axis: min(particle spacing,
// correlation_length / 4).
Eigen::Vector2d field_spacing(double particle_spacing, const Eigen::Vector2d& correlation_length);

// rho(tx, ty) of the form (header) with correlation lengths theta (m).
double correlation(Correlation form, const Eigen::Vector2d& theta, double tx, double ty);
const char* correlation_name(Correlation form);  // "markov", "gaussian"

// The seeding scheme (header): a fixed 64-bit mixer (Steele, Lea and Flood 2014), a fixed hash of
// a field's name (FNV-1a, 64 bits), and the seed of field `name`'s stream in realisation `seed`.
std::uint64_t splitmix64(std::uint64_t x);
std::uint64_t fnv1a64(const std::string& text);
std::uint64_t field_stream_seed(std::uint64_t seed, const std::string& name);

// Fills out[0..n) with standard normals from `stream` by Box-Muller, two per pair of draws:
// u1 = (k1 >> 11) + 1 over 2^53 in (0, 1], u2 = (k2 >> 11) over 2^53 in [0, 1),
// r = sqrt(-2 ln u1), out = r cos(2 pi u2), r sin(2 pi u2) (the last odd value drops the sine).
void standard_normals(std::mt19937_64& stream, double* out, std::size_t n);

// Standard Gaussian fields of one correlation on one grid. The eigenvalues are computed once, at
// construction (one FFT per torus tried); each draw costs two FFTs of the torus. draw() is
// const and may run on several threads at once.
class GaussianFieldGenerator {
 public:
  // Throws talus::Error when no torus up to 8 times the minimal one has eigenvalues >= 0.
  GaussianFieldGenerator(const FieldGrid& grid, Correlation form, const Eigen::Vector2d& theta);
  ~GaussianFieldGenerator();
  GaussianFieldGenerator(GaussianFieldGenerator&&) noexcept;
  GaussianFieldGenerator& operator=(GaussianFieldGenerator&&) noexcept;

  // One field on the grid (FieldGrid::index order), from Mx My normals of `stream`.
  std::vector<double> draw(std::mt19937_64& stream) const;

  const FieldGrid& grid() const { return grid_; }
  Correlation form() const { return form_; }
  const Eigen::Vector2d& theta() const { return theta_; }
  int torus_x() const { return mx_; }  // Mx
  int torus_y() const { return my_; }  // My
  int padding() const { return padding_; }  // 1, 2, 4 or 8: the torus over the minimal one

 private:
  struct Fft;  // the FFTW plans (random_field.cpp)
  FieldGrid grid_;
  Correlation form_;
  Eigen::Vector2d theta_;
  int mx_ = 1, my_ = 1, padding_ = 1;
  std::vector<double> scale_;  // sqrt(lambda) / (Mx My), on the half spectrum My x (Mx / 2 + 1)
  std::unique_ptr<Fft> fft_;
};

// A [random] table's marginal: the value of the parameter for a standard Gaussian g (header),
// clipped to [lo, hi], the parameter's valid range for the material.
struct Marginal {
  RandomDistribution distribution = RandomDistribution::Lognormal;
  double mean = 0, cov = 0;
  double lo = 0, hi = 0;
  double operator()(double g) const;
};
Marginal marginal(const RandomField& field, const Material& material);

// The standard Gaussian field `g` on `grid`, of correlation (form, theta), at each point:
// bilinear, divided by the interpolant's standard deviation (header). Points outside the grid
// take the nearest edge's values.
std::vector<double> gaussian_at(const FieldGrid& grid, Correlation form, const Eigen::Vector2d& theta,
                                const std::vector<double>& g, const std::vector<Eigen::Vector2d>& points);

// The scene's [random] fields on one grid: what a realisation draws.
class RandomFields {
 public:
  // One generator per distinct (correlation, correlation_length); throws talus::Error located
  // at the scene and random.NAME.correlation_length when one cannot be embedded.
  RandomFields(const Scene& scene, const FieldGrid& grid);

  std::size_t size() const { return fields_.size(); }
  const RandomField& field(std::size_t k) const { return fields_[k]; }
  const GaussianFieldGenerator& generator(std::size_t k) const { return generators_[generator_of_[k]]; }
  const FieldGrid& grid() const { return grid_; }

  // Realisation `seed`'s underlying standard Gaussian fields on the grid, one per [random]
  // table in the scene's order, cross-correlated as the scene says.
  std::vector<std::vector<double>> gaussian(std::uint64_t seed) const;
  // Field k's parameter values at the points, from its Gaussian field (one of gaussian()'s).
  std::vector<double> values_at(std::size_t k, const std::vector<double>& gaussian,
                                const std::vector<Eigen::Vector2d>& points) const;

 private:
  FieldGrid grid_;
  std::vector<RandomField> fields_;
  std::vector<Marginal> marginals_;
  std::vector<GaussianFieldGenerator> generators_;
  std::vector<std::size_t> generator_of_;  // [field] -> generators_
  std::vector<int> partner_;               // [field] -> the field it is correlated with, or -1
};

}  // namespace talus::preproc
