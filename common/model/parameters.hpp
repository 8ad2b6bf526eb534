// The model's numeric settings listed once, by the names model.h5 and results.h5 give them:
// writing and reading the files (model.cpp) and the checkpoint's fingerprint of the physics
// (solver/io/checkpoint.cpp) all visit these lists, so a new run setting or material parameter
// is one line here (plus its scene key and its range).
//
// visit(name, value) receives a reference to a double, bool, int, long, Eigen::Vector2d or Transfer;
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
}

// The numeric parameters of a material (its name and model are kept apart).
template <class M, class Visit>
void for_each_material_parameter(M& material, Visit&& visit) {
  visit("density", material.density);
  visit("youngs_modulus", material.youngs_modulus);
  visit("poisson_ratio", material.poisson_ratio);
  visit("friction_angle", material.friction_angle);
  visit("cohesion", material.cohesion);
  visit("dilation_angle", material.dilation_angle);
  visit("tensile_strength", material.tensile_strength);
  visit("saturated_density", material.saturated_density);
  visit("porosity", material.porosity);
  visit("residual_cohesion", material.residual_cohesion);
  visit("residual_friction_angle", material.residual_friction_angle);
  visit("residual_dilation_angle", material.residual_dilation_angle);
  visit("softening_start", material.softening_start);
  visit("softening_end", material.softening_end);
  visit("softening_reference_size", material.softening_reference_size);
}

// The parameters added after the first model format: a file without them gets the defaults.
inline bool optional_material_parameter(const std::string& name) {
  return name == "saturated_density" || name == "porosity" || name.rfind("residual_", 0) == 0 ||
         name.rfind("softening_", 0) == 0;
}

}  // namespace talus
