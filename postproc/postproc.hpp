// talus post: the postprocessor's public entry point. Reads results.h5, computes the metrics
// the scene's [post] metrics list asks for, writes OUT/metrics.json and the CSV histories, draws
// the figures with postproc/figures.py, and prints a short summary.
//
//   metrics "runout"          runout_distance_m, crest_retreat_m, travel_angle_deg,
//                             time_to_rest_s; front.csv (time_s, front_x_m, front_velocity_m_s)
//   metrics "failure_surface" failed_area_m2, failure_surface [[x, y], ...], slip_circle
//                             {xc_m, yc_m, r_m}, onset_time_s, shear_band [[x, y], ...]
//   metrics "bishop"          bishop_fos, bishop_circle {xc_m, yc_m, r_m}, bishop_entry_m,
//                             bishop_exit_m, bishop_circle_kind, bishop_tangent_to_base,
//                             bishop_circles_evaluated, bishop_soil
//   metrics "spring_mass"     spring_mass {...}; spring_mass.csv (time_s, mpm_m, exact_m)
//   metrics "box_incline"     box_incline {...}; box_incline.csv (time_s, mpm_m, exact_m)
//   always                    energy.csv (time_s, kinetic_J, potential_J, strain_J)
//
// Definitions and rules: docs/postproc.md. The library's parts, for use on their own:
// slope_geometry.hpp, runout.hpp, failure_surface.hpp, circle_fit.hpp, bishop.hpp,
// validation.hpp, results.hpp, output.hpp, figure_script.hpp.
#pragma once
#include <ostream>
#include <string>

#include "postproc/figure_script.hpp"

namespace talus::postproc {

struct PostOptions {
  // postproc/figures.py. Empty: TALUS_SOURCE_DIR/postproc/figures.py when the library was
  // compiled with that definition, else no figures (said in the log).
  std::string figures_script;
  std::string python = "/usr/bin/python3";  // the interpreter that has matplotlib and h5py
  bool figures = true;
};

// Returns 0 when everything was written, 1 when the metrics were written but the figures
// failed (the log says why). Throws talus::Error on unreadable or inconsistent results and on
// a scene whose metrics cannot be computed (an unknown metric, a flat "slope", Bishop on an
// elastic material), naming the file and the item.
int run_post(const std::string& results_path, const std::string& out_dir, std::ostream& log,
             const PostOptions& options = {});

}  // namespace talus::postproc
