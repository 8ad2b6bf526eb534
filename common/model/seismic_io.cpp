#include "common/model/seismic_io.hpp"

#include <cmath>

#include "common/error.hpp"

namespace talus {

void write_seismic(const h5::File& file, const SeismicSettings& seismic, const BaseMotion& motion) {
  if (seismic.enabled()) {
    h5::create_group(file, "settings/seismic");
    h5::set_attribute(file, "settings/seismic", "k_h", seismic.k_h);
    h5::set_attribute(file, "settings/seismic", "k_v", seismic.k_v);
  }
  if (!motion.enabled()) return;
  const std::string group = "settings/base_motion";
  h5::create_group(file, group);
  h5::set_attribute(file, group, "type", std::string(motion.type == MotionType::Sine ? "sine" : "record"));
  h5::set_attribute(file, group, "start", motion.start);
  h5::set_attribute(file, group, "base", std::string(motion.compliant ? "compliant" : "rigid"));
  h5::write(file, group + "/boundaries", motion.boundaries);
  h5::write(file, group + "/bodies", motion.bodies);
  if (motion.type == MotionType::Sine) {
    h5::set_attribute(file, group, "amplitude", motion.amplitude);
    h5::set_attribute(file, group, "frequency", motion.frequency);
    h5::set_attribute(file, group, "cycles", static_cast<int64_t>(motion.cycles));
    return;
  }
  h5::set_attribute(file, group, "file", motion.file);
  std::vector<double> rows;
  for (std::size_t k = 0; k < motion.time.size(); ++k)
    rows.insert(rows.end(), {motion.time[k], motion.acceleration[k].x(), motion.acceleration[k].y()});
  h5::write(file, group + "/record", rows, {motion.time.size(), 3});
}

void read_seismic(const h5::File& file, SeismicSettings& seismic, BaseMotion& motion) {
  seismic = {};
  motion = {};
  if (h5::exists(file, "settings/seismic")) {
    seismic.k_h = h5::get_double(file, "settings/seismic", "k_h");
    seismic.k_v = h5::get_double(file, "settings/seismic", "k_v");
    if (!(seismic.k_h >= 0 && seismic.k_h <= 2) || !(seismic.k_v > -1 && seismic.k_v < 1))
      throw Error(located(file.path(), "settings/seismic", "expected k_h in [0, 2] and k_v in (-1, 1)"));
  }
  const std::string group = "settings/base_motion";
  if (!h5::exists(file, group)) return;
  const std::string type = h5::get_string(file, group, "type");
  motion.start = h5::get_double(file, group, "start");
  motion.compliant = h5::get_string(file, group, "base") == "compliant";
  motion.boundaries = h5::read_strings(file, group + "/boundaries");
  motion.bodies = h5::read_strings(file, group + "/bodies");
  if (!(motion.start >= 0) || !std::isfinite(motion.start))
    throw Error(located(file.path(), group + "@start", "expected a finite time >= 0"));
  if (type == "sine") {
    motion.type = MotionType::Sine;
    motion.amplitude = h5::get_double(file, group, "amplitude");
    motion.frequency = h5::get_double(file, group, "frequency");
    motion.cycles = static_cast<int>(h5::get_int(file, group, "cycles"));
    if (!(motion.amplitude > 0) || !std::isfinite(motion.amplitude) || !(motion.frequency > 0) ||
        !std::isfinite(motion.frequency) || motion.cycles < 1)
      throw Error(located(file.path(), group, "expected amplitude > 0, frequency > 0 and cycles >= 1"));
    return;
  }
  if (type != "record")
    throw Error(located(file.path(), group + "@type", "unknown type '" + type + "' (expected sine or record)"));
  motion.type = MotionType::Record;
  motion.file = h5::get_string(file, group, "file");
  h5::Dims dims;
  const std::vector<double> rows = h5::read_doubles(file, group + "/record", &dims);
  if (dims.size() != 2 || dims[1] != 3) throw Error(located(file.path(), group + "/record", "expected [n, 3]"));
  for (std::size_t k = 0; k < dims[0]; ++k) {
    motion.time.push_back(rows[3 * k]);
    motion.acceleration.emplace_back(rows[3 * k + 1], rows[3 * k + 2]);
  }
  if (const std::string problem = motion_record_problem(motion.time, motion.acceleration); !problem.empty())
    throw Error(located(file.path(), group + "/record", problem));
}

void write_absorbing(const h5::File& file, const AbsorbingNodes& a) {
  if (a.empty()) return;
  const hsize_t n = a.node.size();
  std::vector<double> normals, impedances;
  for (std::size_t k = 0; k < n; ++k) {
    normals.insert(normals.end(), {a.normal[k].x(), a.normal[k].y()});
    impedances.insert(impedances.end(), {a.impedance[k].x(), a.impedance[k].y()});
  }
  h5::write(file, "boundary_conditions/absorbing_nodes", a.node, {n});
  h5::write(file, "boundary_conditions/absorbing_lengths", a.length, {n});
  h5::write(file, "boundary_conditions/absorbing_normals", normals, {n, 2});
  h5::write(file, "boundary_conditions/absorbing_impedances", impedances, {n, 2});
  h5::write(file, "boundary_conditions/absorbing_input", a.input, {n});
}

AbsorbingNodes read_absorbing(const h5::File& file, std::size_t node_count) {
  AbsorbingNodes a;
  if (!h5::exists(file, "boundary_conditions/absorbing_nodes")) return a;
  a.node = h5::read_ints(file, "boundary_conditions/absorbing_nodes");
  a.length = h5::read_doubles(file, "boundary_conditions/absorbing_lengths");
  a.input = h5::read_ints(file, "boundary_conditions/absorbing_input");
  const std::vector<double> normals = h5::read_doubles(file, "boundary_conditions/absorbing_normals");
  const std::vector<double> impedances = h5::read_doubles(file, "boundary_conditions/absorbing_impedances");
  const std::size_t n = a.node.size();
  if (a.length.size() != n || a.input.size() != n || normals.size() != 2 * n || impedances.size() != 2 * n)
    throw Error(located(file.path(), "boundary_conditions/absorbing_nodes", "the absorbing datasets differ in length"));
  for (std::size_t k = 0; k < n; ++k) {
    a.normal.emplace_back(normals[2 * k], normals[2 * k + 1]);
    a.impedance.emplace_back(impedances[2 * k], impedances[2 * k + 1]);
    const bool sound = a.node[k] >= 0 && static_cast<std::size_t>(a.node[k]) < node_count && std::isfinite(a.length[k]) &&
                       a.length[k] >= 0 && std::abs(a.normal[k].norm() - 1) < 1e-9 && a.impedance[k].allFinite() &&
                       a.impedance[k].minCoeff() >= 0;
    if (!sound)
      throw Error(located(file.path(), "boundary_conditions/absorbing_nodes",
                          "row " + std::to_string(k + 1) + ": expected a node id, a length >= 0, a unit normal and "
                                                           "impedances >= 0"));
  }
  return a;
}

}  // namespace talus
