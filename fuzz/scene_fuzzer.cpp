// libFuzzer target over the scene parser: the input as a whole scene file, then as the value
// and as the key of a --set override on a valid scene. Bad input must end in talus::Error:
// any other exception, crash, sanitizer report or leak is a finding.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.hpp"
#include "common/scene/scene.hpp"

namespace {

std::string scratch(const char* name) {
  return (std::filesystem::temp_directory_path() / ("talus-fuzz-" + std::to_string(getpid()) + "-" + name)).string();
}

void try_load(const std::string& path, const std::vector<std::string>& overrides = {}) {
  try {
    talus::load_scene(path, overrides);
  } catch (const talus::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string input_path = scratch("input.toml");
  static const std::string base_path = [] {
    const std::string path = scratch("base.toml");
    std::ofstream(path) << "[run]\nend_time = 1.0\n[materials.rock]\nmodel = \"linear_elastic\"\ndensity = 2000.0\n"
                           "youngs_modulus = 1e7\npoisson_ratio = 0.25\n[bodies.block]\nmaterial = \"rock\"\n";
    return path;
  }();
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::ofstream(input_path, std::ios::binary | std::ios::trunc) << text;
  try_load(input_path);
  try_load(base_path, {"run.end_time=" + text});
  try_load(base_path, {text + "=1"});
  return 0;
}
