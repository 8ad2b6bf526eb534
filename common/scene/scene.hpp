// A scene: the TOML file that gives the physics of a `.geo` geometry. Parsed once, at the
// edge, into typed structs; every value is checked for type, range and finiteness, unknown
// keys are rejected with the nearest valid key. Units are SI; angles are in degrees.
// The format is documented in docs/scenes.md.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/materials/materials.hpp"  // Material
#include "common/scene/seismic.hpp"

namespace talus {

// [water]: a phreatic surface. Pore pressure is positive in compression; below the table it is
// hydrostatic in the vertical depth under the table at the point's x, u = unit_weight (h(x) - y)
// (docs/water.md). Total stress = effective stress - u I (tension positive).
enum class WaterMode { Drained, Undrained };

struct WaterSettings {
  std::vector<Eigen::Vector2d> table;  // m; polyline, x strictly increasing; empty: no water
  double unit_weight = 9810;           // N/m^3
  WaterMode mode = WaterMode::Drained;
  double bulk_modulus = 2.2e9;         // Pa, of the pore water (undrained)
  // The table's rise with time: (t, dh) pairs, t increasing; the table is shifted up by dh
  // interpolated linearly in t (constant before the first and after the last). Empty: fixed.
  std::vector<Eigen::Vector2d> rise;

  bool enabled() const { return !table.empty(); }
  // The table's rise at time t (m).
  double rise_at(double t) const;
  // The table's height at x (m), held level beyond its ends, at time t.
  double height(double x, double t = 0) const;
  // Hydrostatic pore pressure at a point (Pa): unit_weight * max(0, height(x, t) - y).
  double pore_pressure(const Eigen::Vector2d& point, double t = 0) const {
    const double depth = height(point.x(), t) - point.y();
    return depth > 0 ? unit_weight * depth : 0.0;
  }
};
const char* water_mode_name(WaterMode mode);  // "drained", "undrained"
// "" when the settings are sound: a table of >= 2 finite points with x strictly increasing, rise
// times strictly increasing, unit_weight and bulk_modulus finite and > 0; else the problem.
std::string water_problem(const WaterSettings& water);


// Geostatic initial stress for horizontally layered ground: sigma_yy = -rho g (surface - y),
// sigma_xx = sigma_zz = k0 sigma_yy (compression negative).
struct InitialStress {
  double k0 = 0;
  std::optional<double> surface;  // m; default: the highest point of the body
};

struct Body {
  std::string name;   // key of [bodies.NAME]
  std::string group;  // physical group in the .geo (default: the body's name)
  std::string material;
  int particles_per_cell = 4;  // one of 1, 3, 4, 6, 10 (fixed barycentric rules)
  bool fixed = false;          // particles never move (a support, such as an inclined surface)
  Eigen::Vector2d initial_velocity{0, 0};  // m/s
  std::optional<InitialStress> initial_stress;
};

enum class BoundaryType { Fixed, Roller, Friction, Absorbing };

struct Boundary {
  std::string name;   // key of [boundaries.NAME]
  std::string group;  // physical curve in the .geo (default: the boundary's name)
  BoundaryType type = BoundaryType::Fixed;
  // Roller: velocity along this unit normal is zero. Default: the curve's own normal
  // (one per node, averaged over the node's boundary segments).
  std::optional<Eigen::Vector2d> normal;
  // Friction: Coulomb coefficient (tan of the base friction angle) against the boundary.
  double friction = 0;
  // Absorbing: the [materials] name whose density and wave speeds give the dashpots'
  // impedances rho c_p and rho c_s (Lysmer and Kuhlemeyer 1969; docs/seismic.md).
  std::string material;
};

// A surface load on a stretch of a body's outline, carried by the particles along it
// (docs/scenes.md, [loads.NAME]). Exactly one of pressure and traction is given.
struct SurfaceLoad {
  std::string name;   // key of [loads.NAME]
  std::string group;  // physical curve in the .geo on a body's outline (default: the load's name)
  std::optional<double> pressure;           // Pa, along the inward normal (positive pushes in)
  std::optional<Eigen::Vector2d> traction;  // Pa, a fixed vector
  // The load rises as (1 - cos(pi t / T)) / 2 over the first T = ramp seconds (0: full from t = 0).
  double ramp = 0;
};

struct ContactPair {
  std::string body_a, body_b;
  double friction = 0;  // Coulomb coefficient; 0 and unused for a bonded pair
  bool bonded = false;  // the two bodies share one velocity field: no sliding, no separation
};

struct ContactSettings {
  // false: bodies share one velocity field (bonded, as the spring and the mass); true: the
  // frictional contact pass runs between bodies that meet at a node, except bonded pairs.
  bool enabled = true;
  double friction = 0;             // Coulomb coefficient for every pair not listed below
  std::vector<ContactPair> pairs;  // per-pair coefficients, or bonded
};

// The bodies' velocity fields under contact (docs/contact.md, "Bonded pairs"): bodies joined
// by bonded pairs, directly or through others, form one group that shares one grid velocity
// field, and contact acts between the groups. Groups are numbered in the order of their first
// body, so without bonded pairs group b is body b.
struct ContactGroups {
  std::vector<int32_t> of_body;                 // [body] -> group
  std::vector<uint8_t> fixed;                   // [group]: all its bodies are fixed
  std::vector<std::vector<double>> friction;    // [group][group], Coulomb coefficient
  std::string problem;                          // empty when the pairs are sound
  std::size_t count() const { return fixed.size(); }
};
// Groups the bodies (names and fixed flags in body order) by the bonded pairs. `problem` names
// the first mistake: a bonded pair naming an unknown body or one body twice, a bonded pair
// listed twice, and with contact enabled a group that bonds a fixed body to a moving one, or
// two pairs between the same two groups with different coefficients (a group's field has one
// coefficient against each other group). Friction pairs naming no body pair are ignored (the
// scene reader refuses them).
ContactGroups contact_groups(const ContactSettings& contact, const std::vector<std::string>& names,
                             const std::vector<uint8_t>& fixed);

// How the background mesh's triangles are laid out (docs/scenes.md, [mesh]).
enum class MeshPattern {
  Delaunay,  // gmsh's frontal-Delaunay triangles of edge mesh.size
  // Quadrilaterals of edge mesh.size (gmsh's Blossom recombination), each cut by its diagonals
  // into four triangles: Nagtegaal, Parks and Rice's crossed triangles (1974), which admit plastic
  // flow at constant volume without locking (docs/slope.md, "Crossed triangles").
  Crossed,
  // A lattice of cells of edge about mesh.size over the domain's rectangle, each cut by its
  // diagonals into four triangles (preproc/lattice.hpp): the nodes of the B-spline shape
  // functions, and the default pattern with them.
  Grid,
};

struct MeshSettings {
  std::optional<double> size;    // m; characteristic element size, overrides the .geo
  MeshPattern pattern = MeshPattern::Delaunay;
  std::string domain = "domain"; // physical surface meshed as the background grid
  // [mesh.parameters]: NAME = number sets the .geo's DefineConstant[NAME = {..., Name
  // "Parameters/NAME"}] (a gmsh ONELAB parameter) before the .geo is read.
  std::map<std::string, double> parameters;
};

// How the grid velocities update the particle velocities (docs/transfer.md).
enum class Transfer {
  Flip,      // v_p += dt sum N_ip a_i, the seed's (A.10): no dissipation, keeps the grid's null-space noise
  PicBlend,  // FLIP, then pic_fraction of the way to the grid velocity: damps the noise and the flow
  Xpic,      // XPIC(m), Hammerquist and Nairn (2017): FLIP less the m-th power of the noise projector
  Apic,      // APIC, Jiang et al. (2015): the grid velocity and its gradient, an affine particle velocity
};

// The shape functions that interpolate between particles and nodes (docs/transfer.md,
// "Shape functions"): the linear triangles of the background mesh (the seed's), or quadratic
// B-splines on the lattice of the grid pattern (mesh.pattern = "grid"), or the linear triangles
// averaged over each particle's triangular domain, whose corners move with the grid (CPDI,
// docs/shape-functions.md, "CPDI").
enum class ShapeFunctions { Linear, QuadraticBspline, Cpdi };

struct RunSettings {
  double end_time = 1;          // s
  double cfl = 0.5;             // alpha in dt = alpha h_min / (c_d + max|v_p|), in (0, 1]
  double output_interval = 0.1; // s between frames
  Eigen::Vector2d gravity{0, -9.81};  // m/s^2
  // Gravity rises smoothly, g (1 - cos(pi t / T)) / 2, over the first T = gravity_ramp seconds
  // (0: full gravity from t = 0, as the seed applies it). A ramp several times the bodies'
  // longest elastic period loads them quasi-statically instead of dropping them.
  double gravity_ramp = 0;
  double damping = 0;           // local (Cundall) damping coefficient in [0, 1)
  bool evs = false;             // enhanced volumetric strain (Detournay and Dzik 2006)
  Transfer transfer = Transfer::Flip;
  ShapeFunctions shape_functions = ShapeFunctions::Linear;
  // PicBlend: share of the grid (PIC) velocity blended into the particle velocity after each
  // step. A few percent damp the particle velocities that the grid cannot see (FLIP's null
  // space) and that otherwise never come to rest. Ignored by the other transfers.
  double pic_fraction = 0;
  int xpic_order = 5;           // Xpic: m >= 1; m = 1 is PIC, larger m approaches FLIP less its noise
  // The internal force's integration (docs/transfer.md, "Mixed integration"): 0 integrates
  // over the material points only (the seed's A.8, scene key integration = "material_points");
  // a share in (0, 1] (integration = "mixed", key full_cell_fill) integrates a cell with its own
  // area where its particles and those of each cell across its edges fill at least that share.
  double full_cell_fill = 0;
  int history_interval = 10;    // steps between energy-history records
  // Stop before end_time once kinetic energy has stayed below rest_ratio x its peak for
  // rest_window seconds (after the peak). rest_ratio = 0 disables it.
  double rest_ratio = 0;
  double rest_window = 0.5;     // s
  long max_steps = 0;           // 0: no limit
};

struct PostSettings {
  // Any of: "runout", "failure_surface", "bishop" (slopes); "spring_mass", "box_incline"
  // (validation scenes against their analytical solutions).
  std::vector<std::string> metrics;
  std::string body;                   // the body analysed (default: the first)
  // The bodies of the slope metrics and of `talus fos` together (a layered slope); empty:
  // `body` alone. The scene's default without `body` or `bodies`: every body that is not
  // fixed and is of a Mohr-Coulomb material (docs/scenes.md).
  std::vector<std::string> bodies;
  double sliding_threshold = 0.05;    // fraction of the slope height: moved more = sliding mass
  double spring_amplitude = 1e-3;     // m, y(t) = A (1 - cos(omega t))
  double spring_omega = 100;          // rad/s
  double incline_angle = 30;          // deg, box_incline: x = 0.5 g (sin a - mu cos a) t^2
  bool animate = true;                // talus post writes runout.mp4 and runout.gif
};

// [random.NAME] (docs/scenes.md): one material parameter as a spatially correlated random
// field, drawn by preproc/random_field/random_field.hpp. Its underlying field is a standard Gaussian one,
// mapped onto the distribution's marginal.
enum class RandomDistribution { Lognormal, Normal, Uniform };
enum class Correlation { Markov, Gaussian };  // the forms are stated in preproc/random_field/random_field.hpp

struct RandomField {
  std::string name;       // key of [random.NAME]
  std::string material;   // a [materials] name
  std::string parameter;  // a scalar parameter of that material, e.g. "cohesion"
  RandomDistribution distribution = RandomDistribution::Lognormal;
  double mean = 0;        // in the parameter's unit, > 0
  double cov = 0;         // coefficient of variation (standard deviation / mean), > 0
  Eigen::Vector2d correlation_length{0, 0};  // m, (horizontal, vertical), > 0; inf: fully correlated
  Correlation correlation = Correlation::Markov;
  // cross_correlation = { with, rho }: the underlying Gaussian field is rho times that of the
  // field `with` plus sqrt(1 - rho^2) times its own (cross_with empty: independent).
  std::string cross_with;
  double cross_rho = 0;
};

struct Scene {
  std::string name;      // [scene] name, default: the TOML file's stem
  std::string path;      // the TOML file as given
  std::string geometry;  // the .geo, resolved against the TOML file's folder
  MeshSettings mesh;
  RunSettings run;
  ContactSettings contact;
  PostSettings post;
  std::vector<Material> materials;
  std::vector<Body> bodies;
  std::vector<Boundary> boundaries;
  WaterSettings water;
  std::vector<SurfaceLoad> loads;
  std::vector<RandomField> random;  // [random.NAME], in the order of their names
  std::string canonical_text;  // the scene after --set overrides, as TOML (hashed by `talus run`)
  SeismicSettings seismic;  // [seismic] (seismic.hpp)
  BaseMotion base_motion;   // [base_motion] (seismic.hpp)

  int material_index(const std::string& name) const;  // -1 if absent
  int body_index(const std::string& name) const;      // -1 if absent
};

// Reads and checks a scene file. `overrides` are "dotted.key=value" strings from --set,
// value in TOML syntax (a bare word is taken as a string). Throws talus::Error.
// "flip", "pic_blend", "xpic", "apic"; and back (nullopt for an unknown name).
const char* transfer_name(Transfer transfer);
std::optional<Transfer> transfer_from_name(const std::string& name);
// A transfer named on a command line (talus converge --transfers, talus bench runout
// --transfers) as scene overrides: flip, apic, pic_blend, xpic (XPIC(5), the order the docs
// recommend) or xpicM (M from 1 to 100). Throws talus::Error ("unknown transfer ...") for
// another name.
std::vector<std::string> transfer_overrides(const std::string& name);
// "linear", "bspline"; and back (nullopt for an unknown name).
const char* shape_functions_name(ShapeFunctions family);
std::optional<ShapeFunctions> shape_functions_from_name(const std::string& name);

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// At most this many frames in a run (end_time / output_interval), and as many periodic
// checkpoints (end_time / --checkpoint-interval): a tiny interval would otherwise write frames
// without end, or add an interval too small to move the time on.
constexpr double kMaxFrames = 100000;
// Empty when run.output_interval gives at most kMaxFrames frames over run.end_time; otherwise
// "got X: N frames over run.end_time = T s, at most ..." for the key named by the caller.
std::string output_interval_problem(const RunSettings& run);

// Coulomb friction for a pair of bodies (per-pair value, else the scene default).
double pair_friction(const ContactSettings& contact, const std::string& a, const std::string& b);

}  // namespace talus
