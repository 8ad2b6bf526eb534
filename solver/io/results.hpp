// Writes results.h5 frame by frame, flushing each, so that a run stopped midway leaves a
// readable file with the frames so far; keeps results.xdmf beside it in step. The frame
// datasets are the particle fields the registry marks as written (particles.hpp) plus the
// velocity that moves each particle and the displacement; results.xdmf reads them through
// per-frame views (results_xdmf.hpp). Every write is checked: a failed one removes results.h5
// and results.xdmf (unreadable by then) and stops the run, and so does results.h5 deleted or
// replaced while the run writes it.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "common/h5.hpp"
#include "common/model/model.hpp"
#include "solver/io/results_xdmf.hpp"
#include "solver/step/simulation.hpp"

namespace talus::solver {

// Particles per chunk of a frame dataset (frames/<field>: one frame by kFrameBlock rows), and per
// piece of a frame as the writer fills and writes it: 2 MB for a 4-wide field.
inline constexpr std::size_t kFrameBlock = std::size_t{1} << 16;

// How far a results.h5 has been written: what a checkpoint records, and a restart keeps.
struct ResultsPosition {
  long frames = 0;
  long history_rows = 0;
};

// The frame datasets, in their order: frames/velocity (the grid velocity at the particles) and
// frames/displacement (position less the initial position), both derived, then every field the
// registry marks kWritten (particles.hpp), in its order; position is the XDMF geometry.
// frames/pore_pressure only with a water table.
std::vector<FrameField> frame_fields(bool water);

class ResultsWriter {
 public:
  // Starts a new results.h5 (replacing any old one).
  ResultsWriter(const std::string& out_dir, const Model& model);
  // Continues the results.h5 of an interrupted run of `model`: keeps its first `resume.frames`
  // frames and `resume.history_rows` history rows, drops anything written after them, and
  // marks the file incomplete until finish(). Throws talus::Error when the file is missing or
  // belongs to another model.
  ResultsWriter(const std::string& out_dir, const Model& model, const ResultsPosition& resume);
  // Writes the pending history and flushes: everything recorded so far is in the file.
  ResultsPosition sync();
  void write_frame(const Simulation& sim);
  // The same from particles gathered off several ranks (domain.hpp, gather_particles) with the
  // grid velocity at each.
  void write_frame(const Particles& particles, const std::vector<Eigen::Vector2d>& velocity, double time, long steps);
  void record_history(const Simulation& sim, const Energies& energy);

  // A frame whose rows every rank of a distributed solve writes (results_parallel.hpp); this
  // writer, rank 0's, does the rest. The file's frame datasets can take such rows (they allocate
  // their space as they grow): false for the results.h5 of an older Talus being continued.
  bool frames_writable_by_ranks() const;
  // Everything of the next frame but its rows: the frame datasets grow by one frame, then its
  // time, views and the pending history are written, and the file is closed for the ranks to
  // open. Returns the frame's index.
  std::size_t begin_ranks_frame(double time, long steps);
  // Once the ranks have written the rows: opens the file again and writes results.xdmf.
  void end_ranks_frame();
  // The ranks failed to write a frame: removes results.h5 and results.xdmf, as any failed
  // write does, and throws talus::Error with `message` saying so.
  [[noreturn]] void abandon(const std::string& message);

  // Writes the pending history and the run's root attributes (complete = 1 for a run that
  // reached its end, 0 for one stopped by an error), and flushes.
  void finish(long steps, double loop_seconds, bool complete);
  const std::string& path() const { return path_; }
  const std::string& xdmf_path() const { return xdmf_path_; }
  long frames() const { return static_cast<long>(time_.size()); }

 private:
  // Runs `write`; when it fails (a full disk, a file size limit), removes results.h5 and
  // results.xdmf, which a failed write leaves unreadable, and throws the error saying so.
  template <class Write>
  void guarded(Write&& write);
  [[noreturn]] void remove_after_failure(const std::string& message);
  // Throws when results.h5 is no longer the file this writer writes (deleted or replaced).
  void check_still_there() const;
  // Writes the frame's rows in model order, kFrameBlock particles at a time (the frame
  // datasets' chunks), so that no buffer of a whole frame is needed; velocity(p) is the grid
  // velocity at the solver's particle p, computed as the block needs it, on `threads` threads.
  void write_frame_data(const Particles& particles, const std::function<Eigen::Vector2d(std::size_t)>& velocity,
                        int threads, double time, long steps);
  // Appends `time` and the frame's views, writes the pending history and flushes.
  void write_frame_metadata(double time, long steps);
  void flush_history();
  void write_xdmf() const;
  std::vector<FrameField> fields() const { return frame_fields(water_); }
  void open_datasets(hsize_t frames, hsize_t history_rows, bool fresh);

  // A per-frame dataset: frames/<name>, `width` values per particle.
  struct FrameSet {
    std::string name;
    int width;
    h5::Appendable data;
  };
  std::string path_, xdmf_path_;
  unsigned long long device_ = 0, inode_ = 0;  // of results.h5 when this writer opened it
  std::size_t particles_;
  bool water_;  // the model has a water table: frames/pore_pressure (field_written)
  h5::File file_;
  h5::Appendable time_set_;
  std::vector<FrameSet> frame_sets_;  // of frame_fields(), in its order
  h5::Appendable history_time_, history_kinetic_, history_potential_, history_strain_, history_particle_kinetic_;
  hsize_t history_rows_ = 0;  // in the file while it is closed for the ranks
  std::vector<double> time_;
  std::vector<double> pending_time_, pending_kinetic_, pending_potential_, pending_strain_,
      pending_particle_kinetic_;
};

}  // namespace talus::solver
