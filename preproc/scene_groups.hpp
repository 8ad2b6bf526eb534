// The scene's named physical groups on the meshed .geo (preproc.cpp, steps 2, 3, 5 and 6):
// the domain, each body's outline as closed loops, boundary curves as mesh segments and node
// sets, loads as segments on the bodies' outlines. Every group the scene names and the .geo
// lacks, or that is of the wrong kind, is an Error naming both files.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/scene/scene.hpp"
#include "preproc/background_mesh.hpp"
#include "preproc/boundary_conditions.hpp"
#include "preproc/gmsh_geometry.hpp"
#include "preproc/polygon.hpp"
#include "preproc/surface_loads.hpp"

namespace talus::preproc {

const PhysicalGroup& domain_group(const GeoMesh& geo, const Scene& scene);

// The outline of a body as closed loops of points (an Error when it does not close).
std::vector<Loop> body_loops(const GeoMesh& geo, const Body& body, const Scene& scene);

// Every vertex of the body's outline must be inside or on the background mesh (to a tolerance
// relative to the domain's size, for outlines meshed apart from the domain), and no edge of it may
// cross another edge of it (a bow tie) or an edge of the domain (into a hole of the domain, or
// out of it between two vertices).
void check_inside_domain(const Region& body_region, const Region& domain, const Body& body, const Scene& scene);

// A physical curve's nodes on the background mesh (its node set in model.h5).
std::vector<int32_t> node_set(const GeoMesh& geo, const PhysicalGroup& curve, const BackgroundMesh& mesh);

// The scene's boundaries as mesh segments.
std::vector<BoundaryCurve> boundary_curves(const GeoMesh& geo, const BackgroundMesh& mesh, const Scene& scene);

// Each load's physical curve as segments on the outline of the body that holds it.
std::vector<LoadCurve> load_curves(const GeoMesh& geo, const Scene& scene);

// The index of a body's material in scene.materials.
int material_of(const Scene& scene, const Body& body);

// "(x, y)"
std::string point_text(const Eigen::Vector2d& p);

}  // namespace talus::preproc
