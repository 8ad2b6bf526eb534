// Surface loads on the particles: each loaded curve is cut into short pieces, and each piece's
// length and outward normal go to the nearest particle of the body it bounds. The shares of a
// load sum to its curve's length, so the total force is the requested one however the
// particles lie; a particle carries one load (where two loads meet, a piece goes to the
// nearest particle that carries no other load).
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "preproc/polygon.hpp"

namespace talus::preproc {

struct LoadSegment {
  Eigen::Vector2d a, b;
  int32_t body = 0;  // the body on whose outline the segment lies
};

struct LoadCurve {
  std::string name;  // the scene's loads.NAME, for messages
  std::vector<LoadSegment> segments;
};

// Fills model.load, model.load_length and model.load_normal (indexed like model.position) from
// the curves, in the order of model.loads. `regions` are the bodies' regions, to orient the
// normals outward. Throws talus::Error naming `scene_path` and the load when a body has no
// particle left to carry a piece.
void distribute_loads(const std::vector<LoadCurve>& curves, const std::vector<Region>& regions, Model& model,
                      const std::string& scene_path);

}  // namespace talus::preproc
