// The analysed body of a model and the slope it forms, as every slope measure sees them: the
// body named by post.body (default the first) and the ground surface of its outer loop in the
// canonical frame (descending towards +x, see Mirror). `talus post` starts here on the metadata
// of a results file, `talus fos` on the model it has just built. Rules: docs/postproc.md.
#pragma once
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "postproc/bishop.hpp"
#include "postproc/pseudo_static.hpp"
#include "postproc/slope_geometry.hpp"

namespace talus::postproc {

// Where the model came from, for the errors (talus::Error, naming the file and the item).
struct Source {
  std::string file;
  // Items spelled as scene keys (post.body, bodies.NAME) rather than as the HDF5 paths of a
  // results file (settings/post@body, bodies/NAME, particles/body).
  bool scene = false;
  std::string needs = "the slope metrics need";  // opens the error on a flat ground surface
};

struct AnalysedBody {
  int index = 0;                       // into Model::bodies
  std::vector<std::size_t> particles;  // the body's particles, in model order
};

// post.body of `model` (default its first body); `body_of` gives each particle's body (Model::body,
// Results::body). Throws when no body has that name, there are no bodies, or it has no particles.
AnalysedBody analysed_body(const Model& model, const std::vector<int32_t>& body_of, const Source& source);

// The bodies of the slope metrics and of `talus fos` together: post.bodies, or post.body alone
// when that list is empty. Throws when a name is unknown or listed twice, or a body has no
// particles.
struct AnalysedBodies {
  std::vector<int> indices;            // into Model::bodies, in the order listed
  std::vector<std::size_t> particles;  // their particles, in model order
};
AnalysedBodies analysed_bodies(const Model& model, const std::vector<int32_t>& body_of, const Source& source);

// Their names, "a", or "a, b and c" for messages.
std::string body_names(const Model& model, const AnalysedBodies& bodies);

struct AnalysedSlope {
  Mirror mirror;          // scene frame <-> canonical frame
  SlopeProfile profile;   // canonical frame
};

// The profile of the body's outer loop. A level-topped body (a column) that moved has its face
// on the side its particles moved to: motion_x is their mean displacement along x (m), 0 when
// not known or none. Throws when the body has no downhill face (a flat layer, or a level top
// that did not move).
AnalysedSlope analysed_slope(const BodyInfo& body, const Source& source, double motion_x = 0);

// The slope formed by several bodies together: the upper envelope of their outer loops
// (slope_profile over loops); one body: exactly as above.
AnalysedSlope analysed_slope(const Model& model, const AnalysedBodies& bodies, const Source& source,
                             double motion_x = 0);

// The positions of the particles `which` of `all`, taken into the canonical frame.
std::vector<Eigen::Vector2d> canonical_positions(const std::vector<Eigen::Vector2d>& all,
                                                 const std::vector<std::size_t>& which, const Mirror& mirror);

// Bishop's critical circle of the slope (bishop_search on the canonical profile), its centre and
// its entry (uphill) and exit back in the scene's frame (mirrored). Empty when none is admissible,
// and for a surface with a vertical face, which a method of slices cannot treat.
std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const SoilStrength& soil);

// The same with the model's water table (none: as above): the material's saturated density below
// the table and the table's pore pressures on the slice bases (WaterTableSoil), the table at t = 0.
std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const Material& material, double gravity,
                                            const WaterSettings& water);

// The surface loads of the analysed bodies' particles (scene frame): Bishop puts their vertical
// components on the slices, each spread over `spacing` (the particle spacing) of x.
struct GroundLoads {
  std::vector<Eigen::Vector2d> position;  // m
  std::vector<Eigen::Vector2d> force;     // N per m, at full load
  double spacing = 0;                     // m
};
// The particles of `bodies` with a non-zero force (`load_force` may be empty: no loads).
GroundLoads ground_loads(const AnalysedBodies& bodies, const std::vector<Eigen::Vector2d>& position,
                         const std::vector<Eigen::Vector2d>& load_force, const std::vector<double>& volume);

// Bishop's critical circle on the analysed bodies with the model's gravity and water table and
// the loads: one body without loads is the single-soil case above; several bodies or loads
// take LayeredGround (slice_model.hpp), each slice's weight from the bodies it crosses and its
// base strength from the body under it. Throws (located at `source`) when a body's material
// is not Mohr-Coulomb.
std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const Model& model,
                                            const AnalysedBodies& bodies, const GroundLoads& loads,
                                            const Source& source);

// The same search (the base and each body's lowest level above it) on any ground in the slope's
// canonical frame, such as a PseudoStatic one; the result in the scene's frame.
std::optional<BishopResult> critical_circle(const AnalysedSlope& slope, const Model& model,
                                            const AnalysedBodies& bodies, const SliceModel& ground);

// The yield coefficient k_y (pseudo_static.hpp) of the analysed bodies with the model's k_v: the
// k_h at which the critical circle has F = 1, to 1e-3. With [seismic] the critical_circle above
// takes the model's k_h and k_v (k_h towards the toe). Empty when the slope has F <= 1 without
// k_h, or no admissible circle. The caller has checked the materials (critical_circle above).
std::optional<YieldCoefficient> yield_coefficient(const AnalysedSlope& slope, const Model& model,
                                                  const AnalysedBodies& bodies, const GroundLoads& loads);

// The LayeredGround of the analysed bodies in the slope's canonical frame.
LayeredGround layered_ground(const AnalysedSlope& slope, const Model& model, const AnalysedBodies& bodies,
                             const GroundLoads& loads);

}  // namespace talus::postproc
