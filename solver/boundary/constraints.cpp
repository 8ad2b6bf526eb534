// The per-node constraints of a model's boundaries (boundary.hpp).
#include "solver/boundary/boundary.hpp"

namespace talus::solver {

Constraints build_constraints(const Model& model) {
  Constraints c;
  c.kind.assign(model.nodes.size(), Constraint::Free);
  c.normal.assign(model.nodes.size(), Vec2::Zero());
  c.friction.assign(model.nodes.size(), 0.0);
  for (std::size_t k = 0; k < model.roller_nodes.size(); ++k) {
    c.kind[model.roller_nodes[k]] = Constraint::Roller;
    c.normal[model.roller_nodes[k]] = model.roller_normals[k].normalized();
  }
  for (std::size_t k = 0; k < model.friction_nodes.size(); ++k) {
    const int32_t i = model.friction_nodes[k];
    c.kind[i] = Constraint::Friction;
    c.normal[i] = model.friction_normals[k].normalized();
    c.friction[i] = model.friction_coefficients[k];
  }
  for (int32_t i : model.fixed_nodes) c.kind[i] = Constraint::Fixed;
  return c;
}

}  // namespace talus::solver
