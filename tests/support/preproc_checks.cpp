#include "support/preproc_checks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>

#include "common/geometry.hpp"

namespace talus::testing {

double twice_signed_area(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

Eigen::Vector3d barycentric(const Model& model, int32_t e, const Eigen::Vector2d& p) {
  const auto& t = model.triangles[e];
  const Eigen::Vector2d a = model.nodes[t[0]], b = model.nodes[t[1]], c = model.nodes[t[2]];
  const double whole = twice_signed_area(a, b, c);
  return {twice_signed_area(p, b, c) / whole, twice_signed_area(a, p, c) / whole, twice_signed_area(a, b, p) / whole};
}

double triangle_area(const Model& model, int32_t e) {
  const auto& t = model.triangles[e];
  return 0.5 * twice_signed_area(model.nodes[t[0]], model.nodes[t[1]], model.nodes[t[2]]);
}

int body_of(const Model& model, const std::string& name) {
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].name == name) return static_cast<int>(b);
  ADD_FAILURE() << "no body " << name;
  return -1;
}

void expect_valid_mesh(const Model& model) {
  std::vector<bool> used(model.nodes.size(), false);
  for (std::size_t e = 0; e < model.triangles.size(); ++e) {
    EXPECT_GT(triangle_area(model, static_cast<int32_t>(e)), 0) << "triangle " << e << " is not counter-clockwise";
    for (int32_t v : model.triangles[e]) used[v] = true;
    for (int k = 0; k < 3; ++k) {
      const int32_t n = model.neighbours[e][k];
      if (n < 0) continue;
      // The neighbour across the edge opposite vertex k lists e back, across the same edge.
      const auto& back = model.neighbours[n];
      const int kb = static_cast<int>(std::find(back.begin(), back.end(), static_cast<int32_t>(e)) - back.begin());
      ASSERT_LT(kb, 3) << "neighbours of " << e << " and " << n << " are not symmetric";
      const std::set<int32_t> edge{model.triangles[e][(k + 1) % 3], model.triangles[e][(k + 2) % 3]};
      const std::set<int32_t> edge_back{model.triangles[n][(kb + 1) % 3], model.triangles[n][(kb + 2) % 3]};
      EXPECT_EQ(edge, edge_back);
    }
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "node ids are not compact";
}

void expect_valid_particles(const Model& model, const Scene& scene) {
  ASSERT_EQ(model.bodies.size(), scene.bodies.size());
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    const int b = model.body[p];
    const BodyInfo& body = model.bodies[b];
    ASSERT_TRUE(inside_loops(body.loops, model.position[p])) << "particle " << p << " outside body " << body.name;
    const Eigen::Vector3d w = barycentric(model, model.element[p], model.position[p]);
    ASSERT_GT(w.minCoeff(), 0) << "particle " << p << " outside its element " << model.element[p];
    const double density = model.materials[body.material].density;
    ASSERT_NEAR(model.mass[p], density * model.volume[p], 1e-12 * model.mass[p]);
    const int ppc = scene.bodies[scene.body_index(body.name)].particles_per_cell;
    ASSERT_NEAR(model.volume[p], triangle_area(model, model.element[p]) / ppc, 1e-12 * model.volume[p]);
  }
}

std::map<std::string, double> volume_per_body(const Model& model) {
  std::map<std::string, double> volume;
  for (std::size_t p = 0; p < model.particle_count(); ++p) volume[model.bodies[model.body[p]].name] += model.volume[p];
  return volume;
}

Meshed mesh_scene(const std::string& name, const std::vector<std::string>& overrides) {
  Meshed m;
  m.scene = load_scene(testing::source_path("geometries/" + name + ".toml"), overrides);
  m.model = preproc::build_model(m.scene, &m.report);
  return m;
}

std::string write_file(const ScratchDir& dir, const std::string& name, const std::string& text) {
  std::ofstream(dir.file(name)) << text;
  return dir.file(name);
}

Body rock_body(const std::string& name, const std::string& group, int particles_per_cell) {
  Body body;
  body.name = name;
  body.group = group;
  body.material = "rock";
  body.particles_per_cell = particles_per_cell;
  return body;
}

Scene rock_scene(const std::string& name, const std::string& path, const std::string& geometry,
                 std::optional<double> size, std::vector<Body> bodies) {
  Scene scene;
  scene.name = name;
  scene.path = path;
  scene.geometry = geometry;
  scene.mesh.size = size;
  Material rock;
  rock.name = "rock";
  rock.density = 2000;
  rock.youngs_modulus = 1e7;
  rock.poisson_ratio = 0.25;
  scene.materials = {rock};
  scene.bodies = std::move(bodies);
  scene.post.body = scene.bodies.front().name;
  return scene;
}

}  // namespace talus::testing
