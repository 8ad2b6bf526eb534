// Shared helpers for the test suite: scratch folders, running the talus binary, and small
// models generated in code (no pasted tables).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "common/model/model.hpp"

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

// A file's whole text ("" when it cannot be read).
std::string read_text(const std::string& path);
// The number after "key": in a JSON text (the first occurrence); NaN when the key is missing
// or its value is not a number (null).
double json_number(const std::string& json, const std::string& key);

// Runs `build/bin/talus ARGS` through the shell, capturing its output.
CommandResult run_talus(const std::string& args);
CommandResult run_shell(const std::string& command);
// What `talus --version` prints: "(with MPI..." or "(without MPI: one rank)", and whether the
// ranks write the frames with the parallel HDF5.
const std::string& talus_version();

// The largest difference between the frames of two results.h5, relative to the largest value
// of each dataset, over every frame dataset (frames/pore_pressure too, with water); `worst`
// names the dataset (or says how their sizes differ, the difference being then infinite).
double frame_difference(const std::string& a, const std::string& b, std::string& worst);

// Absolute path of a file in the source tree, e.g. source_path("geometries/slope.toml").
std::string source_path(const std::string& relative);

// A gmsh .geo of two rectangles stacked on [0, w]: surface 1 over [0, b] and surface 2 over
// [b, t], both the physical surface "domain", with the physical curves "left" = {4, 7} and
// "right" = {2, 5}; lines 1 (y = 0), 3 (y = b) and 6 (y = t) are the horizontal ones. `lc`: the
// points' element size (<= 0: none, the scene's mesh.size); `groups`: the .geo's other physical
// groups, as lines of text ("Physical Surface(\"layer\") = {1};").
std::string stacked_rectangles_geo(double w, double b, double t, double lc, const std::string& groups);

// A structured background mesh of the rectangle [x0, x0 + nx h] x [y0, y0 + ny h], each
// square cut into two counter-clockwise triangles, with neighbours filled in and node sets
// "bottom", "top", "left", "right". No particles, bodies or materials.
Model rectangle_mesh(double x0, double y0, int nx, int ny, double h);
// The same rectangle as the grid pattern meshes it (preproc/lattice.cpp): each square cut by its
// diagonals into four triangles; the squares' corners are the first nodes, row by row, then
// their centres. The B-spline family's lattice.
Model crossed_rectangle_mesh(double x0, double y0, int nx, int ny, double h);

// Where add_box_body puts a triangle's four particles: the four-point barycentric positions
// (the centroid and the permutations of (1/2, 1/4, 1/4)), or the centroids of the midpoint
// sub-triangles as the preprocessor seeds them (preproc/seeding.cpp), whose CPDI domains tile
// the triangle.
enum class Seeding { FourPoints, SubTriangles };

// Adds a body of one material filling the box [x0, x1] x [y0, y1] of the mesh: particles at
// four points of every triangle whose centroid lies in the box (`seeding`), each with a quarter
// of the triangle's area. Returns the body's index.
int add_box_body(Model& model, const std::string& name, const Material& material, double x0, double x1, double y0,
                 double y1, bool fixed = false, Seeding seeding = Seeding::FourPoints);

// Adds a body of one material filling the disc of `radius` around `centre`: the same
// four-point positions as add_box_body, kept per point, so the rim follows the circle to
// within a quarter of a triangle. Its outline is a 64-gon. Returns the body's index.
int add_disc_body(Model& model, const std::string& name, const Material& material, const Eigen::Vector2d& centre,
                  double radius);

// Fixes the "bottom" node set and puts the "left" and "right" sets on rollers (normal x), the
// usual support of a column or block on rectangle_mesh; fixed = "top" hangs a bar instead.
void fix_base_roll_sides(Model& model, const char* fixed = "bottom");

// The deposit of a column collapse against a wall at x = 0 (docs/column.md): bins `bin` wide
// from the wall out to the first empty bin hold the deposit; its tip is the furthest particle in
// them and its height the highest. Particles beyond that gap are detached and only counted.
struct ColumnDeposit {
  double tip = 0;     // L_inf, m from the wall
  double height = 0;  // H_inf, m
  int detached = 0;
};
ColumnDeposit column_deposit(const std::vector<Eigen::Vector2d>& positions, double bin);

// Lube et al. (2005), Phys. Rev. E 72, 041301, 2D columns: (L_inf - L0) / L0 = 1.2 a for
// a < 1.8 and 1.9 a^(2/3) for a > 2.8; no value in the transition between.
std::optional<double> lube_runout(double aspect_ratio);

// A linear elastic material.
Material elastic(double density, double youngs_modulus, double poisson_ratio);
// A Mohr-Coulomb material without dilation or tension cut-off (angles in degrees).
Material mohr_coulomb(double density, double youngs_modulus, double poisson_ratio, double friction_angle,
                      double cohesion);

// Default run settings for tests: no gravity, CFL 0.5, one frame at the end.
void set_run(Model& model, double end_time, Eigen::Vector2d gravity = Eigen::Vector2d::Zero());

}  // namespace talus::testing
