#include "postproc/runout.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace talus::postproc {
namespace {

long column_of(double x, double width) { return static_cast<long>(std::floor(x / width)); }

}  // namespace

ColumnRule column_rule_for(const std::vector<double>& initial_volume) {
  ColumnRule rule;
  if (initial_volume.empty()) return rule;
  std::vector<double> sorted = initial_volume;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double spacing = std::sqrt(std::max(sorted[sorted.size() / 2], 0.0));
  if (spacing > 0) rule.width = 2 * spacing;
  return rule;
}

DepositFront deposit_front(const std::vector<Eigen::Vector2d>& x_p, const std::vector<Eigen::Vector2d>& v_p,
                           const Polyline& initial_surface, const ColumnRule& rule) {
  // Deposit particles by column; std::map keeps the columns ordered along x.
  std::map<long, std::vector<std::size_t>> columns;
  for (std::size_t p = 0; p < x_p.size(); ++p)
    if (x_p[p].y() > surface_height(initial_surface, x_p[p].x()))
      columns[column_of(x_p[p].x(), rule.width)].push_back(p);

  const auto enough = [&](const auto& column) {
    return static_cast<int>(column.second.size()) >= rule.min_particles;
  };
  auto densest = std::max_element(columns.begin(), columns.end(), [](const auto& a, const auto& b) {
    return a.second.size() < b.second.size();
  });
  DepositFront front;
  if (densest == columns.end() || !enough(*densest)) return front;

  auto last = densest;
  for (auto next = std::next(last); next != columns.end() && next->first == last->first + 1 && enough(*next);
       ++next)
    last = next;

  front.found = true;
  front.tip = {-INFINITY, INFINITY};
  double velocity_sum = 0;
  for (std::size_t p : last->second) {
    front.tip.x() = std::max(front.tip.x(), x_p[p].x());
    front.tip.y() = std::min(front.tip.y(), x_p[p].y());
    if (!v_p.empty()) velocity_sum += v_p[p].x();
  }
  front.velocity = velocity_sum / static_cast<double>(last->second.size());
  return front;
}

RunoutMetrics runout_metrics(const SlopeProfile& profile, const std::vector<Eigen::Vector2d>& x0,
                             const std::vector<Eigen::Vector2d>& x1, double drop_threshold, const ColumnRule& rule) {
  RunoutMetrics metrics;

  // Crest retreat: compare the highest particle of each column before and after.
  std::map<long, std::pair<double, double>> tops;  // column -> (initial top, final top)
  for (const auto& p : x0) {
    auto& top = tops.try_emplace(column_of(p.x(), rule.width), -INFINITY, -INFINITY).first->second;
    top.first = std::max(top.first, p.y());
  }
  for (const auto& p : x1) {
    auto found = tops.find(column_of(p.x(), rule.width));
    if (found != tops.end()) found->second.second = std::max(found->second.second, p.y());
  }
  double crown_x = profile.crest.x();
  for (const auto& [column, top] : tops) {
    const double left_edge = column * rule.width;
    if (left_edge + 0.5 * rule.width > profile.toe.x()) break;
    if (top.first - top.second > drop_threshold) {
      crown_x = left_edge;
      break;
    }
  }
  metrics.crest_retreat = std::max(0.0, profile.crest.x() - crown_x);
  metrics.crown = {crown_x, surface_height(profile.surface, crown_x)};

  double highest = -INFINITY;
  for (const auto& p : x1) highest = std::max(highest, p.y());
  metrics.final_height = x1.empty() ? 0 : highest - profile.toe.y();

  const DepositFront front = deposit_front(x1, {}, profile.surface, rule);
  metrics.deposit_found = front.found;
  metrics.tip = front.found ? front.tip : profile.toe;
  if (front.found) {
    metrics.runout_distance = front.tip.x() - profile.toe.x();
    const double fall = metrics.crown.y() - front.tip.y();
    const double reach = front.tip.x() - metrics.crown.x();
    metrics.travel_angle_deg = std::atan2(fall, reach) * 180.0 / M_PI;
  }
  return metrics;
}

std::optional<double> time_to_rest(const std::vector<double>& time, const std::vector<double>& kinetic_energy,
                                   double ratio) {
  if (kinetic_energy.empty()) return std::nullopt;
  const auto peak = std::max_element(kinetic_energy.begin(), kinetic_energy.end());
  if (!(*peak > 0)) return 0.0;
  const double limit = ratio * *peak;
  std::size_t last_above = peak - kinetic_energy.begin();
  for (std::size_t i = last_above; i < kinetic_energy.size(); ++i)
    if (kinetic_energy[i] >= limit) last_above = i;
  if (last_above + 1 >= kinetic_energy.size()) return std::nullopt;
  return time[last_above + 1];
}

}  // namespace talus::postproc
