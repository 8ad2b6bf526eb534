#include "postproc/analysed_slope.hpp"

#include "postproc/pseudo_static.hpp"

#include <algorithm>

#include "common/error.hpp"
#include "postproc/runout.hpp"

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

AnalysedBodies analysed_bodies(const Model& model, const std::vector<int32_t>& body_of, const Source& source) {
  if (model.post.bodies.empty()) {
    const AnalysedBody one = analysed_body(model, body_of, source);
    return {{one.index}, one.particles};
  }
  const auto& bodies = model.bodies;
  const std::string item = source.scene ? "post.bodies" : "settings/post/bodies";
  AnalysedBodies selection;
  for (const std::string& wanted : model.post.bodies) {
    const auto found = std::find_if(bodies.begin(), bodies.end(), [&](const BodyInfo& b) { return b.name == wanted; });
    if (found == bodies.end()) throw Error(located(source.file, item, "no body named '" + wanted + "'"));
    const int index = static_cast<int>(found - bodies.begin());
    if (std::find(selection.indices.begin(), selection.indices.end(), index) != selection.indices.end())
      throw Error(located(source.file, item, "body '" + wanted + "' is listed twice"));
    selection.indices.push_back(index);
  }
  std::vector<char> counted(bodies.size(), 0), seen(bodies.size(), 0);
  for (int index : selection.indices) counted[index] = 1;
  for (std::size_t p = 0; p < body_of.size(); ++p)
    if (counted[body_of[p]]) selection.particles.push_back(p), seen[body_of[p]] = 1;
  for (int index : selection.indices)
    if (!seen[index])
      throw Error(located(source.file, source.scene ? "bodies." + bodies[index].name : "particles/body",
                          "body '" + bodies[index].name + "' has no particles"));
  return selection;
}

std::string body_names(const Model& model, const AnalysedBodies& bodies) {
  std::string out;
  for (std::size_t k = 0; k < bodies.indices.size(); ++k) {
    if (k > 0) out += k + 1 == bodies.indices.size() ? " and " : ", ";
    out += model.bodies[bodies.indices[k]].name;
  }
  return out;
}

AnalysedSlope analysed_slope(const Model& model, const AnalysedBodies& bodies, const Source& source,
                             double motion_x) {
  if (bodies.indices.size() == 1) return analysed_slope(model.bodies[bodies.indices.front()], source, motion_x);
  std::vector<Polyline> loops;
  for (int index : bodies.indices) loops.push_back(outer_loop(model.bodies[index].loops));
  AnalysedSlope slope;
  slope.mirror.active = descends_to_left(loops, motion_x);
  for (auto& loop : loops)
    for (auto& p : loop) p = slope.mirror.point(p);
  slope.profile = slope_profile(loops, motion_x != 0);
  if (!(slope.profile.height > 0))
    throw Error(located(source.file, source.scene ? "post.bodies" : "settings/post/bodies",
                        source.needs + " a slope, but the ground surface of " + body_names(model, bodies) +
                            " is flat"));
  return slope;
}

std::vector<Eigen::Vector2d> canonical_positions(const std::vector<Eigen::Vector2d>& all,
                                                 const std::vector<std::size_t>& which, const Mirror& mirror) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(which.size());
  for (std::size_t p : which) out.push_back(mirror.point(all[p]));
  return out;
}

namespace {

// c and phi of a material that has them (the callers check), with its unit weight.
SoilStrength soil_strength(const Material& material, double gravity) {
  const CohesionFriction strength = limit_equilibrium_strength(material).value();
  return {strength.cohesion, strength.friction_angle, material.density * gravity};
}

}  // namespace

std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const SoilStrength& soil) {
  if (has_vertical_face(slope.profile.surface)) return std::nullopt;
  std::optional<BishopResult> bishop = bishop_search(slope.profile, soil);
  if (bishop) bishop = mirrored(*bishop, slope.mirror);
  return bishop;
}

std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const Material& material, double gravity,
                                            const WaterSettings& water) {
  const SoilStrength soil = soil_strength(material, gravity);
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


GroundLoads ground_loads(const AnalysedBodies& bodies, const std::vector<Eigen::Vector2d>& position,
                         const std::vector<Eigen::Vector2d>& load_force, const std::vector<double>& volume) {
  GroundLoads loads;
  if (load_force.empty()) return loads;
  std::vector<double> v;
  for (std::size_t p : bodies.particles) {
    v.push_back(volume[p]);
    if (load_force[p].x() != 0 || load_force[p].y() != 0)
      loads.position.push_back(position[p]), loads.force.push_back(load_force[p]);
  }
  loads.spacing = 0.5 * column_rule_for(v).width;
  return loads;
}

LayeredGround layered_ground(const AnalysedSlope& slope, const Model& model, const AnalysedBodies& bodies,
                             const GroundLoads& loads) {
  const double gravity = model.run.gravity.norm();
  std::vector<GroundLayer> layers;
  for (int index : bodies.indices) {
    const BodyInfo& body = model.bodies[index];
    const Material& material = model.materials[body.material];
    GroundLayer layer;
    for (const auto& loop : body.loops) {
      Polyline canonical;
      for (const auto& p : loop) canonical.push_back(slope.mirror.point(p));
      layer.loops.push_back(std::move(canonical));
    }
    layer.soil = soil_strength(material, gravity);
    layer.saturated_unit_weight = (material.saturated_density > 0 ? material.saturated_density : material.density) * gravity;
    layers.push_back(std::move(layer));
  }
  std::vector<SurfaceForce> forces;
  for (std::size_t k = 0; k < loads.force.size(); ++k)
    forces.push_back({slope.mirror.x(loads.position[k].x()), -loads.force[k].y()});
  if (!model.water.enabled()) return LayeredGround(std::move(layers), std::move(forces), loads.spacing);
  const Mirror mirror = slope.mirror;
  const WaterSettings water = model.water;
  return LayeredGround(std::move(layers), std::move(forces), loads.spacing, water.unit_weight,
                       [water, mirror](double x) { return water.height(mirror.x(x)); });
}

std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const Model& model,
                                            const AnalysedBodies& bodies, const GroundLoads& loads,
                                            const Source& source) {
  for (int index : bodies.indices) {
    const Material& material = model.materials[model.bodies[index].material];
    if (!limit_equilibrium_strength(material))
      throw Error(located(source.file, (source.scene ? "materials." : "materials/") + material.name,
                          "Bishop's method needs a Mohr-Coulomb material (cohesion and friction angle); body '" +
                              model.bodies[index].name + "' is not"));
  }
  if (bodies.indices.size() == 1 && loads.force.empty() && !model.seismic.enabled())
    return critical_circle(slope, model.materials[model.bodies[bodies.indices.front()].material],
                           model.run.gravity.norm(), model.water);
  if (has_vertical_face(slope.profile.surface)) return std::nullopt;
  const LayeredGround layered = layered_ground(slope, model, bodies, loads);
  if (model.seismic.enabled())
    return critical_circle(slope, model, bodies, PseudoStatic(layered, model.seismic.k_h, model.seismic.k_v));
  return critical_circle(slope, model, bodies, layered);
}

std::optional<YieldCoefficient> yield_coefficient(const AnalysedSlope& slope, const Model& model,
                                                  const AnalysedBodies& bodies, const GroundLoads& loads) {
  if (has_vertical_face(slope.profile.surface)) return std::nullopt;
  const LayeredGround layered = layered_ground(slope, model, bodies, loads);
  return yield_coefficient(
      [&](double k_h) { return critical_circle(slope, model, bodies, PseudoStatic(layered, k_h, model.seismic.k_v)); },
      1e-3);
}

std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const Model& model,
                                            const AnalysedBodies& bodies, const SliceModel& ground) {
  if (has_vertical_face(slope.profile.surface)) return std::nullopt;
  // A critical circle may stay in an upper layer, tangent to the bottom of it (a slope on a
  // strong foundation): the search, which reaches the base exactly, runs again with each body's
  // lowest level above the base as the base.
  std::vector<double> levels{slope.profile.base_y};
  const double near = 1e-6 * slope.profile.height;
  for (int index : bodies.indices) {
    const Polyline& loop = outer_loop(model.bodies[index].loops);
    const double lowest =
        std::min_element(loop.begin(), loop.end(), [](const auto& a, const auto& b) { return a.y() < b.y(); })->y();
    if (lowest > slope.profile.base_y + near && lowest < slope.profile.crest.y() - near &&
        std::none_of(levels.begin(), levels.end(), [&](double y) { return std::abs(y - lowest) <= near; }))
      levels.push_back(lowest);
  }
  std::optional<BishopResult> bishop;
  long evaluated = 0;
  for (double level : levels) {
    SlopeProfile profile = slope.profile;
    profile.base_y = level;
    const std::optional<BishopResult> found = bishop_search(profile, ground);
    if (!found) continue;
    evaluated += found->circles_evaluated;
    if (!bishop || found->factor_of_safety < bishop->factor_of_safety) bishop = found;
  }
  if (!bishop) return bishop;
  bishop->circles_evaluated = evaluated;
  return mirrored(*bishop, slope.mirror);
}

}  // namespace talus::postproc
