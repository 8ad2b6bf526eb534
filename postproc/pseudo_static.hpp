// Pseudo-static analysis (docs/seismic.md): the ground of a method of slices under the seismic
// coefficients k_h (horizontal, towards the toe, +x in the canonical frame) and k_v (vertical,
// positive upwards), and the yield coefficient k_y, the k_h at which Bishop's critical circle has
// F = 1 (Newmark's critical acceleration k_y g).
#pragma once
#include <functional>
#include <optional>

#include "postproc/bishop.hpp"
#include "postproc/slice_model.hpp"

namespace talus::postproc {

// Each slice of `ground` with its weight W taken as (1 - k_v) W in vertical equilibrium and a
// horizontal force k_h W towards +x at the slice's mid-height (for a uniform soil the centroid of
// the column; for layers or a surface load, an approximation). Bishop's simplified method then
// reads: F = sum[(c b + ((1 - k_v) W - u b) tan phi) / m_alpha] /
// [sum (1 - k_v) W sin alpha + k_h sum W (y_c - y_mid) / R].
class PseudoStatic final : public SliceModel {
 public:
  PseudoStatic(const SliceModel& ground, double k_h, double k_v) : ground_(ground), k_h_(k_h), k_v_(k_v) {}
  SliceForces forces(const Slice& slice) const override {
    SliceForces f = ground_.forces(slice);
    f.horizontal = k_h_ * f.weight;
    f.height = 0.5 * (slice.top + slice.bottom);
    f.weight *= 1 - k_v_;
    return f;
  }

 private:
  const SliceModel& ground_;
  double k_h_, k_v_;
};

// The factor of safety of the critical circle under a seismic coefficient k_h (any search over
// circles: Bishop's, say, on PseudoStatic(ground, k_h, k_v)).
using SeismicSearch = std::function<std::optional<BishopResult>(double k_h)>;

struct YieldCoefficient {
  double k_y = 0;                       // the k_h at which F = 1, within `tolerance`
  std::optional<BishopResult> circle;   // the critical circle at k_y
  int searches = 0;                     // searches run
};

// k_y by bisection on [0, k_max]: F(k_h) of the critical circle falls as k_h grows. Empty when
// F(0) <= 1 (no resistance to spare: k_y = 0 is reported by the caller) or F(k_max) > 1, or when
// no circle is admissible.
std::optional<YieldCoefficient> yield_coefficient(const SeismicSearch& search, double tolerance = 1e-4,
                                                  double k_max = 2);

}  // namespace talus::postproc
