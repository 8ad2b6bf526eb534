#include "solver/stress/material_state.hpp"

#include <algorithm>
#include <cmath>

#include "common/error.hpp"
#include "common/model/model.hpp"
#include "solver/step/simulation.hpp"

namespace talus::solver {
namespace {

// c_d = sqrt((K + 4G/3) / rho), with the undrained pore stiffness when there is one (the mixture
// is stiffer: its P-wave speed sets the time step).
double wave_speed(double shear_modulus, double bulk_modulus, double pore_stiffness, double density) {
  if (pore_stiffness > 0) return std::sqrt((bulk_modulus + pore_stiffness + 4 * shear_modulus / 3) / density);
  return std::sqrt((bulk_modulus + 4 * shear_modulus / 3) / density);
}

// Calls f(Model{}, shared, own) with the material's parameters, a particle's `values` in them
// and its strength reduced like the material's.
template <class F>
void with_particle_parameters(const MaterialState& s, const double* values, F&& f) {
  with_model(s.material.model, [&](auto model, const auto& base) {
    using Model = decltype(model);
    SharedParameters shared = s.material;
    auto own = base;
    for (std::size_t k = 0; k < s.property_slots.size(); ++k) set_parameter(shared, own, s.property_slots[k], values[k]);
    if (s.reduction) own = Model::reduced(own, *s.reduction);
    f(model, shared, own);
  });
}

double pore_stiffness(const MaterialState& s, const SharedParameters& shared) {
  return s.water_bulk_modulus > 0 && shared.porosity > 0 ? s.water_bulk_modulus / shared.porosity : 0.0;
}

MaterialState make_state(const Material& m, const PrepareContext& context, double water_bulk_modulus) {
  MaterialState s;
  s.material = m;
  s.context = context;
  s.water_bulk_modulus = water_bulk_modulus;
  s.density = m.density;
  s.shear_modulus = m.shear_modulus();
  s.bulk_modulus = m.bulk_modulus();
  s.pore_stiffness = pore_stiffness(s, m);
  s.wave_speed = wave_speed(s.shear_modulus, s.bulk_modulus, s.pore_stiffness, s.density);
  s.history_width = history_width(m);
  s.prepared = prepare(m, context);
  return s;
}

// For each material, the indices into model.properties of its properties, in model order.
std::vector<std::vector<std::size_t>> properties_by_material(const Model& model) {
  std::vector<std::vector<std::size_t>> out(model.materials.size());
  for (std::size_t k = 0; k < model.properties.size(); ++k)
    for (std::size_t m = 0; m < model.materials.size(); ++m)
      if (model.materials[m].name == model.properties[k].material) out[m].push_back(k);
  return out;
}

}  // namespace

MaterialState make_material(const Material& material) { return make_state(material, PrepareContext{}, 0); }

void prepare_materials(Config& config, const Model& model) {
  // Element size for the regularisation: the mean of sqrt(2 A), the leg of a right isosceles
  // triangle of the same area.
  double size = 0;
  for (double area : config.mesh.area) size += std::sqrt(2 * area);
  size /= std::max<std::size_t>(config.mesh.area.size(), 1);
  const bool undrained = config.water.enabled() && config.water.mode == WaterMode::Undrained;
  config.materials.clear();
  for (const Material& material : model.materials) {
    if (const auto problem = material_problem(material))
      throw Error("model: materials/" + material.name + "@" + problem->key + ": " + problem->message);
    config.materials.push_back(make_state(material, PrepareContext{size}, undrained ? config.water.bulk_modulus : 0));
  }
  if (model.properties.empty()) return;

  if (const auto problem = properties_problem(model)) throw Error("model: " + problem->key + ": " + problem->message);
  const auto by_material = properties_by_material(model);
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    MaterialState& state = config.materials[m];
    for (std::size_t k : by_material[m]) {
      const std::string& key = model.properties[k].parameter;
      if (key == "youngs_modulus" || key == "poisson_ratio") state.elastic_columns = true;
      state.property_slots.push_back(*parameter_slot(state.material, key));
    }
  }
  // The time step and the history width follow the particles' own values.
  const std::vector<double> rows = particle_properties(model, config);
  const std::size_t width = rows.size() / model.particle_count();
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    MaterialState& state = config.materials[model.bodies[model.body[p]].material];
    if (state.property_slots.empty()) continue;
    with_particle_parameters(state, rows.data() + p * width, [&](auto model, const SharedParameters& shared,
                                                                 const auto& own) {
      state.wave_speed = std::max(state.wave_speed, wave_speed(shared.shear_modulus(), shared.bulk_modulus(),
                                                               pore_stiffness(state, shared), shared.density));
      state.history_width = std::max(state.history_width, decltype(model)::history_width(own));
    });
  }
}

std::vector<double> particle_properties(const Model& model, const Config& config) {
  std::size_t width = 0;
  for (const MaterialState& state : config.materials) width = std::max(width, state.property_slots.size());
  if (width == 0) return {};
  const auto by_material = properties_by_material(model);
  const std::size_t n = model.particle_count();
  std::vector<double> rows(n * width, 0.0);
  for (std::size_t p = 0; p < n; ++p) {
    const auto& columns = by_material[model.bodies[model.body[p]].material];
    for (std::size_t k = 0; k < columns.size(); ++k) rows[p * width + k] = model.properties[columns[k]].values[p];
  }
  return rows;
}

void reduce_strength(MaterialState& state, double factor) {
  state.reduction = factor;
  state.prepared = prepare(reduced(state.material, factor), state.context);
}

void prepare_particle_materials(std::vector<MaterialState>& materials, const std::vector<int32_t>& material_of_body,
                                const Particles& P) {
  const std::size_t width = width_of(P.properties, P.size());
  for (MaterialState& state : materials) {
    state.row_of_id.clear();
    state.particle_materials.clear();
    if (!state.property_slots.empty()) state.row_of_id.assign(P.size(), -1);
  }
  for (std::size_t p = 0; p < P.size(); ++p) {
    MaterialState& state = materials[material_of_body[P.body[p]]];
    if (state.property_slots.empty()) continue;
    state.row_of_id[P.id[p]] = static_cast<int32_t>(state.particle_materials.size());
    with_particle_parameters(state, P.properties.data() + p * width, [&](auto model, const SharedParameters& shared,
                                                                         const auto& own) {
      using Model = decltype(model);
      state.particle_materials.push_back(
          {PreparedMaterial(std::in_place_type<typename Model::Prepared>, Model::prepare(shared, own, state.context)),
           shared.shear_modulus(), shared.bulk_modulus(), pore_stiffness(state, shared)});
    });
  }
}

double elastic_energy_density(double shear_modulus, double bulk_modulus, const Vec4& sigma) {
  const double p = (sigma[0] + sigma[1] + sigma[2]) / 3;
  const double sxx = sigma[0] - p, syy = sigma[1] - p, szz = sigma[2] - p;
  const double s_s = sxx * sxx + syy * syy + szz * szz + 2 * sigma[3] * sigma[3];
  return s_s / (4 * shear_modulus) + p * p / (2 * bulk_modulus);
}

}  // namespace talus::solver
