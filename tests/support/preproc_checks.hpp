// Checks of the preprocessor's output written independently of preproc/ (geometry by hand and
// common/geometry.hpp's even-odd rule, not CGAL), shared by the preprocessor's test files: mesh
// and particle invariants, volumes per body, and meshing a scene of geometries/.
#pragma once
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "common/scene/scene.hpp"
#include "preproc/preproc.hpp"
#include "support/test_support.hpp"

namespace talus::testing {

double twice_signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c);
// Barycentric coordinates of p in triangle e.
Eigen::Vector3d barycentric(const Model& model, int32_t e, const Eigen::Vector2d& p);
double triangle_area(const Model& model, int32_t e);
// Index of the named body; a test failure (and -1) when there is none.
int body_of(const Model& model, const std::string& name);

// Mesh invariants that any Model written by `talus mesh` must satisfy.
void expect_valid_mesh(const Model& model);
// Particle invariants: inside its body, inside its element, mass = density x volume, and
// volume = element area / particles per cell.
void expect_valid_particles(const Model& model, const Scene& scene);

std::map<std::string, double> volume_per_body(const Model& model);

struct Meshed {
  Scene scene;
  Model model;
  preproc::MeshReport report;
};

// geometries/NAME.toml, loaded with `overrides` and built into a model.
Meshed mesh_scene(const std::string& name, const std::vector<std::string>& overrides = {});

// A body of material "rock" in the physical group `group`.
Body rock_body(const std::string& name, const std::string& group, int particles_per_cell);
// A scene written here, not read from a file: `geometry`, the element size, one linear
// material "rock" (2000 kg/m^3, E = 10 MPa, nu = 0.25) and `bodies` (post.body: the first).
Scene rock_scene(const std::string& name, const std::string& path, const std::string& geometry,
                 std::optional<double> size, std::vector<Body> bodies);

// Writes `text` to dir/name and returns the path.
std::string write_file(const ScratchDir& dir, const std::string& name, const std::string& text);

}  // namespace talus::testing
