// A material as the solver holds it: its model's state prepared once from the parameters
// (common/materials/materials.hpp), what the time step and the water need of it, and its
// per-particle properties. The stress loop (stress.cpp) dispatches on the prepared state's model
// with no virtual call.
#pragma once
#include <optional>
#include <vector>

#include "common/materials/materials.hpp"
#include "solver/interpolation/mesh.hpp"
#include "solver/step/particles.hpp"

namespace talus {
struct Model;
}

namespace talus::solver {

struct Config;  // simulation.hpp

// A particle's own state, for a material with per-particle properties: what MaterialState holds
// for the material, from the material's parameters with the particle's values.
struct ParticleMaterial {
  PreparedMaterial prepared;
  double shear_modulus = 0, bulk_modulus = 0, pore_stiffness = 0;
};

struct MaterialState {
  PreparedMaterial prepared;  // from the material's parameters, its strength divided by `reduction`
  double density = 0;
  double shear_modulus = 0, bulk_modulus = 0;  // G, K: plane strain uses the 3D moduli
  // c_d = sqrt((K + 4G/3) / rho), with the undrained pore stiffness; with per-particle
  // properties, the fastest of the material's and its particles' (the time step's bound).
  double wave_speed = 0;
  // Undrained water: the pore water's stiffness over the porosity, K_w / n (Pa); 0 otherwise.
  double pore_stiffness = 0;
  // State variables per particle in Particles::history (Mohr-Coulomb's softening: 1).
  int history_width = 0;

  // What preparing the state again needs (strength reduction, particles with properties).
  Material material;
  PrepareContext context;
  std::optional<double> reduction;  // the strength-reduction factor; none: the scene's strength
  double water_bulk_modulus = 0;    // K_w when undrained, else 0

  // Per-particle properties (empty: none): where particle p's k-th value,
  // Particles::properties[p * width + k] (width: the widest material's count), goes in the
  // material's parameters.
  std::vector<ParameterSlot> property_slots;
  bool elastic_columns = false;  // youngs_modulus or poisson_ratio is among them
  // Its particles' own states, prepared once (prepare_particle_materials), not every step: the
  // row of particle id i is row_of_id[i] (-1: a particle of another material).
  std::vector<int32_t> row_of_id;
  std::vector<ParticleMaterial> particle_materials;
  const ParticleMaterial& of_particle(int32_t id) const { return particle_materials[row_of_id[id]]; }
};

// The state of a material alone: no mesh (no softening regularisation), no water.
MaterialState make_material(const Material& material);

// Every material's state once the mesh and the water are in `config` (make_simulation): the
// softening strains' element-size regularisation, the undrained pore stiffness and wave speed,
// and the per-particle properties' slots (with the wave speed and history width over the
// particles' own values). Throws talus::Error on a bad material or property.
void prepare_materials(Config& config, const Model& model);

// Particles::properties in model order: particle p's values of its material's properties, in
// the order of its property_slots, `width` (the most any material has) per particle, 0 in the
// slots its material does not use. Empty without properties.
std::vector<double> particle_properties(const Model& model, const Config& config);

// The strength of a material with one (has_strength) divided by `factor` (strength reduction,
// solver/strength_reduction.cpp). Its particles' own states follow with
// prepare_particle_materials.
void reduce_strength(MaterialState& state, double factor);

// The particle states of every material with per-particle properties, from the particles' values
// (Particles::properties, their source) with the material's strength reduction: at set-up, with
// every particle (on several ranks too: make_simulation builds the whole simulation first), and
// after strength reduction. Preparing them once instead of every step saves what the stress
// update of such a particle would cost again each step (docs/architecture.md, "Materials").
void prepare_particle_materials(std::vector<MaterialState>& materials, const std::vector<int32_t>& material_of_body,
                                const Particles& P);

// Elastic energy density of a stress state, (s:s)/(4G) + p^2/(2K) with the 3D mean stress p, with
// the material's moduli or a particle's own.
double elastic_energy_density(double shear_modulus, double bulk_modulus, const Vec4& sigma);
inline double elastic_energy_density(const MaterialState& material, const Vec4& sigma) {
  return elastic_energy_density(material.shear_modulus, material.bulk_modulus, sigma);
}

}  // namespace talus::solver
