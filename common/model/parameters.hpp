// The model's run settings listed once, by the names model.h5 and results.h5 give them: writing
// and reading the files (metadata.cpp) and the checkpoint's fingerprint of the physics
// (solver/io/checkpoint.cpp) all visit this list, so a new run setting is one line here (plus its
// scene key and its range). A material's parameters have their own visitor
// (common/materials/materials.hpp, for_each_parameter).
//
// visit(name, value) receives a reference to a double, bool, int, long, Eigen::Vector2d, Transfer or
// ShapeFunctions;
// const when the settings are.
#pragma once
#include <string>

#include "common/scene/scene.hpp"

namespace talus {

template <class Run, class Visit>
void for_each_run_setting(Run& run, Visit&& visit) {
  visit("end_time", run.end_time);
  visit("cfl", run.cfl);
  visit("output_interval", run.output_interval);
  visit("gravity", run.gravity);
  visit("gravity_ramp", run.gravity_ramp);
  visit("damping", run.damping);
  visit("evs", run.evs);
  visit("transfer", run.transfer);
  visit("pic_fraction", run.pic_fraction);
  visit("xpic_order", run.xpic_order);
  visit("full_cell_fill", run.full_cell_fill);
  visit("history_interval", run.history_interval);
  visit("rest_ratio", run.rest_ratio);
  visit("rest_window", run.rest_window);
  visit("max_steps", run.max_steps);
  visit("shape_functions", run.shape_functions);
}

}  // namespace talus
