// Runout of a failed slope: the deposit's distal tip (robust against stray particles), the
// runout distance from the initial toe, the crest retreat, the travel angle (Fahrboeschung)
// and the front over time; the time to rest from the kinetic energy history. All positions in
// the canonical frame (slope descending towards +x, see slope_geometry.hpp). Rules and their
// reasons: docs/postproc.md.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "postproc/slope_geometry.hpp"

namespace talus::postproc {

// Vertical columns of `width`, aligned to x = 0; a column is part of the deposit when it holds
// at least `min_particles` deposit particles.
struct ColumnRule {
  double width = 1;       // m
  int min_particles = 3;
};

// Width = 2 x the particle spacing sqrt(median initial particle area). A deposit column then
// holds min_particles = 3 particles once the deposit is about 1.5 spacings thick, while a lone
// particle (or a pair) thrown ahead never makes a column.
ColumnRule column_rule_for(const std::vector<double>& initial_volume);

struct DepositFront {
  bool found = false;          // false: no column holds enough particles above the initial ground
  Eigen::Vector2d tip{0, 0};   // x of the farthest particle of the last column, y of its lowest one (m)
  double velocity = 0;         // mean x-velocity of the deposit particles of the last column (m/s)
};

// The deposit is the particles lying above the initial ground surface. Starting from its
// column with the most such particles, walk downhill (+x) through consecutive columns that
// hold at least rule.min_particles of them; the last one is the front. Particles beyond a gap
// (an empty or thin column) are ignored, however many. `velocity` may be empty.
DepositFront deposit_front(const std::vector<Eigen::Vector2d>& x_p, const std::vector<Eigen::Vector2d>& v_p,
                           const Polyline& initial_surface, const ColumnRule& rule);

struct RunoutMetrics {
  bool deposit_found = false;
  double runout_distance = 0;  // tip.x - toe.x (m); 0 without a deposit
  double crest_retreat = 0;    // crest.x - scarp x (m), >= 0
  double final_height = 0;     // highest final particle above the toe (m): the column's H_inf
  std::optional<double> travel_angle_deg;  // atan(H/L) from the crown to the tip; empty without a deposit
  Eigen::Vector2d crown{0, 0};  // head of the failure on the initial surface (m)
  Eigen::Vector2d tip{0, 0};    // deposit tip (m)
};

// x0: initial positions, x1: final positions of the analysed body's particles. The scarp is
// the most uphill column (upslope of the toe) whose highest particle dropped by more than
// drop_threshold; its uphill edge is the crown's x (so the retreat is exact to one column width).
// Without such a column the crown is the crest.
RunoutMetrics runout_metrics(const SlopeProfile& profile, const std::vector<Eigen::Vector2d>& x0,
                             const std::vector<Eigen::Vector2d>& x1, double drop_threshold, const ColumnRule& rule);

// First time after the peak of the kinetic energy from which it stays below ratio x peak to the
// end of the record. 0 when nothing ever moved; empty when the run ends still moving.
std::optional<double> time_to_rest(const std::vector<double>& time, const std::vector<double>& kinetic_energy,
                                   double ratio = 0.01);

}  // namespace talus::postproc
