// The frames of a distributed solve written by every rank into the one results.h5 through the
// parallel HDF5 (MPI-IO), instead of gathered on rank 0 (domain.hpp, gather_particles), which
// needs the whole frame, and every rank's particles, in rank 0's memory. Rank 0's ResultsWriter
// keeps the file and all its metadata: for a frame it grows the frame datasets, writes the
// time, the views and the history, and closes the file; then every rank opens it with MPI-IO
// and writes its block of rows, one collective write per dataset; then rank 0 opens it again.
// Rank r's block is the model's particles of ids [r N / R, (r + 1) N / R) (N particles, R
// ranks), so before the write the ranks swap their particles' rows (mpi::all_to_all) to hold
// their blocks, in id order. The file is the one a serial solve writes.
//
// Used when built with the parallel HDF5 (mpi::parallel_hdf5); otherwise, and for checkpoints,
// the particles are still gathered on rank 0.
#pragma once
#include <string>
#include <vector>

#include "common/model/model.hpp"
#include "solver/interpolation/mesh.hpp"
#include "solver/io/results.hpp"
#include "solver/step/simulation.hpp"

namespace talus::solver {

class RankFrames {
 public:
  // Whether the frames of this run are written so: several ranks, the parallel HDF5, and a
  // results.h5 that can take rows written by the ranks (ResultsWriter::frames_writable_by_ranks;
  // `writer` is rank 0's, null on the others). Collective.
  static bool wanted(const ResultsWriter* writer);
  // This rank's block of `model`'s particles, with their initial positions (the displacement's
  // origin), for results.h5 at `path`. Call it before the model's columns move.
  RankFrames(const Model& model, const std::string& path);
  // Writes the frame of `sim`, `velocity` being the grid velocity at each of this rank's
  // particles; `writer` is rank 0's (null on the others). Collective. A failure on any rank
  // removes results.h5 and results.xdmf and throws SharedError on every rank.
  void write(const Simulation& sim, const std::vector<Vec2>& velocity, ResultsWriter* writer);

 private:
  // The rank whose block holds particle `id`.
  int owner(std::size_t id) const;
  // Sends the row of each of this rank's particles (its id, then its values of every frame
  // dataset but the displacement) to the rank of its block, and fills block_ with the rows
  // received.
  void exchange_rows(const Particles& P, const std::vector<Vec2>& velocity);
  void place_rows(const std::string& rows);

  std::string path_;
  std::size_t particles_, first_, end_;  // this rank's block: ids [first_, end_)
  int ranks_;
  bool water_;
  std::vector<Vec2> initial_;        // the initial positions of the block
  std::vector<FrameField> fields_;   // frame_fields(), the datasets' order
  std::size_t row_width_;            // values sent per particle
  std::size_t position_, displacement_;  // indices of frames/position and frames/displacement in fields_
  std::vector<std::vector<double>> block_;  // [field] the block's rows of the frame
};

}  // namespace talus::solver
