// The Bishop keys of metrics.json (talus post) and fos.json (talus fos), written by one function
// so that both files say the same thing the same way.
#pragma once
#include <optional>

#include "common/scene/scene.hpp"
#include "postproc/bishop.hpp"
#include "postproc/output.hpp"

namespace talus::postproc {

// bishop_fos, bishop_circle {xc_m, yc_m, r_m}, bishop_entry_m [x, y], bishop_exit_m [x, y],
// bishop_circle_kind ("toe", "face" or "base"), bishop_tangent_to_base, bishop_circles_evaluated;
// all null when there is no admissible circle. `result` is in the scene's frame (see mirrored).
void write_bishop_keys(JsonWriter& json, const std::optional<BishopResult>& result);

// water: null without a water table, else {table_m: [[x, y], ...], unit_weight_N_m3, mode
// ("drained" or "undrained"), rise: [[t_s, dh_m], ...]}: the table Bishop and the solver used.
void write_water_keys(JsonWriter& json, const WaterSettings& water);

}  // namespace talus::postproc
