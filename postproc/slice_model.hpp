// The ground as a method of slices sees it, kept apart from the search for the slip circle:
// per slice, the weight of the column above the slip surface and, at the middle of the slice's
// base, the strength and the pore pressure. Bishop's method (bishop.hpp) asks a SliceModel for
// these and never looks at soil properties itself, so a layered ground, a water table or a
// surcharge is another SliceModel and the same circle search serves it.
#pragma once
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

namespace talus::postproc {

struct SoilStrength {
  double cohesion = 0;        // c' (Pa, or any unit consistent with unit_weight x length)
  double friction_angle = 0;  // phi' (deg)
  double unit_weight = 0;     // gamma = rho g (N/m^3)
};

// One vertical slice of the sliding mass, in the canonical frame (the slope descends towards +x).
struct Slice {
  double x = 0;       // middle of the slice (m)
  double width = 0;   // b (m)
  double top = 0;     // ground surface at x (m)
  double bottom = 0;  // slip surface at x (m), at or below top
};

// What the method needs of one slice.
struct SliceForces {
  double weight = 0;         // W: the column between top and bottom, with any load on it (N per m)
  double cohesion = 0;       // c' at the base (Pa)
  double tan_phi = 0;        // tan(phi') at the base
  double pore_pressure = 0;  // u at the base (Pa)
  // A pseudo-static horizontal force towards +x (the toe), k_h W, and the height it acts at
  // (the slice's mid-height; pseudo_static.hpp). Zero without [seismic].
  double horizontal = 0;     // N per m
  double height = 0;         // m
};

class SliceModel {
 public:
  virtual ~SliceModel() = default;
  virtual SliceForces forces(const Slice& slice) const = 0;
};

// One dry soil throughout: W = gamma b (top - bottom), u = 0.
class UniformSoil final : public SliceModel {
 public:
  explicit UniformSoil(const SoilStrength& soil)
      : soil_(soil), tan_phi_(std::tan(soil.friction_angle * M_PI / 180.0)) {}
  SliceForces forces(const Slice& s) const override {
    return {soil_.unit_weight * s.width * (s.top - s.bottom), soil_.cohesion, tan_phi_, 0.0};
  }

 private:
  SoilStrength soil_;
  double tan_phi_;
};

// One soil with a water table h(x) (canonical frame, any callable of x): the column weighs
// gamma above the table and gamma_sat below it, and the pore pressure at the base is hydrostatic
// in the vertical depth below the table, u = gamma_w max(0, h(x) - bottom) (the convention of
// the solver, docs/water.md). The table is capped at the ground in the weight: water ponded
// above the ground is not a load here.
template <class Table>
class WaterTableSoil final : public SliceModel {
 public:
  WaterTableSoil(const SoilStrength& soil, double saturated_unit_weight, double water_unit_weight, Table table)
      : soil_(soil), tan_phi_(std::tan(soil.friction_angle * M_PI / 180.0)), saturated_(saturated_unit_weight),
        water_(water_unit_weight), table_(std::move(table)) {}
  SliceForces forces(const Slice& s) const override {
    const double h = table_(s.x);
    const double wet_top = std::min(std::max(h, s.bottom), s.top);
    const double weight = s.width * (soil_.unit_weight * (s.top - wet_top) + saturated_ * (wet_top - s.bottom));
    return {weight, soil_.cohesion, tan_phi_, water_ * std::max(0.0, h - s.bottom)};
  }

 private:
  SoilStrength soil_;
  double tan_phi_, saturated_, water_;
  Table table_;
};

// One body of a layered ground (canonical frame): its outline loops (a point is in the body
// when it lies inside an odd number of them), its strength and unit weights.
struct GroundLayer {
  std::vector<std::vector<Eigen::Vector2d>> loops;  // m
  SoilStrength soil;
  double saturated_unit_weight = 0;  // N/m^3, below the water table (without a table: unused)
};

// A force on the ground surface (a surface load carried by one particle, canonical frame),
// spread evenly over `width` of x centred on x.
struct SurfaceForce {
  double x = 0;         // m
  double downward = 0;  // N per m of thickness, the force's vertical component, positive down
};

// Several soils (a layered slope, a weak layer, a body on another) with an optional water table
// and surface loads. Along the vertical through the slice's middle, the column from the slip
// surface up to the ground weighs the unit weight of each body it crosses over the length it
// crosses (gamma above the table, gamma_sat below it); empty space weighs nothing. The base
// takes c' and phi' of the body just above the base point (where two bodies meet there, the
// upper one: the slip surface runs in it), else of the body nearest the point along the
// vertical. The pore pressure is the table's, u = gamma_w max(0, h(x) - bottom). A surface
// force adds its vertical component to the slices under it, in proportion to the overlap of
// its spread with the slice; horizontal components are left out (a pressure on a level crest
// has none).
class LayeredGround final : public SliceModel {
 public:
  LayeredGround(std::vector<GroundLayer> layers, std::vector<SurfaceForce> loads = {}, double load_width = 0,
                double water_unit_weight = 0, std::function<double(double)> table = {});
  SliceForces forces(const Slice& slice) const override;

 private:
  std::vector<GroundLayer> layers_;
  std::vector<double> tan_phi_;
  std::vector<SurfaceForce> loads_;
  double load_width_, water_;
  std::function<double(double)> table_;
};

}  // namespace talus::postproc
