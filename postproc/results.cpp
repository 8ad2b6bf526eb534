#include "postproc/results.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/model/checks.hpp"
#include "common/model/model_io.hpp"

namespace talus::postproc {
namespace {

// A dataset of shape [F, N, width] (width 0: [F, N]) split into frames.
std::vector<double> read_frames(const h5::File& file, const std::string& path, std::size_t frames,
                                std::size_t particles, std::size_t width) {
  h5::Dims dims;
  std::vector<double> flat = h5::read_doubles(file, path, &dims);
  const bool ok = width == 0 ? dims.size() == 2 : (dims.size() == 3 && dims[2] == width);
  if (!ok || dims[0] != frames || dims[1] != particles)
    throw Error(located(file.path(), path,
                        "expected shape [" + std::to_string(frames) + "," + std::to_string(particles) +
                            (width ? "," + std::to_string(width) : std::string()) + "]"));
  for (std::size_t i = 0; i < flat.size(); ++i)
    if (!std::isfinite(flat[i])) throw Error(located(file.path(), path, "non-finite value at flat index " + std::to_string(i)));
  return flat;
}

std::vector<std::vector<Eigen::Vector2d>> as_points(const std::vector<double>& flat, std::size_t frames,
                                                    std::size_t particles) {
  std::vector<std::vector<Eigen::Vector2d>> out(frames, std::vector<Eigen::Vector2d>(particles));
  for (std::size_t f = 0; f < frames; ++f)
    for (std::size_t p = 0; p < particles; ++p)
      out[f][p] = {flat[(f * particles + p) * 2], flat[(f * particles + p) * 2 + 1]};
  return out;
}

std::vector<double> read_vector(const h5::File& file, const std::string& path, std::size_t length) {
  h5::Dims dims;
  std::vector<double> values = h5::read_doubles(file, path, &dims);
  if (dims.size() != 1 || dims[0] != length)
    throw Error(located(file.path(), path, "expected " + std::to_string(length) + " values"));
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i])) throw Error(located(file.path(), path, "non-finite value at row " + std::to_string(i)));
  return values;
}

// No run takes a particle a million times the extent of the particles' start from it (the solver
// stops one when a particle leaves the mesh): such a frame position (1e308) is damage, and would
// break the figures' axes.
constexpr double kMaxTravel = 1e6;

void check_travel(const Results& results, const std::string& path) {
  Eigen::AlignedBox2d start;
  for (const auto& p : results.initial_position) start.extend(p);
  const double extent = std::max(start.diagonal().norm(), 1.0);
  for (std::size_t f = 0; f < results.position.size(); ++f)
    for (std::size_t p = 0; p < results.position[f].size(); ++p) {
      const Eigen::Vector2d& x = results.position[f][p];
      const double distance = start.exteriorDistance(x);
      if (distance > kMaxTravel * extent) {
        std::ostringstream message;
        message.precision(3);
        message << "particle " << p << " of frame " << f << " is at (" << x.x() << ", " << x.y() << ") m, " << distance
                << " m from where the particles started (an extent of " << extent << " m): more than " << kMaxTravel
                << " times that extent, which no run reaches";
        throw Error(located(path, "frames/position", message.str()));
      }
    }
}

std::vector<double> flatten(const std::vector<std::vector<Eigen::Vector2d>>& frames) {
  std::vector<double> flat;
  for (const auto& frame : frames)
    for (const auto& p : frame) flat.push_back(p.x()), flat.push_back(p.y());
  return flat;
}

}  // namespace

Results read_results(const std::string& path) {
  const h5::File file = h5::File::open_read(path);
  check_format_tag(file, "talus-results", kResultsFormatVersion);
  Results results;
  read_metadata(file, results.metadata);

  results.body = h5::read_ints(file, "particles/body");
  const std::size_t n = results.body.size();
  for (std::size_t p = 0; p < n; ++p)
    if (results.body[p] < 0 || results.body[p] >= static_cast<int32_t>(results.metadata.bodies.size()))
      throw Error(located(path, "particles/body", "body index out of range at particle " + std::to_string(p)));
  {
    h5::Dims dims;
    const std::vector<double> flat = h5::read_doubles(file, "particles/initial_position", &dims);
    if (dims.size() != 2 || dims[0] != n || dims[1] != 2)
      throw Error(located(path, "particles/initial_position", "expected shape [" + std::to_string(n) + ",2]"));
    results.initial_position = as_points(flat, 1, n).front();
  }
  results.mass = read_vector(file, "particles/mass", n);
  results.volume = read_vector(file, "particles/volume", n);
  if (h5::exists(file, "particles/load_force")) {
    h5::Dims dims;
    const std::vector<double> flat = h5::read_doubles(file, "particles/load_force", &dims);
    if (dims.size() != 2 || dims[0] != n || dims[1] != 2)
      throw Error(located(path, "particles/load_force", "expected shape [" + std::to_string(n) + ",2]"));
    results.load_force = as_points(flat, 1, n).front();
  }

  h5::Dims time_dims;
  results.frame_time = h5::read_doubles(file, "frames/time", &time_dims);
  const std::size_t f = results.frame_time.size();
  if (f == 0) throw Error(located(path, "frames/time", "no frames"));
  check_frame_times(results.frame_time, path);
  check_particle_count(file, n);
  results.position = as_points(read_frames(file, "frames/position", f, n, 2), f, n);
  check_travel(results, path);
  results.velocity = as_points(read_frames(file, "frames/velocity", f, n, 2), f, n);
  if (h5::exists(file, "frames/plastic_strain")) {
    const std::vector<double> flat = read_frames(file, "frames/plastic_strain", f, n, 0);
    for (std::size_t k = 0; k < f; ++k)
      results.plastic_strain.emplace_back(flat.begin() + k * n, flat.begin() + (k + 1) * n);
  }

  // Complete only when the solver said so: a file without the attribute was cut short or damaged.
  results.complete = h5::has_attribute(file, "/", "complete") && h5::get_int(file, "/", "complete") != 0;
  const std::size_t h = h5::shape(file, "history/time").empty() ? 0 : h5::shape(file, "history/time").front();
  results.history_time = read_vector(file, "history/time", h);
  results.kinetic_energy = read_vector(file, "history/kinetic_energy", h);
  results.potential_energy = read_vector(file, "history/potential_energy", h);
  results.strain_energy = read_vector(file, "history/strain_energy", h);
  return results;
}

void write_results(const std::string& path, const Results& results) {
  h5::write_atomically(path, [&](const h5::File& file) {
    write_results_start(file, results.metadata, results.initial_position, results.body, results.mass,
                        results.volume);
    const hsize_t f = results.frames(), n = results.particles();
    if (!results.load_force.empty()) h5::write(file, "particles/load_force", talus::flatten(results.load_force), {n, 2});
    h5::write(file, "frames/time", results.frame_time, {f});
    h5::write(file, "frames/position", flatten(results.position), {f, n, 2});
    h5::write(file, "frames/velocity", flatten(results.velocity), {f, n, 2});
    if (!results.plastic_strain.empty()) {
      std::vector<double> flat;
      for (const auto& frame : results.plastic_strain) flat.insert(flat.end(), frame.begin(), frame.end());
      h5::write(file, "frames/plastic_strain", flat, {f, n});
    }
    const hsize_t h = results.history_time.size();
    h5::write(file, "history/time", results.history_time, {h});
    h5::write(file, "history/kinetic_energy", results.kinetic_energy, {h});
    h5::write(file, "history/potential_energy", results.potential_energy, {h});
    h5::write(file, "history/strain_energy", results.strain_energy, {h});
    h5::set_attribute(file, "/", "complete", static_cast<int64_t>(results.complete));
  });
}

}  // namespace talus::postproc
