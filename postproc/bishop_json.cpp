#include "postproc/bishop_json.hpp"

namespace talus::postproc {

void write_bishop_keys(JsonWriter& json, const std::optional<BishopResult>& result) {
  if (!result) {
    for (const char* key : {"bishop_fos", "bishop_circle", "bishop_entry_m", "bishop_exit_m", "bishop_circle_kind",
                            "bishop_tangent_to_base", "bishop_circles_evaluated"})
      json.key(key).null();
    return;
  }
  json.key("bishop_fos").value(result->factor_of_safety);
  json.key("bishop_circle").value(std::optional<Circle>(result->circle));
  json.key("bishop_entry_m").begin_array().value(result->x_entry).value(result->y_entry).end_array();
  json.key("bishop_exit_m").begin_array().value(result->x_exit).value(result->y_exit).end_array();
  json.key("bishop_circle_kind").value(to_string(result->kind));
  json.key("bishop_tangent_to_base").value(result->tangent_to_base);
  json.key("bishop_circles_evaluated").value(result->circles_evaluated);
}

void write_water_keys(JsonWriter& json, const WaterSettings& water) {
  if (!water.enabled()) {
    json.key("water").null();
    return;
  }
  json.key("water").begin_object()
      .key("table_m").value(Polyline(water.table))
      .key("unit_weight_N_m3").value(water.unit_weight)
      .key("mode").value(water_mode_name(water.mode))
      .key("rise").value(Polyline(water.rise))
      .end_object();
}

}  // namespace talus::postproc
