#include "preproc/surface_loads.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.hpp"

namespace talus::preproc {
namespace {

// Pieces are at most this fraction of the particle spacing long, so that a piece between two
// particles goes to the nearer one at this resolution.
constexpr double kPieceFraction = 0.1;

// Particles in square buckets of side `cell`, for the nearest particle that passes a test.
class Buckets {
 public:
  Buckets(const std::vector<Eigen::Vector2d>& points, double cell) : points_(points), cell_(cell) {
    Eigen::AlignedBox2d box;
    for (const auto& x : points) box.extend(x);
    origin_ = box.min();
    columns_ = static_cast<long>(std::floor(box.sizes().x() / cell_)) + 1;
    rows_ = static_cast<long>(std::floor(box.sizes().y() / cell_)) + 1;
    start_.assign(columns_ * rows_ + 1, 0);
    for (const auto& x : points) ++start_[index(x) + 1];
    for (std::size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
    entries_.resize(points.size());
    std::vector<long> fill(start_.begin(), start_.end() - 1);
    for (std::size_t p = 0; p < points.size(); ++p) entries_[fill[index(points[p])]++] = static_cast<int32_t>(p);
  }

  // The nearest point for which accept(p) holds, or -1. Rings of buckets around the query
  // point's, until no nearer point can lie further out.
  template <class Accept>
  int32_t nearest(const Eigen::Vector2d& x, Accept&& accept) const {
    const long cx = clamp(static_cast<long>(std::floor((x.x() - origin_.x()) / cell_)), columns_);
    const long cy = clamp(static_cast<long>(std::floor((x.y() - origin_.y()) / cell_)), rows_);
    int32_t best = -1;
    double best_distance = std::numeric_limits<double>::infinity();
    const long rings = std::max(columns_, rows_);
    for (long r = 0; r <= rings; ++r) {
      for (long j = cy - r; j <= cy + r; ++j)
        for (long i = cx - r; i <= cx + r; ++i) {
          if (std::max(std::abs(i - cx), std::abs(j - cy)) != r) continue;  // the ring only
          if (i < 0 || j < 0 || i >= columns_ || j >= rows_) continue;
          const long b = j * columns_ + i;
          for (long k = start_[b]; k < start_[b + 1]; ++k) {
            const int32_t p = entries_[k];
            const double d = (points_[p] - x).norm();
            if ((d < best_distance || (d == best_distance && p < best)) && accept(p)) best = p, best_distance = d;
          }
        }
      // Points beyond ring r are at least r cells from x (x may lie outside the buckets' box).
      if (best >= 0 && best_distance <= r * cell_) break;
    }
    return best;
  }

 private:
  static long clamp(long k, long count) { return std::min(std::max(k, 0L), count - 1); }
  long index(const Eigen::Vector2d& x) const {
    const long i = clamp(static_cast<long>(std::floor((x.x() - origin_.x()) / cell_)), columns_);
    const long j = clamp(static_cast<long>(std::floor((x.y() - origin_.y()) / cell_)), rows_);
    return j * columns_ + i;
  }

  const std::vector<Eigen::Vector2d>& points_;
  double cell_;
  Eigen::Vector2d origin_;
  long columns_ = 1, rows_ = 1;
  std::vector<long> start_;
  std::vector<int32_t> entries_;
};

// The unit normal of segment a-b pointing out of `region`: the side of the midpoint that is
// not inside it.
Eigen::Vector2d outward_normal(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Region& region) {
  const Eigen::Vector2d t = (b - a).normalized();
  Eigen::Vector2d n(t.y(), -t.x());
  const Eigen::Vector2d mid = 0.5 * (a + b);
  const double offset = 1e-3 * (b - a).norm();
  if (region.contains(mid + offset * n) && !region.contains(mid - offset * n)) n = -n;
  return n;
}

}  // namespace

void distribute_loads(const std::vector<LoadCurve>& curves, const std::vector<Region>& regions, Model& model,
                      const std::string& scene_path) {
  const std::size_t n = model.particle_count();
  model.load.assign(n, -1);
  model.load_length.assign(n, 0);
  model.load_normal.assign(n, Eigen::Vector2d::Zero());
  if (curves.empty() || n == 0) return;
  double volume = 0;
  for (double v : model.volume) volume += v;
  const double spacing = std::sqrt(volume / static_cast<double>(n));
  const Buckets buckets(model.position, 2 * spacing);
  for (std::size_t L = 0; L < curves.size(); ++L) {
    const LoadCurve& curve = curves[L];
    const int32_t load = static_cast<int32_t>(L);
    for (const auto& [a, b, body] : curve.segments) {
      const auto carrier = [&, body = body](int32_t p) {
        return model.body[p] == body && (model.load[p] == -1 || model.load[p] == load);
      };
      const double length = (b - a).norm();
      if (!(length > 0)) continue;
      const Eigen::Vector2d normal = outward_normal(a, b, regions[body]);
      const long pieces = std::max(1L, static_cast<long>(std::ceil(length / (kPieceFraction * spacing))));
      const double piece = length / static_cast<double>(pieces);
      for (long k = 0; k < pieces; ++k) {
        const Eigen::Vector2d x = a + ((k + 0.5) / static_cast<double>(pieces)) * (b - a);
        const int32_t p = buckets.nearest(x, carrier);
        if (p < 0)
          throw Error(located(scene_path, "loads." + curve.name,
                              "no particle of its body is left to carry it (every one carries another load)"));
        model.load[p] = load;
        model.load_length[p] += piece;
        model.load_normal[p] += piece * normal;
      }
    }
  }
}

}  // namespace talus::preproc
