#include "common/model/model.hpp"

#include <cmath>
#include <filesystem>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "common/model/checks.hpp"
#include "common/model/model_io.hpp"
#include "common/model/seismic_io.hpp"

namespace talus {
namespace {

std::vector<int32_t> flatten(const std::vector<std::array<int32_t, 3>>& rows) {
  std::vector<int32_t> flat;
  flat.reserve(rows.size() * 3);
  for (const auto& row : rows) flat.insert(flat.end(), row.begin(), row.end());
  return flat;
}

}  // namespace

std::vector<Eigen::Vector2d> particle_load_forces(const Model& model) {
  std::vector<Eigen::Vector2d> force;
  if (model.loads.empty()) return force;
  force.resize(model.particle_count());
  for (std::size_t p = 0; p < force.size(); ++p) {
    const int32_t L = model.load[p];
    force[p] = L < 0                     ? Eigen::Vector2d::Zero()
               : model.loads[L].pressure ? Eigen::Vector2d(-*model.loads[L].pressure * model.load_normal[p])
                                         : Eigen::Vector2d(model.load_length[p] * *model.loads[L].traction);
  }
  return force;
}

void write_model(const std::string& path, const Model& model) {
  h5::write_atomically(path, [&](const h5::File& file) {
    write_format_tag(file, "talus-model", kModelFormatVersion);
    write_metadata(file, model);

    h5::write(file, "mesh/nodes", flatten(model.nodes), {model.nodes.size(), 2});
    h5::write(file, "mesh/triangles", flatten(model.triangles), {model.triangles.size(), 3});
    h5::write(file, "mesh/neighbours", flatten(model.neighbours), {model.neighbours.size(), 3});
    h5::create_group(file, "mesh/node_sets");
    for (const auto& [name, nodes] : model.node_sets) h5::write(file, "mesh/node_sets/" + name, nodes, {nodes.size()});

    h5::write(file, "boundary_conditions/fixed_nodes", model.fixed_nodes, {model.fixed_nodes.size()});
    h5::write(file, "boundary_conditions/roller_nodes", model.roller_nodes, {model.roller_nodes.size()});
    h5::write(file, "boundary_conditions/roller_normals", flatten(model.roller_normals),
              {model.roller_normals.size(), 2});
    if (!model.friction_nodes.empty()) {
      h5::write(file, "boundary_conditions/friction_nodes", model.friction_nodes, {model.friction_nodes.size()});
      h5::write(file, "boundary_conditions/friction_normals", flatten(model.friction_normals),
                {model.friction_normals.size(), 2});
      h5::write(file, "boundary_conditions/friction_coefficients", model.friction_coefficients,
                {model.friction_coefficients.size()});
    }

    write_absorbing(file, model.absorbing);

    const std::size_t n = model.particle_count();
    h5::write(file, "particles/position", flatten(model.position), {n, 2});
    h5::write(file, "particles/velocity", flatten(model.velocity), {n, 2});
    h5::write(file, "particles/volume", model.volume, {n});
    h5::write(file, "particles/mass", model.mass, {n});
    h5::write(file, "particles/stress", flatten(model.stress), {n, 4});
    h5::write(file, "particles/body", model.body, {n});
    h5::write(file, "particles/element", model.element, {n});
    if (!model.loads.empty()) {
      h5::write(file, "particles/load", model.load, {n});
      h5::write(file, "particles/load_length", model.load_length, {n});
      h5::write(file, "particles/load_normal", flatten(model.load_normal), {n, 2});
    }
    write_properties(file, model);
    h5::set_attribute(file, "/", "particles", static_cast<int64_t>(n));
  });
}

Model read_model(const std::string& path) {
  h5::File file = h5::File::open_read(path);
  check_format_tag(file, "talus-model", kModelFormatVersion);
  Model model;
  read_metadata(file, model);

  h5::Dims dims;
  auto nodes = h5::read_doubles(file, "mesh/nodes", &dims);
  check_finite(file, "mesh/nodes", nodes);
  model.nodes = unflatten<Eigen::Vector2d>(nodes, dims, file, "mesh/nodes", dims.empty() ? 0 : dims[0]);
  const int32_t node_count = static_cast<int32_t>(model.nodes.size());

  auto read_triples = [&](const std::string& where, int32_t low, int32_t high) {
    h5::Dims d;
    const auto flat = h5::read_ints(file, where, &d);
    if (d.size() != 2 || d[1] != 3) throw Error(located(path, where, "expected shape [E,3]"));
    std::vector<std::array<int32_t, 3>> out(d[0]);
    for (std::size_t e = 0; e < d[0]; ++e)
      for (int k = 0; k < 3; ++k) {
        const int32_t v = flat[3 * e + k];
        if (v < low || v >= high) throw Error(located(path, where, "index out of range in row " + std::to_string(e)));
        out[e][k] = v;
      }
    return out;
  };
  model.triangles = read_triples("mesh/triangles", 0, node_count);
  if (model.triangles.empty()) throw Error(located(path, "mesh/triangles", "the mesh has no triangles"));
  model.neighbours = read_triples("mesh/neighbours", -1, static_cast<int32_t>(model.triangles.size()));
  if (model.neighbours.size() != model.triangles.size())
    throw Error(located(path, "mesh/neighbours", "expected one row per triangle"));

  auto read_node_list = [&](const std::string& where) {
    auto list = h5::read_ints(file, where);
    for (int32_t v : list)
      if (v < 0 || v >= node_count) throw Error(located(path, where, "node index out of range"));
    return list;
  };
  for (const auto& name : h5::list(file, "mesh/node_sets")) model.node_sets[name] = read_node_list("mesh/node_sets/" + name);
  model.fixed_nodes = read_node_list("boundary_conditions/fixed_nodes");
  model.roller_nodes = read_node_list("boundary_conditions/roller_nodes");
  auto normals = h5::read_doubles(file, "boundary_conditions/roller_normals", &dims);
  check_finite(file, "boundary_conditions/roller_normals", normals);
  model.roller_normals = unflatten<Eigen::Vector2d>(normals, dims, file, "boundary_conditions/roller_normals",
                                                    model.roller_nodes.size());
  if (h5::exists(file, "boundary_conditions/friction_nodes")) {
    model.friction_nodes = read_node_list("boundary_conditions/friction_nodes");
    auto friction_normals = h5::read_doubles(file, "boundary_conditions/friction_normals", &dims);
    check_finite(file, "boundary_conditions/friction_normals", friction_normals);
    model.friction_normals = unflatten<Eigen::Vector2d>(friction_normals, dims, file,
                                                        "boundary_conditions/friction_normals",
                                                        model.friction_nodes.size());
    model.friction_coefficients = h5::read_doubles(file, "boundary_conditions/friction_coefficients", &dims);
    check_count(file, "boundary_conditions/friction_coefficients", dims, model.friction_nodes.size());
    for (double mu : model.friction_coefficients)
      if (!(std::isfinite(mu) && mu >= 0))
        throw Error(located(path, "boundary_conditions/friction_coefficients", "expected finite numbers >= 0"));
  }

  model.absorbing = read_absorbing(file, static_cast<std::size_t>(node_count));

  auto positions = h5::read_doubles(file, "particles/position", &dims);
  const std::size_t n = dims.empty() ? 0 : dims[0];
  if (n == 0) throw Error(located(path, "particles/position", "the model has no particles"));
  check_finite(file, "particles/position", positions);
  model.position = unflatten<Eigen::Vector2d>(positions, dims, file, "particles/position", n);
  auto velocities = h5::read_doubles(file, "particles/velocity", &dims);
  check_finite(file, "particles/velocity", velocities);
  model.velocity = unflatten<Eigen::Vector2d>(velocities, dims, file, "particles/velocity", n);
  auto stresses = h5::read_doubles(file, "particles/stress", &dims);
  check_finite(file, "particles/stress", stresses);
  model.stress = unflatten<Eigen::Vector4d>(stresses, dims, file, "particles/stress", n);
  model.volume = h5::read_doubles(file, "particles/volume", &dims);
  check_count(file, "particles/volume", dims, n);
  model.mass = h5::read_doubles(file, "particles/mass", &dims);
  check_count(file, "particles/mass", dims, n);
  for (std::size_t p = 0; p < n; ++p)
    if (!(model.volume[p] > 0) || !(model.mass[p] > 0) || !std::isfinite(model.volume[p]) || !std::isfinite(model.mass[p]))
      throw Error(located(path, "particles/volume, particles/mass", "particle " + std::to_string(p) +
                                                                       " has a non-positive or non-finite value"));
  model.body = h5::read_ints(file, "particles/body", &dims);
  check_count(file, "particles/body", dims, n);
  model.element = h5::read_ints(file, "particles/element", &dims);
  check_count(file, "particles/element", dims, n);
  for (std::size_t p = 0; p < n; ++p) {
    if (model.body[p] < 0 || model.body[p] >= static_cast<int32_t>(model.bodies.size()))
      throw Error(located(path, "particles/body", "body index out of range for particle " + std::to_string(p)));
    if (model.element[p] < 0 || model.element[p] >= static_cast<int32_t>(model.triangles.size()))
      throw Error(located(path, "particles/element", "element index out of range for particle " + std::to_string(p)));
  }
  if (!model.loads.empty()) {
    model.load = h5::read_ints(file, "particles/load", &dims);
    check_count(file, "particles/load", dims, n);
    model.load_length = h5::read_doubles(file, "particles/load_length", &dims);
    check_count(file, "particles/load_length", dims, n);
    check_finite(file, "particles/load_length", model.load_length);
    auto normals = h5::read_doubles(file, "particles/load_normal", &dims);
    check_finite(file, "particles/load_normal", normals);
    model.load_normal = unflatten<Eigen::Vector2d>(normals, dims, file, "particles/load_normal", n);
    check_particle_loads(model, path);
  }
  read_properties(file, model);
  check_particle_count(file, n);
  check_model_geometry(model, path);
  return model;
}

}  // namespace talus
