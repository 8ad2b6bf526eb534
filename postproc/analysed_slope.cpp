#include "postproc/analysed_slope.hpp"

#include <algorithm>

#include "common/error.hpp"

namespace talus::postproc {

AnalysedBody analysed_body(const Model& model, const std::vector<int32_t>& body_of, const Source& source) {
  const auto& bodies = model.bodies;
  const std::string& wanted = model.post.body;
  AnalysedBody selection;
  if (!wanted.empty()) {
    const auto found = std::find_if(bodies.begin(), bodies.end(), [&](const BodyInfo& b) { return b.name == wanted; });
    if (found == bodies.end())
      throw Error(located(source.file, source.scene ? "post.body" : "settings/post@body",
                          "no body named '" + wanted + "'"));
    selection.index = static_cast<int>(found - bodies.begin());
  }
  if (bodies.empty()) throw Error(located(source.file, "bodies", "no bodies"));
  for (std::size_t p = 0; p < body_of.size(); ++p)
    if (body_of[p] == selection.index) selection.particles.push_back(p);
  if (selection.particles.empty())
    throw Error(located(source.file, source.scene ? "bodies." + bodies[selection.index].name : "particles/body",
                        "body '" + bodies[selection.index].name + "' has no particles"));
  return selection;
}

AnalysedSlope analysed_slope(const BodyInfo& body, const Source& source, double motion_x) {
  AnalysedSlope slope;
  const Polyline& loop = outer_loop(body.loops);
  slope.mirror.active = descends_to_left(loop, motion_x);
  Polyline canonical;
  for (const auto& p : loop) canonical.push_back(slope.mirror.point(p));
  slope.profile = slope_profile(canonical, motion_x != 0);
  if (!(slope.profile.height > 0))
    throw Error(located(source.file, (source.scene ? "bodies." : "bodies/") + body.name,
                        source.needs + " a slope, but the ground surface is flat"));
  return slope;
}

std::vector<Eigen::Vector2d> canonical_positions(const std::vector<Eigen::Vector2d>& all,
                                                 const std::vector<std::size_t>& which, const Mirror& mirror) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(which.size());
  for (std::size_t p : which) out.push_back(mirror.point(all[p]));
  return out;
}

std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const SoilStrength& soil) {
  if (has_vertical_face(slope.profile.surface)) return std::nullopt;
  std::optional<BishopResult> bishop = bishop_search(slope.profile, soil);
  if (bishop) bishop = mirrored(*bishop, slope.mirror);
  return bishop;
}

std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const Material& material, double gravity,
                                            const WaterSettings& water) {
  const SoilStrength soil{material.cohesion, material.friction_angle, material.density * gravity};
  if (!water.enabled()) return critical_circle(slope, soil);
  if (has_vertical_face(slope.profile.surface)) return std::nullopt;
  const double saturated = (material.saturated_density > 0 ? material.saturated_density : material.density) * gravity;
  const Mirror mirror = slope.mirror;
  const WaterTableSoil ground(soil, saturated, water.unit_weight,
                              [&water, mirror](double x) { return water.height(mirror.x(x)); });
  std::optional<BishopResult> bishop = bishop_search(slope.profile, ground);
  if (bishop) bishop = mirrored(*bishop, slope.mirror);
  return bishop;
}

}  // namespace talus::postproc
