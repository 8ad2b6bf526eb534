// The random-field generator (preproc/random_field/random_field.hpp) against its targets, its seeding
// contract, and the scene's [random.NAME] tables (common/scene/random.cpp).
//
// Tolerances. A statistic computed on one realisation (a spatial average over the grid) is one
// value per realisation; realisations are independent, so over R of them the mean of those
// values estimates the statistic's expectation with standard error SE = s / sqrt(R), s their
// sample standard deviation. Each check allows 4 SE: a correct generator fails a check with
// probability about 6e-5 (the values are averages over many nodes, close to normal), and with
// fixed seeds each outcome is the same on every run. Each check also asserts that its SE is
// small against the effect it checks (the `resolution` argument), so a wrong form would fail.
#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numbers>

#include "common/error.hpp"
#include "preproc/random_field/random_field.hpp"
#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

using preproc::correlation;
using preproc::FieldGrid;
using preproc::GaussianFieldGenerator;
using preproc::RandomFields;

// One value per realisation; their mean and its standard error.
struct Estimate {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  double mean() const {
    double sum = 0;
    for (double v : values) sum += v;
    return sum / values.size();
  }
  double standard_error() const {
    const double m = mean();
    double sum = 0;
    for (double v : values) sum += (v - m) * (v - m);
    return std::sqrt(sum / (values.size() - 1) / values.size());
  }
};

void expect_matches(const Estimate& e, double target, double resolution, const std::string& what) {
  EXPECT_NEAR(e.mean(), target, 4 * e.standard_error()) << what << " (SE " << e.standard_error() << ")";
  EXPECT_LT(4 * e.standard_error(), resolution) << what << ": too few realisations to tell";
}

// The mean over the grid of g1(x) g2(x + (lx, ly) spacings): one realisation's estimate of the
// (cross-)correlation at that lag (the fields have mean 0 and variance 1).
double lag_product(const FieldGrid& grid, const std::vector<double>& g1, const std::vector<double>& g2, int lx,
                   int ly) {
  double sum = 0;
  int count = 0;
  for (int j = 0; j + ly < grid.ny; ++j)
    for (int i = 0; i + lx < grid.nx; ++i, ++count) sum += g1[grid.index(i, j)] * g2[grid.index(i + lx, j + ly)];
  return sum / count;
}

FieldGrid small_grid() {
  FieldGrid grid;
  grid.nx = 32;
  grid.ny = 24;
  grid.spacing = {0.5, 0.5};
  return grid;
}

constexpr int kRealisations = 3000;
constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<Eigen::Vector2d> node_positions(const FieldGrid& grid) {
  std::vector<Eigen::Vector2d> nodes;
  for (int j = 0; j < grid.ny; ++j)
    for (int i = 0; i < grid.nx; ++i) nodes.push_back(grid.node(i, j));
  return nodes;
}

// A scene of one Mohr-Coulomb material, "sand", and these fields of it.
Scene scene_of(const std::vector<RandomField>& fields) {
  Scene scene;
  scene.path = "scene.toml";
  Material sand = testing::mohr_coulomb(1800, 1e7, 0.3, 30, 10e3);
  sand.name = "sand";
  scene.materials = {sand};
  scene.random = fields;
  return scene;
}

RandomField field(const std::string& name, const std::string& parameter, RandomDistribution distribution, double mean,
                  double cov, const Eigen::Vector2d& theta, Correlation form = Correlation::Markov) {
  RandomField f;
  f.name = name;
  f.material = "sand";
  f.parameter = parameter;
  f.distribution = distribution;
  f.mean = mean;
  f.cov = cov;
  f.correlation_length = theta;
  f.correlation = form;
  return f;
}

std::string message_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no talus::Error";
  return "";
}

// The correlation against lag along x, y and the diagonal, with the mean and the variance, of
// kRealisations draws of one generator.
void check_correlation(Correlation form, const Eigen::Vector2d& theta, double resolution = 0.05) {
  const FieldGrid grid = small_grid();
  const GaussianFieldGenerator generator(grid, form, theta);
  const std::vector<std::array<int, 2>> lags = {{1, 0}, {2, 0}, {4, 0}, {8, 0}, {0, 1}, {0, 2}, {0, 4}, {4, 2}};
  std::vector<Estimate> at_lag(lags.size());
  Estimate mean, variance;
  std::mt19937_64 stream(7);
  for (int r = 0; r < kRealisations; ++r) {
    const std::vector<double> g = generator.draw(stream);
    double sum = 0;
    for (double v : g) sum += v;
    mean.add(sum / g.size());
    variance.add(lag_product(grid, g, g, 0, 0));
    for (std::size_t l = 0; l < lags.size(); ++l) at_lag[l].add(lag_product(grid, g, g, lags[l][0], lags[l][1]));
  }
  const std::string name = preproc::correlation_name(form);
  expect_matches(mean, 0, resolution, name + " mean");
  expect_matches(variance, 1, resolution, name + " variance");
  // Resolution: the gap between the Markov and Gaussian forms at theta / 2 is 0.09.
  for (std::size_t l = 0; l < lags.size(); ++l) {
    const double tx = lags[l][0] * grid.spacing.x(), ty = lags[l][1] * grid.spacing.y();
    expect_matches(at_lag[l], correlation(form, theta, tx, ty), resolution,
                   name + " at lag (" + std::to_string(tx) + ", " + std::to_string(ty) + ") m");
  }
}

TEST(RandomField, CorrelationFormsAreTheStatedOnes) {
  const Eigen::Vector2d theta(4, 2);
  EXPECT_DOUBLE_EQ(correlation(Correlation::Markov, theta, 2, 0), std::exp(-1.0));
  EXPECT_DOUBLE_EQ(correlation(Correlation::Markov, theta, 0, -2), std::exp(-2.0));
  // Anisotropic Markov: the scaled distance, not the product of the 1D forms (exp(-2) here).
  EXPECT_DOUBLE_EQ(correlation(Correlation::Markov, theta, 2, 1), std::exp(-std::sqrt(2.0)));
  EXPECT_DOUBLE_EQ(correlation(Correlation::Gaussian, theta, 4, 0), std::exp(-std::numbers::pi));
  EXPECT_DOUBLE_EQ(correlation(Correlation::Gaussian, theta, 2, 1),
                   correlation(Correlation::Gaussian, theta, 2, 0) * correlation(Correlation::Gaussian, theta, 0, 1));
}

TEST(RandomField, GridSpansTheBoxNoCoarserThanAsked) {
  const FieldGrid grid = preproc::grid_over({-1, 2}, {9, 4.5}, {0.3, 0.25});
  EXPECT_EQ(grid.nx, 35);  // 10 / 0.3 = 33.3 -> 34 cells
  EXPECT_EQ(grid.ny, 11);  // 2.5 / 0.25 = 10 cells exactly
  EXPECT_LE(grid.spacing.x(), 0.3);
  EXPECT_DOUBLE_EQ(grid.spacing.y(), 0.25);
  EXPECT_NEAR(grid.node(grid.nx - 1, grid.ny - 1).x(), 9, 1e-12);
  EXPECT_NEAR(grid.node(grid.nx - 1, grid.ny - 1).y(), 4.5, 1e-12);
  const Eigen::Vector2d spacing = preproc::field_spacing(0.125, {20, 0.4});
  EXPECT_DOUBLE_EQ(spacing.x(), 0.125);  // the particles' spacing
  EXPECT_DOUBLE_EQ(spacing.y(), 0.1);    // a quarter of the vertical correlation length
}

TEST(RandomField, MarkovFieldHasItsMeanVarianceAndCorrelation) { check_correlation(Correlation::Markov, {4, 2}); }

TEST(RandomField, GaussianFieldHasItsMeanVarianceAndCorrelation) {
  check_correlation(Correlation::Gaussian, {3, 1.5});
}

TEST(RandomField, PaddingCuresNegativeEigenvalues) {
  // On the 15.5 x 11.5 m grid the minimal torus of these correlations has negative eigenvalues.
  const GaussianFieldGenerator markov(small_grid(), Correlation::Markov, {15, 7.5});
  EXPECT_EQ(markov.padding(), 2);
  check_correlation(Correlation::Gaussian, {10, 5}, 0.15);
}

TEST(RandomField, UnembeddableCorrelationIsRefused) {
  Scene scene = scene_of({field("soft", "cohesion", RandomDistribution::Lognormal, 10e3, 0.3, {100, 50},
                                Correlation::Gaussian)});
  const std::string message = message_of([&] { RandomFields(scene, small_grid()); });
  for (const char* word : {"scene.toml: random.soft.correlation_length:", "gaussian", "[100, 50]", "15.5 x 11.5 m",
                           "negative eigenvalues", "shorter correlation_length", "markov"})
    EXPECT_NE(message.find(word), std::string::npos) << word << " not in: " << message;
}

TEST(RandomField, InfiniteCorrelationLengthIsFullyCorrelated) {
  const FieldGrid grid = small_grid();
  const GaussianFieldGenerator one_value(grid, Correlation::Markov, {kInf, kInf});
  const GaussianFieldGenerator layers(grid, Correlation::Markov, {kInf, 2});
  EXPECT_EQ(one_value.padding(), 1);
  Estimate variance, along_y;
  std::mt19937_64 stream(11);
  double spread = 0, along_x = 0;  // the largest change across the field, and along x
  for (int r = 0; r < kRealisations; ++r) {
    const std::vector<double> g = one_value.draw(stream);
    spread = std::max(spread, *std::max_element(g.begin(), g.end()) - *std::min_element(g.begin(), g.end()));
    variance.add(g[0] * g[0]);
    const std::vector<double> h = layers.draw(stream);
    for (int j = 0; j < grid.ny; ++j)
      for (int i = 1; i < grid.nx; ++i) along_x = std::max(along_x, std::abs(h[grid.index(i, j)] - h[grid.index(0, j)]));
    along_y.add(lag_product(grid, h, h, 0, 2));
  }
  EXPECT_LT(spread, 1e-6);
  EXPECT_LT(along_x, 1e-6);
  expect_matches(variance, 1, 0.25, "one value's variance");
  expect_matches(along_y, std::exp(-1.0), 0.1, "layers at 1 m vertical lag");
}

TEST(RandomField, CrossCorrelatedPairHasItsRho) {
  RandomField friction = field("friction", "friction_angle", RandomDistribution::Normal, 30, 0.1, {4, 2});
  friction.cross_with = "cohesion";
  friction.cross_rho = -0.5;
  const Scene scene = scene_of({field("cohesion", "cohesion", RandomDistribution::Lognormal, 10e3, 0.3, {4, 2}),
                                friction,
                                field("stiffness", "youngs_modulus", RandomDistribution::Lognormal, 1e7, 0.2, {4, 2})});
  const RandomFields fields(scene, small_grid());
  Estimate at_zero, at_lag, variance, independent;
  for (int r = 0; r < kRealisations; ++r) {
    const auto g = fields.gaussian(1000 + r);
    at_zero.add(lag_product(fields.grid(), g[0], g[1], 0, 0));
    at_lag.add(lag_product(fields.grid(), g[0], g[1], 4, 0));
    variance.add(lag_product(fields.grid(), g[1], g[1], 0, 0));
    independent.add(lag_product(fields.grid(), g[0], g[2], 0, 0));
  }
  // Resolution: rho's sign, and a tenth of it.
  expect_matches(at_zero, -0.5, 0.05, "cross-correlation at lag 0");
  expect_matches(at_lag, -0.5 * std::exp(-1.0), 0.05, "cross-correlation at 2 m along x");
  expect_matches(variance, 1, 0.05, "the correlated field's variance");
  expect_matches(independent, 0, 0.05, "a field without cross_correlation");
}

TEST(RandomField, MarginalsHaveTheirMeanAndCov) {
  const Scene scene = scene_of({field("cohesion", "cohesion", RandomDistribution::Lognormal, 10e3, 0.3, {4, 2}),
                                field("stiffness", "youngs_modulus", RandomDistribution::Normal, 1e7, 0.2, {4, 2}),
                                field("friction", "friction_angle", RandomDistribution::Uniform, 30, 0.1, {4, 2})});
  const RandomFields fields(scene, small_grid());
  const std::vector<Eigen::Vector2d> nodes = node_positions(fields.grid());
  std::vector<Estimate> mean(3), variance(3);
  double lowest = kInf, highest = -kInf;  // of the uniform values
  for (int r = 0; r < kRealisations; ++r) {
    const auto g = fields.gaussian(5000 + r);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::vector<double> v = fields.values_at(k, g[k], nodes);
      const double target = fields.field(k).mean;
      double sum = 0, squares = 0;
      for (double x : v) sum += x, squares += (x - target) * (x - target);
      mean[k].add(sum / v.size());
      variance[k].add(squares / v.size());
      if (k == 2) {
        lowest = std::min(lowest, *std::min_element(v.begin(), v.end()));
        highest = std::max(highest, *std::max_element(v.begin(), v.end()));
      }
    }
  }
  // Resolution: 5 % of the mean, 10 % of the variance (a cov off by 5 %).
  for (std::size_t k = 0; k < 3; ++k) {
    const RandomField& f = fields.field(k);
    const double sd = f.cov * f.mean;
    expect_matches(mean[k], f.mean, 0.05 * f.mean, f.name + " mean");
    expect_matches(variance[k], sd * sd, 0.1 * sd * sd, f.name + " variance");
  }
  const double half_width = std::sqrt(3.0) * 0.1 * 30;
  EXPECT_GE(lowest, 30 - half_width);
  EXPECT_LE(highest, 30 + half_width);
  EXPECT_LT(lowest, 30 - 0.99 * half_width);  // the whole range is reached
  EXPECT_GT(highest, 30 + 0.99 * half_width);
}

// A normal friction angle of mean 30 degrees and cov 0.5 is clipped to [0, 90): the clip at 0
// takes P(g < -2) = 2.3 % of the values and moves the mean to E[clip(X, 0, 90)] (X normal).
TEST(RandomField, TruncatedNormalIsClippedAndItsMeanMoves) {
  const Scene scene = scene_of({field("friction", "friction_angle", RandomDistribution::Normal, 30, 0.5, {0.5, 0.5})});
  const RandomFields fields(scene, small_grid());
  const std::vector<Eigen::Vector2d> nodes = node_positions(fields.grid());
  Estimate mean, clipped;
  double highest = 0, lowest = kInf;
  for (int r = 0; r < kRealisations; ++r) {
    const std::vector<double> v = fields.values_at(0, fields.gaussian(r)[0], nodes);
    double sum = 0;
    int zeros = 0;
    for (double x : v) sum += x, zeros += x == 0;
    mean.add(sum / v.size());
    clipped.add(static_cast<double>(zeros) / v.size());
    highest = std::max(highest, *std::max_element(v.begin(), v.end()));
    lowest = std::min(lowest, *std::min_element(v.begin(), v.end()));
  }
  auto Phi = [](double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); };
  auto phi = [](double x) { return std::exp(-x * x / 2) / std::sqrt(2 * std::numbers::pi); };
  const double mu = 30, sigma = 15, a = (0 - mu) / sigma, b = (90 - mu) / sigma;
  const double clipped_mean = 90 * (1 - Phi(b)) + mu * (Phi(b) - Phi(a)) + sigma * (phi(a) - phi(b));  // 30.127
  expect_matches(mean, clipped_mean, clipped_mean - mu, "clipped mean");
  expect_matches(clipped, Phi(a), 0.1 * Phi(a), "share clipped at 0");
  EXPECT_EQ(lowest, 0.0);
  EXPECT_LT(highest, 90.0);
}

TEST(RandomField, PointValuesAreStandardBetweenNodes) {
  const FieldGrid grid = small_grid();
  const Eigen::Vector2d theta(2, 1);  // spacing theta_x / 4, theta_y / 2: plain bilinear would lose 43 %
  const GaussianFieldGenerator generator(grid, Correlation::Markov, theta);
  std::vector<Eigen::Vector2d> centres;
  for (int j = 0; j + 1 < grid.ny; ++j)
    for (int i = 0; i + 1 < grid.nx; ++i) centres.push_back(grid.node(i, j) + grid.spacing / 2);
  const std::vector<Eigen::Vector2d> nodes = node_positions(grid);
  Estimate variance;
  std::mt19937_64 stream(3);
  for (int r = 0; r < kRealisations; ++r) {
    const std::vector<double> g = generator.draw(stream);
    const std::vector<double> at_centres = preproc::gaussian_at(grid, Correlation::Markov, theta, g, centres);
    double squares = 0;
    for (double x : at_centres) squares += x * x;
    variance.add(squares / at_centres.size());
    if (r == 0) {
      EXPECT_EQ(preproc::gaussian_at(grid, Correlation::Markov, theta, g, nodes), g);  // nodes: exact
    }
  }
  expect_matches(variance, 1, 0.05, "variance at cell centres");
}

// The scene's fields and two threads' counts: one seed, the same bits.
Scene pair_scene() {
  RandomField friction = field("friction", "friction_angle", RandomDistribution::Normal, 30, 0.1, {4, 2});
  friction.cross_with = "cohesion";
  friction.cross_rho = 0.3;
  return scene_of({field("cohesion", "cohesion", RandomDistribution::Lognormal, 10e3, 0.3, {4, 2}), friction});
}

bool same_bits(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (a[k].size() != b[k].size() || std::memcmp(a[k].data(), b[k].data(), a[k].size() * sizeof(double)) != 0)
      return false;
  return true;
}

TEST(RandomField, OneSeedGivesTheSameBitsOnAnyThreadCount) {
  const RandomFields fields(pair_scene(), small_grid());
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = fields.gaussian(42);
  omp_set_num_threads(4);
  const auto four = fields.gaussian(42);
  std::vector<std::vector<std::vector<double>>> side_by_side(4);
#pragma omp parallel for num_threads(4)
  for (int t = 0; t < 4; ++t) side_by_side[t] = fields.gaussian(42);  // draw() on four threads at once
  omp_set_num_threads(threads);
  EXPECT_TRUE(same_bits(one, fields.gaussian(42)));
  EXPECT_TRUE(same_bits(one, four));
  for (const auto& g : side_by_side) EXPECT_TRUE(same_bits(one, g));
  EXPECT_FALSE(same_bits(one, fields.gaussian(43)));
  EXPECT_NE(one[0], one[1]);
}

TEST(RandomField, AddingAFieldChangesNoOther) {
  Scene more = pair_scene();
  more.random.insert(more.random.begin(),
                     field("alpha", "youngs_modulus", RandomDistribution::Lognormal, 1e7, 0.2, {1, 1}));
  const auto alone = RandomFields(scene_of({pair_scene().random[0]}), small_grid()).gaussian(7);
  const auto with_others = RandomFields(more, small_grid()).gaussian(7);
  EXPECT_TRUE(same_bits({alone[0]}, {with_others[1]}));
}

// The seeding scheme is fixed (random_field.hpp): its parts against their published values, and
// the first values of one realisation (a change of scheme, order or FFT shows here).
TEST(RandomField, SeedingSchemeIsPinned) {
  EXPECT_EQ(preproc::splitmix64(0), 0xe220a8397b1dcdafULL);      // Vigna's splitmix64.c, seed 0
  EXPECT_EQ(preproc::fnv1a64(""), 0xcbf29ce484222325ULL);        // FNV-1a offset basis
  EXPECT_EQ(preproc::fnv1a64("a"), 0xaf63dc4c8601ec8cULL);       // FNV-1a test vector
  std::mt19937_64 standard;
  standard.discard(9999);
  EXPECT_EQ(standard(), 9981545732273789042ULL);  // C++ [rand.predef]
  const auto g = RandomFields(pair_scene(), small_grid()).gaussian(42);
  const double pinned[] = {-1.9448818363833609, -0.12973337555203057, -0.66210931657276262};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(g[k % 2][k * 100], pinned[k], 1e-12) << k;
}

// The scene's [random.NAME] tables (common/scene/random.cpp), read by load_scene from the bad-input
// table's small valid scene with two fields added.
const char* const kRandomTables = R"(
[random.cohesion]
material = "rock"
parameter = "cohesion"
distribution = "lognormal"
mean = 10e3
cov = 0.3
correlation_length = [20.0, 2.0]
correlation = "markov"

[random.friction]
material = "rock"
parameter = "friction_angle"
distribution = "normal"
mean = 30.0
cov = 0.1
correlation_length = [20.0, 2.0]
cross_correlation = { with = "cohesion", rho = -0.5 }
)";

std::string random_scene(const testing::ScratchDir& dir, const std::string& tables,
                         const std::string& extra_material = "") {
  testing::write_file(dir.path() / "block.geo", testing::kGeo);
  return testing::write_file(dir.path() / "block.toml", testing::kScene + extra_material + tables);
}

TEST(RandomScene, TablesAreReadBack) {
  const testing::ScratchDir dir("random-scene");
  const Scene scene = load_scene(random_scene(dir, kRandomTables), {"random.friction.cov=0.15"});
  ASSERT_EQ(scene.random.size(), 2u);
  const RandomField& c = scene.random[0];
  EXPECT_EQ(c.name, "cohesion");
  EXPECT_EQ(c.material, "rock");
  EXPECT_EQ(c.parameter, "cohesion");
  EXPECT_EQ(c.distribution, RandomDistribution::Lognormal);
  EXPECT_EQ(c.mean, 10e3);
  EXPECT_EQ(c.cov, 0.3);
  EXPECT_EQ(c.correlation_length, Eigen::Vector2d(20, 2));
  EXPECT_EQ(c.correlation, Correlation::Markov);
  EXPECT_EQ(c.cross_with, "");
  const RandomField& f = scene.random[1];
  EXPECT_EQ(f.parameter, "friction_angle");
  EXPECT_EQ(f.distribution, RandomDistribution::Normal);
  EXPECT_EQ(f.cov, 0.15);  // from --set
  EXPECT_EQ(f.cross_with, "cohesion");
  EXPECT_EQ(f.cross_rho, -0.5);
  // The defaults, and inf for a fully correlated axis.
  std::string tables = testing::replaced(kRandomTables, "correlation = \"markov\"\n", "");
  for (int k = 0; k < 2; ++k) tables = testing::replaced(tables, "[20.0, 2.0]", "[inf, inf]");
  const Scene fully = load_scene(random_scene(dir, tables));
  EXPECT_EQ(fully.random[0].correlation, Correlation::Markov);
  EXPECT_TRUE(std::isinf(fully.random[0].correlation_length.x()));
  EXPECT_TRUE(load_scene(random_scene(dir, "")).random.empty());
}

struct BadTable {
  std::string what, from, to;  // the change to kRandomTables
  std::string item;            // the dotted key the one message must name
};

TEST(RandomScene, EachBadKeyIsOneErrorNamingIt) {
  const std::string steel = "\n[materials.steel]\nmodel = \"linear_elastic\"\ndensity = 7800.0\n"
                            "youngs_modulus = 2e11\npoisson_ratio = 0.3\n";
  const std::string strength = "\n[random.strength]\nmaterial = \"rock\"\nparameter = \"cohesion\"\n"
                               "distribution = \"normal\"\nmean = 5e3\ncov = 0.2\ncorrelation_length = [5.0, 1.0]\n";
  const std::string pair = "cross_correlation = { with = \"cohesion\", rho = -0.5 }";
  const std::vector<BadTable> rows = {
      {"unknown key", "correlation = \"markov\"\n", "correlation = \"markov\"\ncolour = 1\n", "random.cohesion.colour"},
      {"not a table", "\n[random.cohesion]", "\n[random]\nbad = 5\n[random.cohesion]", "random.bad"},
      {"name not a word", "[random.cohesion]", "[random.\"co hesion\"]", "random.co hesion"},
      {"bad distribution", "\"lognormal\"", "\"weibull\"", "random.cohesion.distribution"},
      {"cov 0", "cov = 0.3", "cov = 0.0", "random.cohesion.cov"},
      {"cov < 0", "cov = 0.3", "cov = -0.3", "random.cohesion.cov"},
      {"cov inf", "cov = 0.3", "cov = inf", "random.cohesion.cov"},
      {"NaN mean", "mean = 10e3", "mean = nan", "random.cohesion.mean"},
      {"no mean", "mean = 10e3\n", "", "random.cohesion.mean"},
      {"mean out of range", "mean = 30.0", "mean = 95.0", "random.friction.mean"},
      {"mean beyond another parameter", "parameter = \"cohesion\"\ndistribution = \"lognormal\"\nmean = 10e3",
       "parameter = \"dilation_angle\"\ndistribution = \"lognormal\"\nmean = 35.0", "random.cohesion.mean"},
      {"uniform out of range", "\"lognormal\"\nmean = 10e3\ncov = 0.3", "\"uniform\"\nmean = 10e3\ncov = 0.7",
       "random.cohesion.cov"},
      {"unknown material", "material = \"rock\"\nparameter = \"cohesion\"",
       "material = \"clay\"\nparameter = \"cohesion\"", "random.cohesion.material"},
      {"parameter not allowed", "parameter = \"cohesion\"", "parameter = \"density\"", "random.cohesion.parameter"},
      {"parameter of another model", "correlation = \"markov\"\n",
       "correlation = \"markov\"\n" + steel + "\n[random.x]\nmaterial = \"steel\"\nparameter = \"cohesion\"\n",
       "random.x.parameter"},
      {"residual without softening", "parameter = \"cohesion\"", "parameter = \"residual_cohesion\"",
       "random.cohesion.parameter"},
      {"same material and parameter", "correlation = \"markov\"\n", "correlation = \"markov\"\n" + strength,
       "random.strength.parameter"},
      {"lengths not two", "[20.0, 2.0]\ncorrelation", "[20.0]\ncorrelation", "random.cohesion.correlation_length"},
      {"length 0", "[20.0, 2.0]\ncorrelation", "[20.0, 0.0]\ncorrelation", "random.cohesion.correlation_length"},
      {"length NaN", "[20.0, 2.0]\ncorrelation", "[nan, 2.0]\ncorrelation", "random.cohesion.correlation_length"},
      {"no lengths", "correlation_length = [20.0, 2.0]\ncorrelation", "correlation",
       "random.cohesion.correlation_length"},
      {"bad correlation", "\"markov\"", "\"spherical\"", "random.cohesion.correlation"},
      {"cross_correlation not a table", pair, "cross_correlation = 0.5", "random.friction.cross_correlation"},
      {"missing partner", "with = \"cohesion\"", "with = \"strength\"", "random.friction.cross_correlation.with"},
      {"self", "with = \"cohesion\"", "with = \"friction\"", "random.friction.cross_correlation.with"},
      {"rho 1", "rho = -0.5", "rho = 1.0", "random.friction.cross_correlation.rho"},
      {"|rho| > 1", "rho = -0.5", "rho = -1.5", "random.friction.cross_correlation.rho"},
      {"no rho", ", rho = -0.5", "", "random.friction.cross_correlation.rho"},
      {"unknown key in the pair", "rho = -0.5", "rho = -0.5, lag = 1.0", "random.friction.cross_correlation.lag"},
      {"pair given twice", "correlation = \"markov\"\n",
       "correlation = \"markov\"\ncross_correlation = { with = \"friction\", rho = -0.5 }\n",
       "random.cohesion.cross_correlation.with"},
      {"pair of two correlations", "[20.0, 2.0]\ncross", "[10.0, 2.0]\ncross", "random.friction.cross_correlation.with"},
  };
  for (const BadTable& row : rows) {
    const testing::ScratchDir dir("random-scene");
    const std::string path = random_scene(dir, testing::replaced(kRandomTables, row.from, row.to));
    const std::string message = message_of([&] { load_scene(path); });
    EXPECT_EQ(message.rfind(path + ": " + row.item + ": ", 0), 0u) << row.what << ": " << message;
  }
}

}  // namespace
}  // namespace talus
