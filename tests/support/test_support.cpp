#include "support/test_support.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

#include "common/h5.hpp"

namespace talus::testing {

ScratchDir::ScratchDir(const std::string& tag) {
  std::random_device random;
  path_ = std::filesystem::temp_directory_path() /
          ("talus-test-" + tag + "-" + std::to_string(random()) + std::to_string(random()));
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

CommandResult run_shell(const std::string& command) {
  CommandResult result;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  while (std::fgets(buffer.data(), buffer.size(), pipe)) result.output += buffer.data();
  const int raw = pclose(pipe);
  if (WIFEXITED(raw)) result.status = WEXITSTATUS(raw);
  else if (WIFSIGNALED(raw)) result.status = 128 + WTERMSIG(raw);
  return result;
}

CommandResult run_talus(const std::string& args) { return run_shell(std::string(TALUS_BINARY) + " " + args); }

const std::string& talus_version() {
  static const std::string text = run_talus("--version").output;
  return text;
}

double frame_difference(const std::string& a, const std::string& b, std::string& worst) {
  const h5::File x_file = h5::File::open_read(a), y_file = h5::File::open_read(b);
  double largest = 0;
  for (const std::string& dataset : h5::list(x_file, "frames")) {
    const std::string name = "frames/" + dataset;
    const auto x = h5::read_doubles(x_file, name);
    const auto y = h5::read_doubles(y_file, name);
    if (x.size() != y.size()) {
      worst = name + ": " + std::to_string(x.size()) + " against " + std::to_string(y.size()) + " values";
      return HUGE_VAL;
    }
    double scale = 0, difference = 0;
    for (std::size_t k = 0; k < x.size(); ++k) {
      scale = std::max(scale, std::abs(x[k]));
      difference = std::max(difference, std::abs(x[k] - y[k]));
    }
    const double relative = scale > 0 ? difference / scale : difference;
    if (relative >= largest) {
      largest = relative;
      worst = name;
    }
  }
  return largest;
}

std::string source_path(const std::string& relative) { return std::string(TALUS_SOURCE_DIR) + "/" + relative; }

std::string stacked_rectangles_geo(double w, double b, double t, double lc, const std::string& groups) {
  std::ostringstream geo;
  geo.precision(17);
  const std::string size = lc > 0 ? ", lc" : "";
  if (lc > 0) geo << "lc = " << lc << ";\n";
  const double corners[6][2] = {{0, 0}, {w, 0}, {w, b}, {0, b}, {w, t}, {0, t}};
  for (int k = 0; k < 6; ++k) geo << "Point(" << k + 1 << ") = {" << corners[k][0] << ", " << corners[k][1] << ", 0" << size << "};\n";
  geo << R"(Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {3, 5};
Line(6) = {5, 6};
Line(7) = {6, 4};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7};
Plane Surface(2) = {2};
Physical Surface("domain") = {1, 2};
Physical Curve("left") = {4, 7};
Physical Curve("right") = {2, 5};
)" << groups;
  return geo.str();
}

namespace {

// Element neighbours from shared edges: the edge opposite local vertex k joins the other two.
void fill_neighbours(Model& model) {
  std::map<std::pair<int, int>, std::pair<int, int>> edge_owner;
  model.neighbours.assign(model.triangles.size(), {-1, -1, -1});
  for (int e = 0; e < static_cast<int>(model.triangles.size()); ++e)
    for (int k = 0; k < 3; ++k) {
      int a = model.triangles[e][(k + 1) % 3], b = model.triangles[e][(k + 2) % 3];
      auto key = std::minmax(a, b);
      auto found = edge_owner.find(key);
      if (found == edge_owner.end()) {
        edge_owner[key] = {e, k};
      } else {
        model.neighbours[e][k] = found->second.first;
        model.neighbours[found->second.first][found->second.second] = e;
      }
    }
}

// The rectangle's corner nodes, row by row, and its four sides as node sets.
Model rectangle_corners(double x0, double y0, int nx, int ny, double h) {
  Model model;
  model.scene_name = "rectangle";
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) model.nodes.emplace_back(x0 + i * h, y0 + j * h);
  auto node = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int i = 0; i <= nx; ++i) {
    model.node_sets["bottom"].push_back(node(i, 0));
    model.node_sets["top"].push_back(node(i, ny));
  }
  for (int j = 0; j <= ny; ++j) {
    model.node_sets["left"].push_back(node(0, j));
    model.node_sets["right"].push_back(node(nx, j));
  }
  return model;
}

}  // namespace

Model rectangle_mesh(double x0, double y0, int nx, int ny, double h) {
  Model model = rectangle_corners(x0, y0, nx, ny, h);
  auto node = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      model.triangles.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1)});
      model.triangles.push_back({node(i, j), node(i + 1, j + 1), node(i, j + 1)});
    }
  fill_neighbours(model);
  return model;
}

Model crossed_rectangle_mesh(double x0, double y0, int nx, int ny, double h) {
  Model model = rectangle_corners(x0, y0, nx, ny, h);
  auto node = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int32_t centre = static_cast<int32_t>(model.nodes.size());
      model.nodes.emplace_back(x0 + (i + 0.5) * h, y0 + (j + 0.5) * h);
      const int32_t corner[4] = {node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)};
      for (int k = 0; k < 4; ++k) model.triangles.push_back({corner[k], corner[(k + 1) % 4], centre});
    }
  fill_neighbours(model);
  return model;
}

namespace {

// Registers a body of `material` described by `info` and seeds it at the four-point barycentric
// positions of the mesh's triangles, each with a quarter of the triangle's area; `keep(centroid,
// point)` says which of them belong to the body. Returns the body's index.
template <class Keep>
int add_seeded_body(Model& model, BodyInfo info, const Material& material, Keep keep,
                    Seeding seeding = Seeding::FourPoints) {
  const int body = static_cast<int>(model.bodies.size());
  model.materials.push_back(material);
  model.materials.back().name = info.name + "_material";
  info.material = static_cast<int>(model.materials.size()) - 1;
  model.bodies.push_back(info);
  // Four equal-weight interior points: the centroid and the three permutations of (1/2, 1/4, 1/4),
  // or of (2/3, 1/6, 1/6) (the sub-triangles' centroids).
  const double major = seeding == Seeding::FourPoints ? 0.5 : 2.0 / 3, minor = (1 - major) / 2;
  const double rule[4][3] = {
      {1.0 / 3, 1.0 / 3, 1.0 / 3}, {major, minor, minor}, {minor, major, minor}, {minor, minor, major}};
  for (std::size_t e = 0; e < model.triangles.size(); ++e) {
    const auto& t = model.triangles[e];
    const Eigen::Vector2d a = model.nodes[t[0]], b = model.nodes[t[1]], c = model.nodes[t[2]];
    const Eigen::Vector2d centroid = (a + b + c) / 3;
    const double area = 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
    for (const auto& w : rule) {
      const Eigen::Vector2d x = w[0] * a + w[1] * b + w[2] * c;
      if (!keep(centroid, x)) continue;
      model.position.push_back(x);
      model.velocity.push_back(Eigen::Vector2d::Zero());
      model.volume.push_back(area / 4);
      model.mass.push_back(material.density * area / 4);
      model.stress.push_back(Eigen::Vector4d::Zero());
      model.body.push_back(body);
      model.element.push_back(static_cast<int32_t>(e));
    }
  }
  return body;
}

}  // namespace

int add_box_body(Model& model, const std::string& name, const Material& material, double x0, double x1, double y0,
                 double y1, bool fixed, Seeding seeding) {
  BodyInfo info;
  info.name = name;
  info.fixed = fixed;
  info.loops = {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
  return add_seeded_body(model, info, material, [&](const Eigen::Vector2d& centroid, const Eigen::Vector2d&) {
    return centroid.x() >= x0 && centroid.x() <= x1 && centroid.y() >= y0 && centroid.y() <= y1;
  }, seeding);
}

int add_disc_body(Model& model, const std::string& name, const Material& material, const Eigen::Vector2d& centre,
                  double radius) {
  BodyInfo info;
  info.name = name;
  constexpr int kSides = 64;  // outline only: the particles follow the circle itself
  info.loops.emplace_back();
  for (int k = 0; k < kSides; ++k) {
    const double angle = 2 * M_PI * k / kSides;
    info.loops.back().push_back(centre + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
  }
  return add_seeded_body(model, info, material, [&](const Eigen::Vector2d&, const Eigen::Vector2d& x) {
    return (x - centre).norm() <= radius;
  });
}

void fix_base_roll_sides(Model& model, const char* fixed) {
  model.fixed_nodes = model.node_sets[fixed];
  for (const char* side : {"left", "right"})
    for (int32_t i : model.node_sets[side]) {
      model.roller_nodes.push_back(i);
      model.roller_normals.push_back(Eigen::Vector2d(1, 0));
    }
}

Material elastic(double density, double youngs_modulus, double poisson_ratio) {
  Material m;  // linear elastic, the default model
  m.density = density;
  m.youngs_modulus = youngs_modulus;
  m.poisson_ratio = poisson_ratio;
  return m;
}

ColumnDeposit column_deposit(const std::vector<Eigen::Vector2d>& positions, double bin) {
  std::vector<bool> occupied;
  for (const auto& x : positions) {
    const std::size_t k = static_cast<std::size_t>(std::max(0.0, x.x()) / bin);
    if (k >= occupied.size()) occupied.resize(k + 1, false);
    occupied[k] = true;
  }
  const std::size_t gap = std::find(occupied.begin(), occupied.end(), false) - occupied.begin();
  ColumnDeposit deposit;
  for (const auto& x : positions) {
    if (static_cast<std::size_t>(std::max(0.0, x.x()) / bin) >= gap) {
      ++deposit.detached;
      continue;
    }
    deposit.tip = std::max(deposit.tip, x.x());
    deposit.height = std::max(deposit.height, x.y());
  }
  return deposit;
}

std::optional<double> lube_runout(double a) {
  if (a < 1.8) return 1.2 * a;
  if (a > 2.8) return 1.9 * std::pow(a, 2.0 / 3.0);
  return std::nullopt;
}

Material mohr_coulomb(double density, double youngs_modulus, double poisson_ratio, double friction_angle,
                      double cohesion) {
  Material m = elastic(density, youngs_modulus, poisson_ratio);
  MohrCoulomb::Parameters own;
  own.friction_angle = friction_angle;
  own.cohesion = cohesion;
  m.model = own;
  return m;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

double json_number(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\":";
  const std::size_t at = json.find(tag);
  if (at == std::string::npos) return std::nan("");
  const char* value = json.c_str() + at + tag.size();
  char* end = nullptr;
  const double parsed = std::strtod(value, &end);
  return end == value ? std::nan("") : parsed;  // null, or not a number
}

void set_run(Model& model, double end_time, Eigen::Vector2d gravity) {
  model.run.end_time = end_time;
  model.run.cfl = 0.5;
  model.run.output_interval = end_time;
  model.run.gravity = gravity;
  model.run.history_interval = 10;
}

}  // namespace talus::testing
