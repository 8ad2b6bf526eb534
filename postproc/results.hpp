// results.h5 as the postprocessor needs it: frames of particle positions, velocities and
// equivalent plastic strain, the particles' body, mass and initial volume, the energy history,
// and the scene metadata (bodies with outlines, materials, run/contact/post settings) that the
// solver copies from the model. Every shape is checked against the particle and frame counts.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/model/model.hpp"

namespace talus::postproc {

struct Results {
  Model metadata;  // scene_name, bodies, materials, run, contact, post (no mesh, no particles)

  std::vector<double> frame_time;                               // s [F]
  std::vector<std::vector<Eigen::Vector2d>> position;           // m [F][N]
  std::vector<std::vector<Eigen::Vector2d>> velocity;           // m/s [F][N]
  std::vector<std::vector<double>> plastic_strain;              // [F][N]; empty when not written

  std::vector<Eigen::Vector2d> initial_position;  // m [N], the model's particles before step 1
  std::vector<int32_t> body;    // [N] index into metadata.bodies
  std::vector<double> mass;     // kg per m [N]
  std::vector<double> volume;   // m^2 (initial) [N]
  // Surface-load force of each particle at full load (N/m) [N]; empty when the scene has no loads.
  std::vector<Eigen::Vector2d> load_force;

  std::vector<double> history_time, kinetic_energy, potential_energy, strain_energy;  // s, J per m

  bool complete = true;  // the solver's root attribute `complete`: false when the run was cut short

  std::size_t frames() const { return frame_time.size(); }
  std::size_t particles() const { return body.size(); }
};

// Throws talus::Error naming the file and the dataset on a missing or misshapen item.
Results read_results(const std::string& path);

// Writes a results.h5 in the solver's layout (used by tests and tools that synthesise runs).
void write_results(const std::string& path, const Results& results);

}  // namespace talus::postproc
