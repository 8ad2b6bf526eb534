#include "solver/checkpoint.hpp"

#include <cmath>
#include <cstring>
#include <filesystem>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/model_io.hpp"

namespace talus::solver {
namespace {

// FNV-1a over raw bytes.
class Fingerprint {
 public:
  template <class T>
  void add(const std::vector<T>& values) {
    add_bytes(values.data(), values.size() * sizeof(T));
  }
  void add(double value) { add_bytes(&value, sizeof value); }
  uint64_t value() const { return hash_; }

 private:
  void add_bytes(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ bytes[i]) * 1099511628211ull;
  }
  uint64_t hash_ = 1469598103934665603ull;
};

template <class Vec>
std::vector<Vec> read_rows(const h5::File& file, const std::string& path, std::size_t rows) {
  constexpr int width = Vec::RowsAtCompileTime;
  h5::Dims dims;
  const std::vector<double> flat = h5::read_doubles(file, path, &dims);
  if (dims.size() != 2 || dims[0] != rows || dims[1] != static_cast<hsize_t>(width))
    throw Error(located(file.path(), path, "expected shape [" + std::to_string(rows) + "," + std::to_string(width) + "]"));
  std::vector<Vec> out(rows);
  for (std::size_t i = 0; i < rows; ++i)
    for (int k = 0; k < width; ++k) {
      out[i][k] = flat[i * width + k];
      if (!std::isfinite(out[i][k])) throw Error(located(file.path(), path, "non-finite value in row " + std::to_string(i)));
    }
  return out;
}

template <class T, class Read>
std::vector<T> read_column(const h5::File& file, const std::string& path, std::size_t rows, Read read) {
  h5::Dims dims;
  std::vector<T> values = read(file, path, &dims);
  if (dims.size() != 1 || dims[0] != rows)
    throw Error(located(file.path(), path, "expected " + std::to_string(rows) + " values"));
  return values;
}

const char* const kLoopGroup = "loop";

}  // namespace

uint64_t model_fingerprint(const Model& model) {
  Fingerprint f;
  f.add(flatten(model.nodes));
  f.add(model.triangles);
  f.add(flatten(model.position));
  f.add(model.mass);
  f.add(model.volume);
  f.add(model.body);
  for (double setting : {model.run.end_time, model.run.cfl, model.run.output_interval, model.run.gravity.x(),
                         model.run.gravity.y(), model.run.gravity_ramp, model.run.damping, model.run.pic_fraction})
    f.add(setting);
  return f.value();
}

std::string checkpoint_path(const std::string& out_dir) {
  return (std::filesystem::path(out_dir) / "checkpoint.h5").string();
}

void write_checkpoint(const std::string& out_dir, const Model& model, const Simulation& sim, const LoopState& loop,
                      const ResultsPosition& results) {
  const std::string path = checkpoint_path(out_dir);
  h5::write_atomically(path, [&](const h5::File& file) {
    write_format_tag(file, "talus-checkpoint", kCheckpointFormatVersion);
    const uint64_t fingerprint = model_fingerprint(model);
    int64_t stored = 0;
    std::memcpy(&stored, &fingerprint, sizeof stored);
    h5::set_attribute(file, "/", "model_fingerprint", stored);

    const Particles& P = sim.particles;
    const hsize_t n = P.size();
    h5::set_attribute(file, "/", "particles", static_cast<int64_t>(n));
    h5::set_attribute(file, "/", "moving_count", static_cast<int64_t>(P.moving_count));
    h5::set_attribute(file, "/", "time", sim.time);
    h5::set_attribute(file, "/", "steps", static_cast<int64_t>(sim.steps));
    h5::write(file, "particles/x", flatten(P.x), {n, 2});
    h5::write(file, "particles/v", flatten(P.v), {n, 2});
    h5::write(file, "particles/m", P.m, {n});
    h5::write(file, "particles/volume", P.volume, {n});
    h5::write(file, "particles/sigma", flatten(P.sigma), {n, 4});
    h5::write(file, "particles/eps_p", P.eps_p, {n});
    h5::write(file, "particles/d_eps", flatten(P.d_eps), {n, 4});
    h5::write(file, "particles/body", P.body, {n});
    h5::write(file, "particles/element", P.element, {n});
    h5::write(file, "particles/id", P.id, {n});

    h5::create_group(file, kLoopGroup);
    h5::set_attribute(file, kLoopGroup, "next_output", loop.next_output);
    h5::set_attribute(file, kLoopGroup, "next_checkpoint", loop.next_checkpoint);
    h5::set_attribute(file, kLoopGroup, "peak_kinetic", loop.peak_kinetic);
    h5::set_attribute(file, kLoopGroup, "peak_time", loop.peak_time);
    h5::set_attribute(file, kLoopGroup, "rest_since", loop.rest_since);
    h5::set_attribute(file, kLoopGroup, "budget", loop.budget);
    h5::set_attribute(file, kLoopGroup, "budget_limit", loop.budget_limit);
    h5::set_attribute(file, kLoopGroup, "results_frames", static_cast<int64_t>(results.frames));
    h5::set_attribute(file, kLoopGroup, "results_history_rows", static_cast<int64_t>(results.history_rows));
  });
}

void read_checkpoint(const std::string& out_dir, const Model& model, Simulation& sim, LoopState& loop,
                     ResultsPosition& results) {
  const std::string path = checkpoint_path(out_dir);
  if (!std::filesystem::exists(path))
    throw Error(located(path, "", "no checkpoint to restart from (solve with --checkpoint-interval T, or stop a "
                                  "solve with Ctrl-C, to write one)"));
  h5::File file = h5::File::open_read(path);
  check_format_tag(file, "talus-checkpoint", kCheckpointFormatVersion);
  const uint64_t fingerprint = model_fingerprint(model);
  int64_t expected = 0;
  std::memcpy(&expected, &fingerprint, sizeof expected);
  if (h5::get_int(file, "/", "model_fingerprint") != expected)
    throw Error(located(path, "", "written for another model (or another version of this one): solve afresh"));

  const std::size_t n = model.particle_count();
  if (h5::get_int(file, "/", "particles") != static_cast<int64_t>(n))
    throw Error(located(path, "particles", "expected " + std::to_string(n) + " particles"));
  const int64_t moving = h5::get_int(file, "/", "moving_count");
  if (moving < 0 || moving > static_cast<int64_t>(n)) throw Error(located(path, "moving_count", "out of range"));

  Particles P;
  P.x = read_rows<Vec2>(file, "particles/x", n);
  P.v = read_rows<Vec2>(file, "particles/v", n);
  P.sigma = read_rows<Vec4>(file, "particles/sigma", n);
  P.d_eps = read_rows<Vec4>(file, "particles/d_eps", n);
  P.m = read_column<double>(file, "particles/m", n, h5::read_doubles);
  P.volume = read_column<double>(file, "particles/volume", n, h5::read_doubles);
  P.eps_p = read_column<double>(file, "particles/eps_p", n, h5::read_doubles);
  P.body = read_column<int32_t>(file, "particles/body", n, h5::read_ints);
  P.element = read_column<int32_t>(file, "particles/element", n, h5::read_ints);
  P.id = read_column<int32_t>(file, "particles/id", n, h5::read_ints);
  P.moving_count = static_cast<std::size_t>(moving);
  std::vector<bool> seen(n, false);
  for (std::size_t p = 0; p < n; ++p) {
    if (!(P.m[p] > 0) || !(P.volume[p] > 0) || !std::isfinite(P.eps_p[p]))
      throw Error(located(path, "particles", "particle " + std::to_string(p) + " has a bad mass, volume or strain"));
    if (P.body[p] < 0 || P.body[p] >= static_cast<int32_t>(sim.body_fixed.size()) || P.element[p] < 0 ||
        P.element[p] >= static_cast<int32_t>(sim.mesh.element_count()) || P.id[p] < 0 ||
        P.id[p] >= static_cast<int32_t>(n) || seen[P.id[p]])
      throw Error(located(path, "particles", "particle " + std::to_string(p) + " has an index out of range"));
    seen[P.id[p]] = true;
    if (sim.body_fixed[P.body[p]] != (p >= P.moving_count))
      throw Error(located(path, "moving_count", "particles of fixed bodies must come after all the others"));
  }
  sim.particles = std::move(P);
  sim.time = h5::get_double(file, "/", "time");
  sim.steps = static_cast<long>(h5::get_int(file, "/", "steps"));
  if (!std::isfinite(sim.time) || sim.time < 0 || sim.steps < 0)
    throw Error(located(path, "time, steps", "out of range"));

  loop.next_output = h5::get_double(file, kLoopGroup, "next_output");
  loop.next_checkpoint = h5::get_double(file, kLoopGroup, "next_checkpoint");
  loop.peak_kinetic = h5::get_double(file, kLoopGroup, "peak_kinetic");
  loop.peak_time = h5::get_double(file, kLoopGroup, "peak_time");
  loop.rest_since = h5::get_double(file, kLoopGroup, "rest_since");
  loop.budget = h5::get_double(file, kLoopGroup, "budget");
  loop.budget_limit = h5::get_double(file, kLoopGroup, "budget_limit");
  results.frames = static_cast<long>(h5::get_int(file, kLoopGroup, "results_frames"));
  results.history_rows = static_cast<long>(h5::get_int(file, kLoopGroup, "results_history_rows"));
}

}  // namespace talus::solver
