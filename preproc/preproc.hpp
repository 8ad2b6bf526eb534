// The preprocessor stage (`talus mesh`): meshes a scene's .geo with the gmsh API into a
// background mesh of linear triangles, seeds particles inside each body's boundary polygon
// (CGAL point-in-polygon), and resolves the boundary conditions per node. The result is the
// Model that `talus solve` reads from model.h5 (docs/model-format.md).
#pragma once
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "common/scene/scene.hpp"

namespace talus::preproc {

struct BodyReport {
  std::string name;
  std::size_t particles = 0;
  double particle_volume = 0;      // sum of the particles' volumes, m^2 (unit thickness)
  double polygon_area = 0;         // area inside the body's boundary loops, m^2
  double relative_difference = 0;  // (particle_volume - polygon_area) / polygon_area
};

struct LoadReport {
  std::string name;
  std::size_t particles = 0;  // particles that carry it
  double length = 0;          // the loaded length, m (the sum of their shares)
};

struct MeshReport {
  std::string scene;
  std::string geometry;  // the .geo that was meshed
  std::size_t nodes = 0;
  std::size_t elements = 0;
  std::size_t quadrilaterals = 0;             // mesh.pattern = "crossed": those gmsh made
  std::size_t quadrilaterals_cut_in_two = 0;  // of them, not convex: two triangles, not four
  std::size_t particles = 0;
  std::size_t fixed_nodes = 0;
  std::size_t roller_nodes = 0;
  std::size_t friction_nodes = 0;
  std::vector<BodyReport> bodies;
  std::vector<LoadReport> loads;
  // A Mohr-Coulomb material of a moving body on Delaunay triangles with EVS off: linear
  // triangles lock in plastic flow at constant volume (docs/slope.md, "Crossed triangles"), so
  // the report says how to avoid it. Empty: none.
  std::string locking_material;
  double gmsh_seconds = 0;     // reading the .geo and meshing
  double seeding_seconds = 0;  // everything after gmsh: topology, seeding, boundary conditions
  double seconds = 0;          // total
};

// Meshes scene.geometry with the gmsh C++ API and seeds particles; throws talus::Error on bad
// input (missing or unparsable .geo, a physical group the .geo lacks, a body outside the
// domain or too small for the mesh, overlapping bodies).
Model build_model(const Scene& scene, MeshReport* report = nullptr);

// A one-screen summary of a MeshReport.
void print_report(const MeshReport& report, std::ostream& out);

}  // namespace talus::preproc
