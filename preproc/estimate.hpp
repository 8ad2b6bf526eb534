// Before meshing: is the requested mesh sensible for the machine and for the bodies? From the
// .geo's geometry (read by gmsh, not meshed) and the element size h (mesh.size, or the mean
// length of gmsh's 1D mesh of the domain's boundary when the .geo sets the sizes):
//   element area   a_e = sqrt(3)/4 h^2            (an equilateral triangle of side h)
//   triangles      T   = A_domain / a_e,   nodes ~ T / 2
//   particles      P   = sum over bodies of particles_per_cell x A_body / a_e
//   memory         M   = 500 B x P + 200 B x nodes + 150 B x T    (generous per item)
// A scene is refused when M exceeds the memory left to the process (memory_left: MemAvailable,
// ulimit -v and -d, the cgroup's limit), when model.h5 (88 B x P + 16 B x nodes + 24 B x T)
// would exceed the file size limit (ulimit -f), or when a body would get fewer than one
// particle (particles_per_cell x A_body < a_e): all with the numbers.
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
  double model_bytes = 0;      // estimated size of model.h5
  std::vector<double> body_areas;  // m^2, per scene body (0: group not found)
};

SizeEstimate estimate_size(const Scene& scene);

// The memory this process may still take, and what bounds it: the least of MemAvailable, the
// address-space limit (RLIMIT_AS, ulimit -v) less what the process maps already, the data-size
// limit (RLIMIT_DATA) less its data, and what its cgroup's memory limit leaves.
struct MemoryLeft {
  double bytes = 0;   // INFINITY when nothing bounds it
  std::string what;   // "MemAvailable", "the address-space limit (ulimit -v) of ..."
};
MemoryLeft memory_left();

// What the memory cgroup of this process and those above it leave (limit less usage, the least
// of them; cgroup v2 memory.max and memory.current, v1 memory.limit_in_bytes and
// memory.usage_in_bytes), read from /proc/self/cgroup and /proc/self/mountinfo under `root`
// ("" for the machine's own; tests give a folder laid out alike). INFINITY without a limit.
double cgroup_memory_left(const std::string& root = "");

// Throws talus::Error when the estimate says the mesh is too large or too coarse. Leaves every
// other problem of the .geo to the meshing that follows, which reports it with gmsh's words.
void check_size(const Scene& scene);

}  // namespace talus::preproc
