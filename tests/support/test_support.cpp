#include "support/test_support.hpp"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <map>
#include <random>

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

std::string source_path(const std::string& relative) { return std::string(TALUS_SOURCE_DIR) + "/" + relative; }

Model rectangle_mesh(double x0, double y0, int nx, int ny, double h) {
  Model model;
  model.scene_name = "rectangle";
  auto node = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) model.nodes.emplace_back(x0 + i * h, y0 + j * h);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      model.triangles.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1)});
      model.triangles.push_back({node(i, j), node(i + 1, j + 1), node(i, j + 1)});
    }
  // Neighbours from shared edges: the edge opposite local vertex k joins the other two.
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

}  // namespace talus::testing
