// The oedometric column of the surface-load and undrained tests: an elastic column 0.5 m wide
// and H = 2 m high on a fixed base, rollers on both sides, under a pressure q on its top ("crest"),
// ramped over 0.3 s and damped to rest, gravity off; 0.3 m of empty domain above it.
#pragma once

#include <string>

#include "support/test_support.hpp"

namespace talus::testing {

constexpr double kColumnWidth = 0.5, kColumnHeight = 2.0, kColumnLoad = 1e4, kColumnE = 1e7, kColumnNu = 0.3;

inline const std::string kOedometerColumnGeo = stacked_rectangles_geo(
    kColumnWidth, kColumnHeight, kColumnHeight + 0.3, 0.1,
    "Physical Surface(\"column\") = {1};\nPhysical Curve(\"base\") = {1};\nPhysical Curve(\"crest\") = {3};\n");

// The scene (geometry "scene.geo"), with `material_extra` added to the soil's keys and `extra`
// (whole tables) at the end.
inline std::string oedometer_column_scene(const std::string& material_extra = "", const std::string& extra = "") {
  return R"([scene]
geometry = "scene.geo"

[run]
end_time = 2.0
gravity = [0.0, 0.0]
damping = 0.15

[materials.soil]
model = "linear_elastic"
density = 2000.0
youngs_modulus = 1.0e7
poisson_ratio = 0.3
)" + material_extra +
         R"(
[bodies.column]
material = "soil"

[boundaries.base]
type = "fixed"

[boundaries.left]
type = "roller"

[boundaries.right]
type = "roller"

[loads.surcharge]
group = "crest"
pressure = 1.0e4
ramp = 0.3
)" + extra;
}

}  // namespace talus::testing
