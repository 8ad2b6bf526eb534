// Before meshing: is the requested mesh sensible for the machine and for the bodies? From the
// .geo's geometry (read by gmsh, not meshed) and the element size h (mesh.size, or the mean
// length of gmsh's 1D mesh of the domain's boundary when the .geo sets the sizes):
//   element area   a_e = sqrt(3)/4 h^2            (an equilateral triangle of side h)
//   triangles      T   = A_domain / a_e,   nodes ~ T / 2
//   particles      P   = sum over bodies of particles_per_cell x A_body / a_e
//   memory         M   = 500 B x P + 200 B x nodes + 150 B x T    (generous per item)
// A scene is refused when M exceeds MemAvailable (/proc/meminfo), or when a body would get
// fewer than one particle (particles_per_cell x A_body < a_e): both with the numbers.
// A body given as a closed physical curve is measured by its bounding box (an upper bound).
#pragma once
#include <string>
#include <vector>

#include "common/scene/scene.hpp"

namespace talus::preproc {

struct SizeEstimate {
  bool known = false;          // false when gmsh cannot read the .geo or find the domain
  double element_size = 0;     // h, m
  double element_area = 0;     // m^2
  double domain_area = 0;      // m^2
  double triangles = 0, nodes = 0, particles = 0;
  double bytes = 0;            // estimated memory of the solve
  std::vector<double> body_areas;  // m^2, per scene body (0: group not found)
};

SizeEstimate estimate_size(const Scene& scene);

// Throws talus::Error when the estimate says the mesh is too large or too coarse. Leaves every
// other problem of the .geo to the meshing that follows, which reports it with gmsh's words.
void check_size(const Scene& scene);

}  // namespace talus::preproc
