#include "solver/io/results.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <limits>
#include <sstream>
#include <tuple>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "common/model/model_io.hpp"
#include "solver/io/particle_io.hpp"
#include "solver/io/results_xdmf.hpp"

namespace talus::solver {
namespace {

// The device and inode of `path`; zeros when it does not exist.
std::pair<unsigned long long, unsigned long long> identity(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0) return {0, 0};
  return {static_cast<unsigned long long>(info.st_dev), static_cast<unsigned long long>(info.st_ino)};
}

}  // namespace

template <class Write>
void ResultsWriter::guarded(Write&& write) {
  try {
    write();
  } catch (const Error& error) {
    if (identity(path_) != std::make_pair(device_, inode_)) throw;  // not ours to remove
    remove_after_failure(error.what());
  }
}

void ResultsWriter::remove_after_failure(const std::string& message) {
  try {
    file_.close();
  } catch (const Error&) {  // the close fails too: the file is being removed
  }
  std::error_code ignored;
  std::filesystem::remove(path_, ignored);
  std::filesystem::remove(xdmf_path_, ignored);
  throw Error(message + "; removed " + path_ + " and results.xdmf (a file whose write failed cannot be read)");
}

void ResultsWriter::abandon(const std::string& message) {
  if (identity(path_) != std::make_pair(device_, inode_)) throw Error(message);  // not ours to remove
  remove_after_failure(message);
}

void ResultsWriter::check_still_there() const {
  const auto now = identity(path_);
  if (now == std::make_pair(device_, inode_)) return;
  std::error_code ignored;  // it describes the frames of the file that is gone
  std::filesystem::remove(xdmf_path_, ignored);
  throw Error(located(path_, "", std::string(now.second == 0 ? "deleted" : "replaced by another file") +
                                     " while the solve was writing it: " + std::to_string(frames()) +
                                     " frames went into a file that is gone; stopped (solve again)"));
}

ResultsWriter::ResultsWriter(const std::string& out_dir, const Model& model)
    : path_((std::filesystem::path(out_dir) / "results.h5").string()),
      xdmf_path_((std::filesystem::path(out_dir) / "results.xdmf").string()),
      particles_(model.particle_count()),
      water_(model.water.enabled()),
      file_(h5::File::create(path_)) {
  std::tie(device_, inode_) = identity(path_);
  guarded([&] {
    write_results_start(file_, model, model.position, model.body, model.mass, model.volume);
    std::vector<int32_t> material(particles_);
    for (std::size_t p = 0; p < particles_; ++p) material[p] = model.bodies[model.body[p]].material;
    h5::write(file_, "particles/material", material, {particles_});
    if (!model.loads.empty())
      h5::write(file_, "particles/load_force", flatten(particle_load_forces(model)), {particles_, 2});
    write_xdmf_vertices(file_, particles_);
    open_datasets(0, 0, true);
    h5::set_attribute(file_, "/", "steps", static_cast<int64_t>(0));
    h5::set_attribute(file_, "/", "loop_seconds", 0.0);
    h5::set_attribute(file_, "/", "complete", static_cast<int64_t>(0));
    file_.flush();
  });
}

namespace {

h5::File open_existing(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw Error(located(path, "", "no results to continue (was the interrupted run written to this folder?)"));
  h5::File file = h5::File::open_write(path);
  check_format_tag(file, "talus-results", kResultsFormatVersion);
  return file;
}

}  // namespace

ResultsWriter::ResultsWriter(const std::string& out_dir, const Model& model, const ResultsPosition& resume)
    : path_((std::filesystem::path(out_dir) / "results.h5").string()),
      xdmf_path_((std::filesystem::path(out_dir) / "results.xdmf").string()),
      particles_(model.particle_count()),
      water_(model.water.enabled()),
      file_(open_existing(path_)) {
  std::tie(device_, inode_) = identity(path_);
  if (h5::get_int(file_, "/", "particles") != static_cast<int64_t>(particles_))
    throw Error(located(path_, "particles", "written for a model of another particle count"));
  if (resume.frames < 1 || resume.history_rows < 0)
    throw Error(located(path_, "", "the checkpoint records no frame to continue from"));
  open_datasets(static_cast<hsize_t>(resume.frames), static_cast<hsize_t>(resume.history_rows), false);
  std::vector<double> times = h5::read_doubles(file_, "frames/time");
  time_.assign(times.begin(), times.begin() + resume.frames);
  drop_frame_views(file_, 0);  // views of the kept frames are made anew, of the later ones not
  for (std::size_t f = 0; f < time_.size(); ++f) write_frame_views(file_, particles_, f, fields());
  h5::set_attribute(file_, "/", "complete", static_cast<int64_t>(0));
  file_.flush();
  write_xdmf();
}

namespace {

const char* const kVelocity = "velocity";
const char* const kDisplacement = "displacement";

}  // namespace

std::vector<FrameField> frame_fields(bool water) {
  std::vector<FrameField> fields{{kVelocity, 2}, {kDisplacement, 2}};
  Particles widths;  // the registry's element widths: one particle of every field
  widths.for_each_field([&](const FieldInfo& field, auto& column) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    if (field_written(field, water)) fields.push_back({field.results_name, FieldElement<T>::width});
  });
  return fields;
}

void ResultsWriter::open_datasets(hsize_t frames, hsize_t history_rows, bool fresh) {
  const hsize_t n = particles_;
  // Frame datasets allocate their space as they grow: the ranks of a distributed solve write
  // their rows with the parallel HDF5 (results_parallel.hpp), which writes only allocated chunks.
  auto frame_set = [&](const std::string& path, const h5::Dims& record, hsize_t chunk, bool early,
                       hsize_t record_chunk = 0) {
    return fresh ? h5::Appendable(file_, path, record, H5T_NATIVE_DOUBLE, chunk, early, record_chunk)
                 : h5::Appendable::reopen(file_, path, record, frames);
  };
  auto history_set = [&](const char* path) {
    return fresh ? h5::Appendable(file_, path, {}, H5T_NATIVE_DOUBLE, 1024)
                 : h5::Appendable::reopen(file_, path, {}, history_rows);
  };
  time_set_ = frame_set("frames/time", {}, 256, false);
  frame_sets_.clear();
  for (const FrameField& field : fields()) {
    const h5::Dims record = field.width == 1 ? h5::Dims{n} : h5::Dims{n, static_cast<hsize_t>(field.width)};
    frame_sets_.push_back({field.name, field.width, frame_set("frames/" + field.name, record, 1, true, kFrameBlock)});
  }
  history_time_ = history_set("history/time");
  history_kinetic_ = history_set("history/kinetic_energy");
  history_potential_ = history_set("history/potential_energy");
  history_strain_ = history_set("history/strain_energy");
  history_particle_kinetic_ = history_set("history/particle_kinetic_energy");
}

ResultsPosition ResultsWriter::sync() {
  check_still_there();
  guarded([&] {
    flush_history();
    file_.flush();
  });
  return {frames(), static_cast<long>(history_time_.size())};
}

void ResultsWriter::write_frame(const Simulation& sim) {
  check_still_there();
  guarded([&] {
    write_frame_data(
        sim.particles, [&](std::size_t p) { return grid_velocity_at_particle(sim, p); }, sim.config.threads, sim.time,
        sim.steps);
  });
}

void ResultsWriter::write_frame(const Particles& particles, const std::vector<Eigen::Vector2d>& velocity, double time,
                                long steps) {
  check_still_there();
  guarded([&] { write_frame_data(particles, [&](std::size_t p) { return velocity[p]; }, 1, time, steps); });
}

void ResultsWriter::write_frame_data(const Particles& P, const std::function<Eigen::Vector2d(std::size_t)>& velocity,
                                     int threads, double time, long steps) {
  const std::size_t n = particles_;
  // Frames are in the model's particle order (the solver keeps its own, sorted, order): where[id]
  // is the solver's index of the model's particle id.
  if (n > std::numeric_limits<uint32_t>::max()) throw Error("internal error: more than 2^32 particles in one frame");
  std::vector<uint32_t> where(n);
  for (std::size_t p = 0; p < n; ++p) where[static_cast<std::size_t>(P.id[p])] = static_cast<uint32_t>(p);
  const std::size_t block = std::min<std::size_t>(n, kFrameBlock);
  std::vector<double> rows;
  // One frame dataset, a block of ids at a time: prepare(first, count) before each block, then
  // value(p, i, out) writes the row of the block's i-th id, at the solver's index p.
  auto write_set = [&](FrameSet& set, const auto& prepare, const auto& value) {
    set.data.extend();
    const std::size_t width = static_cast<std::size_t>(set.width);
    rows.resize(block * width);
    for (std::size_t first = 0; first < n; first += block) {
      const std::size_t count = std::min(block, n - first);
      prepare(first, count);
#pragma omp parallel for schedule(static) num_threads(threads)
      for (long i = 0; i < static_cast<long>(count); ++i) {
        const std::size_t row = static_cast<std::size_t>(i);
        value(where[first + row], row, rows.data() + row * width);
      }
      set.data.write_rows(set.data.size() - 1, first, count, rows.data());
    }
  };
  const auto nothing = [](std::size_t, std::size_t) {};
  auto set = frame_sets_.begin();
  write_set(*set++, nothing, [&](std::size_t p, std::size_t, double* out) {
    const Eigen::Vector2d v = velocity(p);
    out[0] = v.x(), out[1] = v.y();
  });
  // The displacement: the position less the initial position, read back from this file a block
  // at a time (no column of either is kept).
  std::vector<double> initial;
  write_set(
      *set++,
      [&](std::size_t first, std::size_t count) {
        initial = h5::read_double_rows(file_, "particles/initial_position", first, count);
      },
      [&](std::size_t p, std::size_t row, double* out) {
        for (int k = 0; k < 2; ++k) out[k] = P.x[p][k] - initial[row * 2 + k];
      });
  P.for_each_field([&](const FieldInfo& field, const auto& column) {
    using E = FieldElement<typename std::decay_t<decltype(column)>::value_type>;
    if (field_written(field, water_))
      write_set(*set++, nothing, [&](std::size_t p, std::size_t, double* out) {
        for (int k = 0; k < E::width; ++k) out[k] = E::get(column[p], k);
      });
  });
  write_frame_metadata(time, steps);
  write_xdmf();
}

void ResultsWriter::write_frame_metadata(double time, long steps) {
  time_set_.append(&time);
  time_.push_back(time);
  write_frame_views(file_, particles_, time_.size() - 1, fields());
  flush_history();
  h5::set_attribute(file_, "/", "steps", static_cast<int64_t>(steps));
  file_.flush();
}

bool ResultsWriter::frames_writable_by_ranks() const {
  for (const FrameSet& set : frame_sets_)
    if (!set.data.allocated_early()) return false;
  return true;
}

std::size_t ResultsWriter::begin_ranks_frame(double time, long steps) {
  check_still_there();
  guarded([&] {
    for (FrameSet& set : frame_sets_) set.data.extend();
    write_frame_metadata(time, steps);
    // Every dataset is closed with the file: the ranks cannot open a file this process holds.
    history_rows_ = history_time_.size();
    for (h5::Appendable* set : {&time_set_, &history_time_, &history_kinetic_, &history_potential_, &history_strain_,
                                &history_particle_kinetic_})
      *set = {};
    for (FrameSet& set : frame_sets_) set.data = {};
    file_.close();
  });
  return time_.size() - 1;
}

void ResultsWriter::end_ranks_frame() {
  guarded([&] {
    file_ = h5::File::open_write(path_);
    open_datasets(time_.size(), history_rows_, false);
    write_xdmf();
  });
}

void ResultsWriter::record_history(const Simulation& sim, const Energies& energy) {
  pending_time_.push_back(sim.time);
  pending_kinetic_.push_back(energy.grid_kinetic);
  pending_particle_kinetic_.push_back(energy.kinetic);
  pending_potential_.push_back(energy.potential);
  pending_strain_.push_back(energy.strain);
}

void ResultsWriter::flush_history() {
  const hsize_t rows = pending_time_.size();
  history_time_.append(pending_time_.data(), rows);
  history_kinetic_.append(pending_kinetic_.data(), rows);
  history_potential_.append(pending_potential_.data(), rows);
  history_strain_.append(pending_strain_.data(), rows);
  history_particle_kinetic_.append(pending_particle_kinetic_.data(), rows);
  pending_time_.clear();
  pending_kinetic_.clear();
  pending_potential_.clear();
  pending_strain_.clear();
  pending_particle_kinetic_.clear();
}

void ResultsWriter::finish(long steps, double loop_seconds, bool complete) {
  check_still_there();
  guarded([&] {
    flush_history();
    h5::set_attribute(file_, "/", "steps", static_cast<int64_t>(steps));
    h5::set_attribute(file_, "/", "loop_seconds", loop_seconds);
    h5::set_attribute(file_, "/", "complete", static_cast<int64_t>(complete));
    file_.flush();
    file_.close();
    write_xdmf();
  });
}

void ResultsWriter::write_xdmf() const {
  write_xdmf_file(xdmf_path_, std::filesystem::path(path_).filename().string(), particles_, time_, fields());
}

}  // namespace talus::solver
