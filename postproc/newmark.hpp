// Newmark's (1965) rigid sliding block ("Effects of earthquakes on dams and embankments",
// Geotechnique 15(2):139-160): a block that slides one way only (downhill) once the driving
// acceleration exceeds its critical acceleration, and sticks again when its relative velocity
// returns to zero. docs/seismic.md.
#pragma once
#include <functional>
#include <vector>

namespace talus::postproc {

// The block's relative acceleration while it slides is gain x (a_drive(t) - a_c); a_drive is the
// ground's inertial acceleration towards the toe (-a_g,x for a slope descending towards +x).
// For a block of friction coefficient mu = tan(phi) on an incline of angle theta shaken
// horizontally, the relative motion along the incline has a_c = g tan(phi - theta) and
// gain = cos(theta) + mu sin(theta) (the normal force grows with the horizontal push).
struct NewmarkBlock {
  double critical_acceleration = 0;  // a_c (m/s^2)
  double gain = 1;
};

// The incline's block: a_c = g (mu cos theta - sin theta) / (cos theta + mu sin theta).
NewmarkBlock incline_block(double mu, double theta_deg, double g);

struct NewmarkHistory {
  std::vector<double> time;          // s
  std::vector<double> displacement;  // m, relative to the ground, downhill
  std::vector<double> velocity;      // m/s
  double final_displacement() const { return displacement.empty() ? 0.0 : displacement.back(); }
};

// Integrates the block from rest at t0 to t1 with step dt (the trapezoidal rule on the
// velocity, the step's end clipped where the velocity returns to zero), sampling every
// `every` steps and at t1.
NewmarkHistory newmark_sliding(const std::function<double(double)>& a_drive, const NewmarkBlock& block, double t0,
                               double t1, double dt = 1e-5, int every = 100);

}  // namespace talus::postproc

#include <Eigen/Core>

#include "common/scene/seismic.hpp"

namespace talus::postproc {

// The newmark_block metric: a box on an incline of angle_deg descending towards +x, with
// friction mu, on a ground shaken by `motion`. The box's centre-of-mass displacement down the
// incline relative to the ground (results.h5 holds positions in the ground's frame) from the
// motion's start, against Newmark's integration of the same record from the same time.
struct NewmarkBlockCheck {
  NewmarkBlock block;
  std::vector<double> time;     // s, the frames from the motion's start
  std::vector<double> mpm;      // m, down the incline
  std::vector<double> newmark;  // m
  double mpm_final = 0, newmark_final = 0;
  double relative_error = 0;    // |mpm_final - newmark_final| / newmark_final
};

// displacement: the box's centre-of-mass displacement from its initial position at each frame time.
NewmarkBlockCheck newmark_block_check(const std::vector<double>& time, const std::vector<Eigen::Vector2d>& displacement,
                                      double angle_deg, double gravity, double mu, const BaseMotion& motion);

}  // namespace talus::postproc
