// Writes results.h5 frame by frame, flushing each, so that a run stopped midway leaves a
// readable file with the frames so far; keeps results.xdmf beside it in step.
#pragma once
#include <string>
#include <vector>

#include "common/h5.hpp"
#include "common/model.hpp"
#include "solver/simulation.hpp"

namespace talus::solver {

class ResultsWriter {
 public:
  ResultsWriter(const std::string& out_dir, const Model& model);
  void write_frame(const Simulation& sim);
  void record_history(const Simulation& sim, const Energies& energy);
  // Writes the pending history and the run's root attributes (complete = 1 for a run that
  // reached its end, 0 for one stopped by an error), and flushes.
  void finish(long steps, double loop_seconds, bool complete);
  const std::string& path() const { return path_; }
  long frames() const { return static_cast<long>(time_.size()); }

 private:
  void flush_history();
  void write_xdmf() const;

  std::string path_, xdmf_path_;
  std::size_t particles_;
  h5::File file_;
  h5::Appendable time_set_, position_, velocity_, stress_, plastic_strain_;
  h5::Appendable history_time_, history_kinetic_, history_potential_, history_strain_, history_particle_kinetic_;
  std::vector<double> time_;
  std::vector<double> pending_time_, pending_kinetic_, pending_potential_, pending_strain_,
      pending_particle_kinetic_;
  std::vector<double> scratch_;
};

}  // namespace talus::solver
