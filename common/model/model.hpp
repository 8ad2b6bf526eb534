// The model: what `talus mesh` writes (model.h5) and `talus solve` reads. A background mesh
// of linear triangles, named node sets, per-node boundary constraints, particles, bodies,
// materials and run settings. The file layout is documented in docs/model-format.md.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/scene/scene.hpp"

namespace talus {

inline constexpr int kModelFormatVersion = 1;

struct BodyInfo {
  std::string name;
  int material = 0;  // index into Model::materials
  bool fixed = false;
  // Boundary loops of the body in the initial configuration (outer loops and holes; a point
  // is inside when it is inside an odd number of loops). Closed: last vertex != first.
  std::vector<std::vector<Eigen::Vector2d>> loops;
};

// A material parameter given per particle, such as one realisation of a random field of
// cohesion (docs/model-format.md, /particles/properties): the material, one of its parameter keys
// (any of its model's or youngs_modulus, poisson_ratio, porosity; not density or
// saturated_density, which act through each particle's mass and initial stress, fixed when
// meshing), and one value per particle. Only the values of the material's particles are used;
// the others are ignored (NaN when written).
struct ParticleProperty {
  std::string material;
  std::string parameter;
  std::vector<double> values;
};

struct Model {
  std::string scene_name;

  // Background mesh. Triangles are counter-clockwise; neighbours[e][k] is the element
  // across the edge opposite local vertex k, or -1 on the domain boundary.
  std::vector<Eigen::Vector2d> nodes;
  std::vector<std::array<int32_t, 3>> triangles;
  std::vector<std::array<int32_t, 3>> neighbours;

  // Nodes of each physical curve of the .geo, by name.
  std::map<std::string, std::vector<int32_t>> node_sets;

  // Boundary conditions resolved per node: a fixed node has zero velocity; a roller node has
  // zero velocity along its unit normal. A node in two rollers of different normals is fixed.
  std::vector<int32_t> fixed_nodes;
  std::vector<int32_t> roller_nodes;
  std::vector<Eigen::Vector2d> roller_normals;
  // A friction node keeps the velocity out of the domain along its outward unit normal at zero
  // or below and resists sliding by Coulomb friction (coefficient per node); see
  // solver/interpolation/mesh.hpp. Optional in the file (absent: none).
  std::vector<int32_t> friction_nodes;
  std::vector<Eigen::Vector2d> friction_normals;
  std::vector<double> friction_coefficients;

  // Particles (struct of arrays, all of length N).
  std::vector<Eigen::Vector2d> position;  // m
  std::vector<Eigen::Vector2d> velocity;  // m/s
  std::vector<double> volume;             // m^3 per unit thickness (m^2)
  std::vector<double> mass;               // kg per unit thickness
  std::vector<Eigen::Vector4d> stress;    // Pa, (xx, yy, zz, xy), tension positive
  std::vector<int32_t> body;              // index into bodies
  std::vector<int32_t> element;           // containing triangle
  // Surface loads (all three empty when the scene has none): the index into `loads` of the
  // load a particle carries (-1: none), the length of the loaded curve it stands for (m; the
  // shares of a load sum to its curve's length), and the sum of its pieces' lengths times their
  // outward unit normals in the initial configuration (m).
  std::vector<int32_t> load;
  std::vector<double> load_length;
  std::vector<Eigen::Vector2d> load_normal;

  // Per-particle material parameters (empty: every particle has its material's).
  std::vector<ParticleProperty> properties;

  std::vector<BodyInfo> bodies;
  std::vector<Material> materials;
  std::vector<SurfaceLoad> loads;
  RunSettings run;
  ContactSettings contact;
  PostSettings post;
  WaterSettings water;  // settings/water (absent: no water table)
  SeismicSettings seismic;  // settings/seismic (absent: off)
  BaseMotion base_motion;   // settings/base_motion (absent: the ground stays at rest)
  AbsorbingNodes absorbing;  // boundary_conditions/absorbing_* (absent: none)

  std::size_t particle_count() const { return position.size(); }
};

// Each particle's surface-load force at full load (N per m): the pressure along the inward
// normal (-pressure x load_normal) or traction x load_length; zero for a particle without a
// load. Empty when the model has no loads.
std::vector<Eigen::Vector2d> particle_load_forces(const Model& model);

// The first problem of the per-particle properties, at the item "particles/properties/M.P" of
// model.h5: an unknown material or key, a key given twice or not allowed per particle, a column
// of another length, or a particle whose values leave its material invalid (each value against
// its range given the particle's other values, then the model's rules). None when sound.
std::optional<MaterialProblem> properties_problem(const Model& model);

// Writes to PATH.tmp and renames when complete, so no half-written model is ever left.
void write_model(const std::string& path, const Model& model);
// Checks the format tag and version, the presence and shapes of every dataset, and that the
// indices are in range; throws talus::Error naming the file and the item otherwise.
Model read_model(const std::string& path);

}  // namespace talus
