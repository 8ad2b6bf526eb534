// Shared helpers for the test suite: scratch folders, running the talus binary, and small
// models generated in code (no pasted tables).
#pragma once
#include <filesystem>
#include <string>

#include "common/model.hpp"

namespace talus::testing {

// A fresh, empty folder under the build's temporary area, removed when the object dies.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag);
  ~ScratchDir();
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

struct CommandResult {
  int status = -1;     // exit status, or 128 + signal
  std::string output;  // stdout and stderr together
};

// Runs `build/bin/talus ARGS` through the shell, capturing its output.
CommandResult run_talus(const std::string& args);
CommandResult run_shell(const std::string& command);

// Absolute path of a file in the source tree, e.g. source_path("geometries/slope.toml").
std::string source_path(const std::string& relative);

// A structured background mesh of the rectangle [x0, x0 + nx h] x [y0, y0 + ny h], each
// square cut into two counter-clockwise triangles, with neighbours filled in and node sets
// "bottom", "top", "left", "right". No particles, bodies or materials.
Model rectangle_mesh(double x0, double y0, int nx, int ny, double h);

// Adds a body of one material filling the box [x0, x1] x [y0, y1] of the mesh: particles at
// the four-point barycentric positions of every triangle whose centroid lies in the box,
// each with a quarter of the triangle's area. Returns the body's index.
int add_box_body(Model& model, const std::string& name, const Material& material, double x0, double x1, double y0,
                 double y1, bool fixed = false);

// Adds a body of one material filling the disc of `radius` around `centre`: the same
// four-point positions as add_box_body, kept per point, so the rim follows the circle to
// within a quarter of a triangle. Its outline is a 64-gon. Returns the body's index.
int add_disc_body(Model& model, const std::string& name, const Material& material, const Eigen::Vector2d& centre,
                  double radius);

// Fixes the "bottom" node set and puts the "left" and "right" sets on rollers (normal x), the
// usual support of a column or block on rectangle_mesh.
void fix_base_roll_sides(Model& model);

// A linear elastic material.
Material elastic(double density, double youngs_modulus, double poisson_ratio);
// A Mohr-Coulomb material without dilation or tension cut-off (angles in degrees).
Material mohr_coulomb(double density, double youngs_modulus, double poisson_ratio, double friction_angle,
                      double cohesion);

// Default run settings for tests: no gravity, CFL 0.5, one frame at the end.
void set_run(Model& model, double end_time, Eigen::Vector2d gravity = Eigen::Vector2d::Zero());

}  // namespace talus::testing
