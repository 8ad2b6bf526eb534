// Seeding particles: fixed barycentric positions in every background triangle, kept where they
// fall inside a body's region. Each kept particle stands for area / particles_per_cell.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "preproc/background_mesh.hpp"
#include "preproc/polygon.hpp"

namespace talus::preproc {

// The particles_per_cell values that have a seeding pattern.
inline constexpr int kSupportedParticlesPerCell[] = {1, 3, 4, 6, 10};

// Barycentric coordinates of the seeds in one triangle; empty for an unsupported count.
std::vector<Eigen::Vector3d> seed_pattern(int particles_per_cell);

struct SeedBody {
  std::string name;
  const Region* region = nullptr;
  int particles_per_cell = 4;
};

struct Seeds {
  std::vector<Eigen::Vector2d> position;
  std::vector<double> volume;
  std::vector<int32_t> body;     // index into the SeedBody list
  std::vector<int32_t> element;  // background triangle
};

// Particles sorted by element, then by body. Throws talus::Error (naming `scene_path` and both
// bodies) when a seed of one body lies inside another body.
Seeds seed_particles(const BackgroundMesh& mesh, const std::vector<SeedBody>& bodies, const std::string& scene_path);

}  // namespace talus::preproc
