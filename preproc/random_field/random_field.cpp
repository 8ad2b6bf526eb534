// Random fields (random_field.hpp): the grid, the correlation forms, the seeding and the
// circulant-embedding generator. The marginals and the scene's fields: random_field_values.cpp.
#include "preproc/random_field/random_field.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <new>
#include <numbers>
#include <sstream>

#include "common/error.hpp"

namespace talus::preproc {
namespace {

// FFTW's planner is not thread-safe (only fftw_execute is): plans are made and destroyed under
// this lock, so that generators may be built on several threads at once.
std::mutex& planner_lock() {
  static std::mutex lock;
  return lock;
}

// FFTW_ESTIMATE chooses the algorithm by a fixed heuristic (FFTW_MEASURE times them, and may
// choose differently run to run); FFTW_NO_SIMD keeps the choice off the CPU's vector units,
// which FFTW detects at run time, so that every x86-64 machine rounds alike.
constexpr unsigned kPlanFlags = FFTW_ESTIMATE | FFTW_NO_SIMD;

// Eigenvalues below this share of the largest are round-off, taken as 0 (random_field.hpp).
constexpr double kRoundOff = 1e-10;
constexpr int kMaxPadding = 8;

// The smallest n' >= n whose prime factors are 2, 3, 5 and 7, the sizes FFTW's codelets cover.
int fft_size(int n) {
  for (int m = std::max(n, 1);; ++m) {
    int r = m;
    for (int p : {2, 3, 5, 7})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

// A torus side for n grid nodes, padded p times: at least 2 (n - 1) p, one node when n is 1.
int torus_side(int n, int p) { return n == 1 ? 1 : fft_size(2 * (n - 1) * p); }

template <class T>
struct FftwBuffer {
  explicit FftwBuffer(std::size_t n) : data(static_cast<T*>(fftw_malloc(sizeof(T) * std::max<std::size_t>(n, 1)))) {
    if (!data) throw std::bad_alloc();
  }
  ~FftwBuffer() { fftw_free(data); }
  FftwBuffer(const FftwBuffer&) = delete;
  FftwBuffer& operator=(const FftwBuffer&) = delete;
  T* data;
};

}  // namespace

FieldGrid grid_over(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const Eigen::Vector2d& max_spacing) {
  if (!(hi.array() >= lo.array()).all() || !lo.allFinite() || !hi.allFinite() || !(max_spacing.minCoeff() > 0))
    throw Error("internal error: grid_over needs a finite box and spacings > 0");
  FieldGrid grid;
  grid.origin = lo;
  int* counts[2] = {&grid.nx, &grid.ny};
  for (int a = 0; a < 2; ++a) {
    const double length = hi[a] - lo[a];
    const int cells = static_cast<int>(std::ceil(length / max_spacing[a] - 1e-9));
    *counts[a] = std::max(cells, 0) + 1;
    grid.spacing[a] = cells > 0 ? length / cells : max_spacing[a];
  }
  return grid;
}

Eigen::Vector2d field_spacing(double particle_spacing, const Eigen::Vector2d& correlation_length) {
  return (correlation_length / 4).cwiseMin(particle_spacing);
}

double correlation(Correlation form, const Eigen::Vector2d& theta, double tx, double ty) {
  const double sx = tx / theta.x(), sy = ty / theta.y();
  switch (form) {
    case Correlation::Markov: return std::exp(-2 * std::sqrt(sx * sx + sy * sy));
    case Correlation::Gaussian: return std::exp(-std::numbers::pi * (sx * sx + sy * sy));
  }
  return 0;
}

const char* correlation_name(Correlation form) {
  return form == Correlation::Markov ? "markov" : "gaussian";
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

std::uint64_t fnv1a64(const std::string& text) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) hash = (hash ^ c) * 0x100000001b3ULL;
  return hash;
}

std::uint64_t field_stream_seed(std::uint64_t seed, const std::string& name) {
  return splitmix64(splitmix64(seed) ^ fnv1a64(name));
}

void standard_normals(std::mt19937_64& stream, double* out, std::size_t n) {
  constexpr double kUnit = 1.0 / 9007199254740992.0;  // 2^-53
  for (std::size_t k = 0; k < n; k += 2) {
    const double u1 = static_cast<double>((stream() >> 11) + 1) * kUnit;
    const double u2 = static_cast<double>(stream() >> 11) * kUnit;
    const double r = std::sqrt(-2 * std::log(u1));
    const double angle = 2 * std::numbers::pi * u2;
    out[k] = r * std::cos(angle);
    if (k + 1 < n) out[k + 1] = r * std::sin(angle);
  }
}

struct GaussianFieldGenerator::Fft {
  fftw_plan forward = nullptr, backward = nullptr;  // r2c and c2r of the My x Mx torus
  ~Fft() {
    std::lock_guard<std::mutex> hold(planner_lock());
    if (forward) fftw_destroy_plan(forward);
    if (backward) fftw_destroy_plan(backward);
  }
};

GaussianFieldGenerator::GaussianFieldGenerator(const FieldGrid& grid, Correlation form, const Eigen::Vector2d& theta)
    : grid_(grid), form_(form), theta_(theta) {
  if (!(theta.minCoeff() > 0) || grid.nx < 1 || grid.ny < 1)  // inf: fully correlated
    throw Error("internal error: a random field needs correlation lengths > 0 and a grid");
  double worst = 0;  // the last torus's smallest eigenvalue over its largest
  for (padding_ = 1; padding_ <= kMaxPadding; padding_ *= 2) {
    mx_ = torus_side(grid.nx, padding_);
    my_ = torus_side(grid.ny, padding_);
    const int half = mx_ / 2 + 1;
    FftwBuffer<double> row(static_cast<std::size_t>(mx_) * my_);
    FftwBuffer<fftw_complex> spectrum(static_cast<std::size_t>(my_) * half);
    for (int ly = 0; ly < my_; ++ly)
      for (int lx = 0; lx < mx_; ++lx)
        row.data[static_cast<std::size_t>(ly) * mx_ + lx] = correlation(
            form, theta, std::min(lx, mx_ - lx) * grid.spacing.x(), std::min(ly, my_ - ly) * grid.spacing.y());
    fftw_plan plan;
    {
      std::lock_guard<std::mutex> hold(planner_lock());
      plan = fftw_plan_dft_r2c_2d(my_, mx_, row.data, spectrum.data, kPlanFlags);
    }
    fftw_execute(plan);
    {
      std::lock_guard<std::mutex> hold(planner_lock());
      fftw_destroy_plan(plan);
    }
    // The row is even in each lag, so its DFT is real: the eigenvalues.
    const std::size_t count = static_cast<std::size_t>(my_) * half;
    double largest = 0, smallest = 0;
    for (std::size_t k = 0; k < count; ++k) {
      largest = std::max(largest, spectrum.data[k][0]);
      smallest = std::min(smallest, spectrum.data[k][0]);
    }
    worst = smallest / largest;
    if (smallest < -kRoundOff * largest) continue;
    const double n = static_cast<double>(mx_) * my_;
    scale_.resize(count);
    for (std::size_t k = 0; k < count; ++k) scale_[k] = std::sqrt(std::max(spectrum.data[k][0], 0.0)) / n;
    break;
  }
  if (padding_ > kMaxPadding) {
    std::ostringstream message;
    message << "the " << correlation_name(form) << " correlation with correlation_length [" << theta.x() << ", "
            << theta.y() << "] m cannot be drawn exactly over the " << (grid.nx - 1) * grid.spacing.x() << " x "
            << (grid.ny - 1) * grid.spacing.y()
            << " m domain: its circulant embedding keeps negative eigenvalues (the smallest " << worst
            << " of the largest) even on a torus " << kMaxPadding
            << " times the minimal one; give a shorter correlation_length, or inf along an axis for a field "
               "fully correlated along it";
    if (form == Correlation::Gaussian) message << " or correlation = \"markov\"";
    throw Error(message.str());
  }
  fft_ = std::make_unique<Fft>();
  FftwBuffer<double> real(static_cast<std::size_t>(mx_) * my_);
  FftwBuffer<fftw_complex> complex(static_cast<std::size_t>(my_) * (mx_ / 2 + 1));
  std::lock_guard<std::mutex> hold(planner_lock());
  fft_->forward = fftw_plan_dft_r2c_2d(my_, mx_, real.data, complex.data, kPlanFlags);
  fft_->backward = fftw_plan_dft_c2r_2d(my_, mx_, complex.data, real.data, kPlanFlags);
  if (!fft_->forward || !fft_->backward) throw Error("internal error: FFTW made no plan for the random field");
}

GaussianFieldGenerator::~GaussianFieldGenerator() = default;
GaussianFieldGenerator::GaussianFieldGenerator(GaussianFieldGenerator&&) noexcept = default;
GaussianFieldGenerator& GaussianFieldGenerator::operator=(GaussianFieldGenerator&&) noexcept = default;

std::vector<double> GaussianFieldGenerator::draw(std::mt19937_64& stream) const {
  const std::size_t n = static_cast<std::size_t>(mx_) * my_;
  FftwBuffer<double> real(n);  // fftw_malloc: the plans' alignment, for the new-array execute
  FftwBuffer<fftw_complex> complex(scale_.size());
  standard_normals(stream, real.data, n);
  fftw_execute_dft_r2c(fft_->forward, real.data, complex.data);
  for (std::size_t k = 0; k < scale_.size(); ++k) {
    complex.data[k][0] *= scale_[k];
    complex.data[k][1] *= scale_[k];
  }
  fftw_execute_dft_c2r(fft_->backward, complex.data, real.data);
  std::vector<double> field(grid_.size());
  for (int j = 0; j < grid_.ny; ++j)
    std::copy_n(real.data + static_cast<std::size_t>(j) * mx_, grid_.nx, field.begin() + grid_.index(0, j));
  return field;
}

}  // namespace talus::preproc
