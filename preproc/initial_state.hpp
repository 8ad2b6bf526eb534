// The state the particles start in (preproc.cpp, step 4): geostatic stress under gravity and a
// water table, the density above and below the table, and the checks of the water table
// against the domain and the ground.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "preproc/polygon.hpp"

namespace talus::preproc {

// Geostatic stress of horizontally layered ground, tension positive: the weight of the
// material above, sigma_yy = -rho |g| (surface - y), and sigma_xx = sigma_zz = k0 sigma_yy.
// Above the surface there is no overburden. With a water table at height h (at the point's x,
// capped at the surface) the ground below it weighs rho_sat, the pore pressure is
// u = gamma_w (h - y) below it, and k0 acts on the effective stress:
//   sigma'_yy = sigma_yy + u, sigma'_xx = sigma'_zz = k0 sigma'_yy, sigma = sigma' - u I.
Eigen::Vector4d geostatic_stress(const InitialStress& initial, double surface, const Material& material,
                                 double gravity, const WaterSettings& water, const Eigen::Vector2d& point);

// The density of a particle: saturated below the water table (at t = 0), dry above it.
double density_at(const Material& material, const WaterSettings& water, const Eigen::Vector2d& point);

// A water table must reach over the domain: its x range overlaps the domain's, and it is not
// wholly below it even at its highest rise.
void check_water_table(const WaterSettings& water, const Region& domain, const Scene& scene);

// Water standing above the ground is not modelled: its weight on the surface is not applied,
// so soil under it would carry a pore pressure with no load above it (tensile effective stress,
// no strength). The table, at its highest rise, must therefore stay at or below the ground
// wherever there are bodies: the top of the highest particle (y + sqrt(V)/2) of each vertical
// strip two particle spacings wide, within one spacing. Strips without particles are not
// checked (the table may run over empty parts of the domain).
void check_table_below_ground(const WaterSettings& water, const std::vector<Eigen::Vector2d>& position,
                              const std::vector<double>& volume, const Scene& scene);

// The particles' initial velocities and stresses within the bounds of initial_state_problem
// (common/model/checks.hpp), checked on the built model (after its run settings are set): an
// Error names the body's initial_velocity or initial_stress in the scene.
void check_initial_state(const Model& model, const Scene& scene);

}  // namespace talus::preproc
