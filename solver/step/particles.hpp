// The particles: a struct of arrays whose fields are declared once, in TALUS_PARTICLE_FIELDS.
// That one line per field gives its type, name, unit and roles; re-ordering (sort), the
// checkpoint and results.h5 with its XDMF all visit the list, so adding a field is one line
// here plus its physics. A field may be left empty (size 0) when a scene does not need it:
// every visitor skips it, so an unused field costs neither memory nor time.
#pragma once
#include <cstdint>
#include <string_view>
#include <vector>

#include "solver/interpolation/mesh.hpp"

namespace talus::solver {

// What happens to a field besides the physics that uses it.
enum FieldRole : unsigned {
  kCheckpointed = 1u << 0,  // saved in checkpoint.h5, read back by --restart
  kWritten = 1u << 1,       // a frame dataset of results.h5 (frames/<results name>) and an XDMF attribute
};

// FIELD(type, member, results name, unit, roles). Every field is re-ordered with the particles.
// `history` holds the materials' per-particle state variables (MaterialState::history_width
// values per particle, the widest material's), empty when no material keeps any; `properties`
// the particle's own values of its material's parameters (material_state.hpp,
// particle_properties: as many per particle as the material with most has), empty without any.
#define TALUS_PARTICLE_FIELDS(FIELD)                                             \
  FIELD(Vec2, x, "position", "m", kCheckpointed | kWritten)                      \
  FIELD(Vec2, v, "", "m/s", kCheckpointed)                                       \
  FIELD(double, m, "", "kg/m", kCheckpointed)                                    \
  FIELD(double, volume, "volume", "m^2", kCheckpointed | kWritten)               \
  FIELD(Vec4, sigma, "stress", "Pa", kCheckpointed | kWritten)                   \
  FIELD(double, eps_p, "plastic_strain", "-", kCheckpointed | kWritten)          \
  FIELD(double, history, "", "-", kCheckpointed)                                 \
  FIELD(double, properties, "", "-", kCheckpointed)                              \
  FIELD(double, pore_pressure, "pore_pressure", "Pa", kCheckpointed | kWritten)  \
  FIELD(double, excess_pore_pressure, "", "Pa", kCheckpointed)                   \
  FIELD(Vec4, C, "", "1/s", kCheckpointed)                                       \
  FIELD(Vec2, domain, "", "m", kCheckpointed)                                    \
  FIELD(int32_t, body, "", "-", kCheckpointed)                                   \
  FIELD(int32_t, element, "", "-", kCheckpointed)                                \
  FIELD(int32_t, id, "", "-", kCheckpointed)                                     \
  FIELD(int32_t, load, "", "-", kCheckpointed)                                   \
  FIELD(Vec2, load_force, "", "N/m", kCheckpointed)                             \
  FIELD(Vec2, step_velocity, "", "m/s", 0)

// Declaration of one field as the visitors see it.
struct FieldInfo {
  const char* name;          // the member's name: x, sigma, ...
  const char* results_name;  // frames/<results_name> in results.h5 ("" when not written)
  const char* unit;
  unsigned roles;
};

// x position (m), v velocity (m/s), m mass (kg/m), volume (m^2 per m thickness), sigma Cauchy
// stress (Pa), eps_p equivalent plastic shear strain, C APIC's affine velocity matrix
// C_ab = dv_a / dx_b as (xx, xy, yx, yy) (empty unless the transfer is APIC), domain the three
// corners of the particle's domain (m; empty unless the shape functions are CPDI), body and element
// indices, id the index in the model's (and the results') order, load the surface load the
// particle carries (-1: none) and load_force its force at full load (both empty without loads);
// step_velocity the grid velocity that moved the particle in the last step, sum S_ip v_i with
// that step's stencil (A.12), kept only at a step that ends on a frame (Scratch::keep_step_velocity)
// so that it travels with a particle that changes rank, empty otherwise.
// With a water table, pore_pressure u (Pa, positive in compression) and, undrained, its excess
// over the hydrostatic part; sigma is then the TOTAL stress and the effective stress is
// sigma + u (1, 1, 1, 0) (docs/water.md). Both are empty without water. Particles of fixed bodies are kept after all the
// others (indices [moving_count, size)), so the update loops run over [0, moving_count) only.
struct Particles {
#define TALUS_DECLARE_FIELD(type, member, results_name, unit, roles) std::vector<type> member;
  TALUS_PARTICLE_FIELDS(TALUS_DECLARE_FIELD)
#undef TALUS_DECLARE_FIELD
  std::size_t moving_count = 0;
  int history_width = 0;  // values of `history` per particle

  std::size_t size() const { return x.size(); }

  // Calls visit(info, column) for every field, in declaration order.
  template <class Visit>
  void for_each_field(Visit&& visit) {
#define TALUS_VISIT_FIELD(type, member, results_name, unit, roles) visit(FieldInfo{#member, results_name, unit, roles}, member);
    TALUS_PARTICLE_FIELDS(TALUS_VISIT_FIELD)
  }
  template <class Visit>
  void for_each_field(Visit&& visit) const {
    TALUS_PARTICLE_FIELDS(TALUS_VISIT_FIELD)
#undef TALUS_VISIT_FIELD
  }
  // Calls visit(info, column, other_column) for every field of this and `other`, in
  // declaration order (copying particles between two sets).
  template <class Visit>
  void for_each_field_with(const Particles& other, Visit&& visit) {
#define TALUS_VISIT_PAIR(type, member, results_name, unit, roles) \
  visit(FieldInfo{#member, results_name, unit, roles}, member, other.member);
    TALUS_PARTICLE_FIELDS(TALUS_VISIT_PAIR)
#undef TALUS_VISIT_PAIR
  }
};

// Whether a simulation fills a written field, so that results.h5 has its frames: the pore
// pressure only with a water table (`water`); every other written field always.
inline bool field_written(const FieldInfo& field, bool water) {
  return (field.roles & kWritten) && (water || std::string_view(field.name) != "pore_pressure");
}

// The effective stress of particle p: sigma + u (1, 1, 1, 0) with water, sigma without.
inline Vec4 effective_stress(const Particles& P, std::size_t p) {
  if (P.pore_pressure.empty()) return P.sigma[p];
  const double u = P.pore_pressure[p];
  return P.sigma[p] + Vec4(u, u, u, 0);
}

// Values per particle of a column (0 for an unused field).
template <class T>
std::size_t width_of(const std::vector<T>& column, std::size_t particles) {
  return particles == 0 ? 0 : column.size() / particles;
}

// Re-orders every field so that particle k becomes old particle order[k].
void permute_particles(Particles& particles, const std::vector<int32_t>& order);

}  // namespace talus::solver
