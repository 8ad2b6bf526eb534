// results.xdmf and the per-frame views in results.h5 that it reads. ParaView's three XDMF
// readers (legacy, Xdmf3 S and T) and meshio's time-series reader agree on little: plain HDF
// data items, one per attribute, each a whole dataset (no hyperslabs, no functions). So every
// frame gets its own datasets /xdmf/<frame>/<name>, and these are HDF5 virtual datasets: views
// of the frames/ datasets that cost no storage. Vectors are 3 wide with z = 0 (the views' fill
// value), which ParaView's glyphs and colouring by magnitude want.
#pragma once
#include <string>
#include <vector>

#include "common/h5.hpp"

namespace talus::solver {

// A per-frame dataset frames/<name> of `width` values per particle.
struct FrameField {
  std::string name;
  int width;
};

// Creates /xdmf/vertices (0..P-1, the XDMF topology's connectivity) when it is missing.
void write_xdmf_vertices(const h5::File& file, std::size_t particles);

// Creates the views /xdmf/<frame>/... of frame `frame` (the frames/ datasets must hold it):
// position [P,2], every 2-wide field as [P,3], a 4-wide stress as its components _xx, _yy,
// _zz, _xy [P], a scalar as [P]. Throws talus::Error naming the dataset on failure.
void write_frame_views(const h5::File& file, std::size_t particles, std::size_t frame,
                       const std::vector<FrameField>& fields);

// Removes /xdmf/<frame> for every frame >= `keep` (a restart dropping the later frames).
void drop_frame_views(const h5::File& file, std::size_t keep);

// Writes `xdmf_path` (atomically): a temporal collection of polyvertex grids, one per time in
// `times`, reading `h5_name`'s views, plus the particles' body and material index.
void write_xdmf_file(const std::string& xdmf_path, const std::string& h5_name, std::size_t particles,
                     const std::vector<double>& times, const std::vector<FrameField>& fields);

}  // namespace talus::solver
