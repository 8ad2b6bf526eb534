#include "preproc/initial_state.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "common/error.hpp"
#include "common/model/checks.hpp"

namespace talus::preproc {

// Geostatic stress of horizontally layered ground, tension positive: the weight of the
// material above, sigma_yy = -rho |g| (surface - y), and sigma_xx = sigma_zz = k0 sigma_yy.
// Above the surface there is no overburden. With a water table at height h (at the point's x,
// capped at the surface) the ground below it weighs rho_sat, the pore pressure is
// u = gamma_w (h - y) below it, and k0 acts on the effective stress:
//   sigma'_yy = sigma_yy + u, sigma'_xx = sigma'_zz = k0 sigma'_yy, sigma = sigma' - u I.
Eigen::Vector4d geostatic_stress(const InitialStress& initial, double surface, const Material& material,
                                 double gravity, const WaterSettings& water, const Eigen::Vector2d& point) {
  const double y = point.y();
  if (!water.enabled()) {
    const double sigma_yy = -material.density * gravity * std::max(0.0, surface - y);
    return {initial.k0 * sigma_yy, sigma_yy, initial.k0 * sigma_yy, 0};
  }
  const double table = std::min(water.height(point.x()), surface);
  const double saturated = material.saturated_density > 0 ? material.saturated_density : material.density;
  const double dry_depth = std::max(0.0, surface - std::max(y, table));
  const double wet_depth = std::max(0.0, table - y);
  const double sigma_yy = -gravity * (material.density * dry_depth + saturated * wet_depth);
  const double u = water.pore_pressure(point);
  const double effective_yy = sigma_yy + u;
  return {initial.k0 * effective_yy - u, sigma_yy, initial.k0 * effective_yy - u, 0};
}

// The density of a particle: saturated below the water table (at t = 0), dry above it.
double density_at(const Material& material, const WaterSettings& water, const Eigen::Vector2d& point) {
  if (water.enabled() && material.saturated_density > 0 && point.y() < water.height(point.x()))
    return material.saturated_density;
  return material.density;
}

// A water table must reach over the domain: its x range overlaps the domain's, and it is not
// wholly below it even at its highest rise.
void check_water_table(const WaterSettings& water, const Region& domain, const Scene& scene) {
  if (!water.enabled()) return;
  const Eigen::AlignedBox2d box = domain.bounds();
  double highest = -INFINITY, rise = 0;  // the table's highest point, and its highest rise
  for (const auto& point : water.table) highest = std::max(highest, point.y());
  for (const auto& point : water.rise) rise = std::max(rise, point.y());
  if (water.table.back().x() <= box.min().x() || water.table.front().x() >= box.max().x() ||
      highest + rise <= box.min().y()) {
    std::ostringstream message;
    message << "the table (x from " << water.table.front().x() << " to " << water.table.back().x() << " m, highest y "
            << highest << " m) lies outside the domain (x from " << box.min().x() << " to " << box.max().x()
            << " m, y from " << box.min().y() << " to " << box.max().y() << " m)";
    throw Error(located(scene.path, "water.table", message.str()));
  }
}

// Water standing above the ground is not modelled: its weight on the surface is not applied,
// so soil under it would carry a pore pressure with no load above it (tensile effective stress,
// no strength). The table, at its highest rise, must therefore stay at or below the ground
// wherever there are bodies: the top of the highest particle (y + sqrt(V)/2) of each vertical
// strip two particle spacings wide, within one spacing. Strips without particles are not
// checked (the table may run over empty parts of the domain).
void check_table_below_ground(const WaterSettings& water, const std::vector<Eigen::Vector2d>& position,
                              const std::vector<double>& volume, const Scene& scene) {
  if (!water.enabled() || position.empty()) return;
  // The table is highest at t = 0 or at one of the rise's points (it is linear between them).
  double highest_time = 0, mean_volume = 0, lowest_x = INFINITY;
  for (const auto& point : water.rise)
    if (water.rise_at(point.x()) > water.rise_at(highest_time)) highest_time = point.x();
  const bool risen = !water.rise.empty() && water.rise_at(highest_time) > 0;
  for (std::size_t p = 0; p < position.size(); ++p) {
    mean_volume += volume[p] / static_cast<double>(position.size());
    lowest_x = std::min(lowest_x, position[p].x());
  }
  const double strip = 2 * std::sqrt(mean_volume);
  std::vector<std::ptrdiff_t> top;  // per strip: the particle whose top is highest, or -1
  auto top_of = [&](std::size_t p) { return position[p].y() + 0.5 * std::sqrt(volume[p]); };
  for (std::size_t p = 0; p < position.size(); ++p) {
    const auto k = static_cast<std::size_t>((position[p].x() - lowest_x) / strip);
    if (k >= top.size()) top.resize(k + 1, -1);
    if (top[k] < 0 || top_of(p) > top_of(static_cast<std::size_t>(top[k]))) top[k] = static_cast<std::ptrdiff_t>(p);
  }
  for (const std::ptrdiff_t t : top) {
    if (t < 0) continue;
    const auto p = static_cast<std::size_t>(t);
    const double ground = top_of(p), table = water.height(position[p].x(), highest_time);
    if (table - ground > std::sqrt(volume[p])) {
      std::ostringstream message;
      message << std::setprecision(4) << "at x = " << position[p].x() << " m the table" << (risen ? " at its highest rise" : "")
              << " (y = " << table << " m) is " << table - ground << " m above the ground (y = " << ground
              << " m): water standing above the ground is not modelled (its weight on the surface is not applied); "
                 "let the table follow the ground surface where the water reaches it";
      throw Error(located(scene.path, "water.table", message.str()));
    }
  }
}

void check_initial_state(const Model& model, const Scene& scene) {
  const auto problem = initial_state_problem(model);
  if (!problem) return;
  const Body& body = scene.bodies.at(static_cast<std::size_t>(model.body[problem->particle]));
  const std::string key = "bodies." + body.name + (problem->speed ? ".initial_velocity" : ".initial_stress");
  throw Error(located(scene.path, key, problem->message));
}

}  // namespace talus::preproc
