#include "solver/io/results_parallel.hpp"

#include <cstring>

#include "common/error.hpp"
#include "solver/parallel/domain.hpp"
#include "solver/parallel/mpi.hpp"
#include "solver/io/particle_io.hpp"

namespace talus::solver {
namespace {

// The first id of rank r's block of n particles on `ranks` ranks.
std::size_t block_start(int r, std::size_t n, int ranks) {
  return static_cast<std::size_t>(r) * n / static_cast<std::size_t>(ranks);
}

std::size_t field_index(const std::vector<FrameField>& fields, const std::string& name) {
  for (std::size_t s = 0; s < fields.size(); ++s)
    if (fields[s].name == name) return s;
  throw Error("internal error: no frame dataset " + name);
}

// Selects rows [first, first + count) of frame `frame` of a frame dataset ([F, N] or
// [F, N, width]) in `file_space`, and makes the matching memory space; none when count is 0.
h5::Handle select_rows(hid_t file_space, hsize_t frame, hsize_t first, hsize_t count, hsize_t width) {
  const h5::Dims start = width == 1 ? h5::Dims{frame, first} : h5::Dims{frame, first, 0};
  const h5::Dims rows = width == 1 ? h5::Dims{1, count} : h5::Dims{1, count, width};
  return h5::select_block(file_space, start, rows);
}

// Writes rows [first, first + count) of frame `frame` of every frames/<field> of `path` from
// `block`, on all ranks at once. The writes and the close are collective: every rank makes
// every one of them, whatever failed before on it. Returns this rank's first failure, "" for none.
std::string write_block(const std::string& path, hsize_t frame, hsize_t first, hsize_t count,
                        const std::vector<FrameField>& fields, const std::vector<std::vector<double>>& block) {
  std::string failure;
  auto check = [&](bool ok, const std::string& item, const std::string& what) {
    if (!ok && failure.empty()) failure = located(path, item, what);
    return ok;
  };
  h5::Handle fapl(H5Pcreate(H5P_FILE_ACCESS)), dxpl(H5Pcreate(H5P_DATASET_XFER));
  const bool parallel = mpi::set_parallel_io(fapl.id(), dxpl.id());
  h5::Handle file(parallel ? H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.id()) : -1);
  // A file open on some ranks only would leave them waiting in the collective writes.
  const long opened = mpi::sum(static_cast<long>(file.valid()));
  if (opened != 0 && opened != mpi::size())
    throw Error(located(path, "", "opened with MPI-IO on " + std::to_string(opened) + " ranks of " +
                                      std::to_string(mpi::size())));
  if (!check(file.valid(), "", "cannot open the file with MPI-IO on every rank")) return failure;
  for (std::size_t s = 0; s < fields.size(); ++s) {
    const std::string name = "frames/" + fields[s].name;
    // Opening reads the file's metadata, the same on every rank: it fails on all or none.
    h5::Handle dataset(H5Dopen2(file.id(), name.c_str(), H5P_DEFAULT));
    if (!check(dataset.valid(), name, "cannot open dataset")) continue;
    h5::Handle file_space(H5Dget_space(dataset.id()));
    h5::Handle memory_space = select_rows(file_space.id(), frame, first, count, static_cast<hsize_t>(fields[s].width));
    check(H5Dwrite(dataset.id(), H5T_NATIVE_DOUBLE, memory_space.id(), file_space.id(), dxpl.id(), block[s].data()) >= 0,
          name, "cannot write the frame's rows (disk full, or over the file size limit?)");
  }
  check(H5Fclose(file.release()) >= 0, "", "cannot write HDF5 file with MPI-IO (disk full, or over the file size limit?)");
  return failure;
}

}  // namespace

bool RankFrames::wanted(const ResultsWriter* writer) {
  if (!mpi::distributed() || !mpi::parallel_hdf5()) return false;
  return mpi::any(writer && writer->frames_writable_by_ranks());
}

RankFrames::RankFrames(const Model& model, const std::string& path)
    : path_(path),
      particles_(model.particle_count()),
      ranks_(mpi::size()),
      water_(model.water.enabled()),
      fields_(frame_fields(water_)) {
  first_ = block_start(mpi::rank(), particles_, ranks_);
  end_ = block_start(mpi::rank() + 1, particles_, ranks_);
  initial_.assign(model.position.begin() + static_cast<std::ptrdiff_t>(first_),
                  model.position.begin() + static_cast<std::ptrdiff_t>(end_));
  position_ = field_index(fields_, "position");
  displacement_ = field_index(fields_, "displacement");
  row_width_ = 1;  // the id
  for (std::size_t s = 0; s < fields_.size(); ++s)
    if (s != displacement_) row_width_ += static_cast<std::size_t>(fields_[s].width);
  block_.resize(fields_.size());
}

int RankFrames::owner(std::size_t id) const {
  // The last rank whose block starts at or before id; id R / N is never past it.
  int r = static_cast<int>(id * static_cast<std::size_t>(ranks_) / particles_);
  while (r + 1 < ranks_ && block_start(r + 1, particles_, ranks_) <= id) ++r;
  return r;
}

void RankFrames::exchange_rows(const Particles& P, const std::vector<Vec2>& velocity) {
  std::vector<std::string> send(static_cast<std::size_t>(ranks_));
  std::vector<double> row(row_width_);
  const std::size_t row_bytes = row_width_ * sizeof(double);
  for (std::size_t p = 0; p < P.size(); ++p) {
    std::size_t k = 0;
    row[k++] = static_cast<double>(P.id[p]);
    row[k++] = velocity[p].x();
    row[k++] = velocity[p].y();
    P.for_each_field([&](const FieldInfo& field, const auto& column) {
      using E = FieldElement<typename std::decay_t<decltype(column)>::value_type>;
      if (field_written(field, water_))
        for (int c = 0; c < E::width; ++c) row[k++] = static_cast<double>(E::get(column[p], c));
    });
    send[static_cast<std::size_t>(owner(static_cast<std::size_t>(P.id[p])))].append(
        reinterpret_cast<const char*>(row.data()), row_bytes);
  }
  const std::vector<std::string> received = mpi::all_to_all(send);
  std::vector<std::string>().swap(send);
  for (std::size_t s = 0; s < fields_.size(); ++s)
    block_[s].assign((end_ - first_) * static_cast<std::size_t>(fields_[s].width), 0.0);
  std::size_t rows = 0;
  for (const std::string& part : received) {
    place_rows(part);
    rows += part.size() / row_bytes;
  }
  if (rows != end_ - first_)
    throw Error("internal error: rank " + std::to_string(mpi::rank()) + " received " + std::to_string(rows) +
                " rows of its block of " + std::to_string(end_ - first_) + " particles");
}

void RankFrames::place_rows(const std::string& rows) {
  const std::size_t row_bytes = row_width_ * sizeof(double);
  std::vector<double> row(row_width_);
  for (std::size_t offset = 0; offset + row_bytes <= rows.size(); offset += row_bytes) {
    std::memcpy(row.data(), rows.data() + offset, row_bytes);
    const std::size_t id = static_cast<std::size_t>(row[0]);
    if (id < first_ || id >= end_) throw Error("internal error: particle " + std::to_string(id) + " sent to the wrong rank");
    const std::size_t i = id - first_;
    std::size_t k = 1;
    for (std::size_t s = 0; s < fields_.size(); ++s) {
      if (s == displacement_) continue;
      const std::size_t width = static_cast<std::size_t>(fields_[s].width);
      for (std::size_t c = 0; c < width; ++c) block_[s][i * width + c] = row[k++];
    }
    // As ResultsWriter::write_frame_data computes it: the same bits.
    for (std::size_t c = 0; c < 2; ++c)
      block_[displacement_][i * 2 + c] = block_[position_][i * 2 + c] - initial_[i][static_cast<int>(c)];
  }
}

void RankFrames::write(const Simulation& sim, const std::vector<Vec2>& velocity, ResultsWriter* writer) {
  exchange_rows(sim.particles, velocity);
  std::vector<double> frame{0};
  on_root([&] { frame[0] = static_cast<double>(writer->begin_ranks_frame(sim.time, sim.steps)); });
  mpi::broadcast(frame, 0);
  std::string failure =
      write_block(path_, static_cast<hsize_t>(frame[0]), first_, end_ - first_, fields_, block_);
  for (auto& rows : block_) std::vector<double>().swap(rows);  // not kept between frames
  const int failed = mpi::first_rank_with(!failure.empty());
  if (failed >= 0) {
    mpi::broadcast(failure, failed);
    on_root([&] { writer->abandon(failure); });
  }
  on_root([&] { writer->end_ranks_frame(); });
}

}  // namespace talus::solver
