#include "common/fingerprint.hpp"

#include <fstream>

namespace talus {

bool Fingerprint::add_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    add(buffer, static_cast<std::size_t>(in.gcount()));
    if (!in) break;
  }
  return true;
}

}  // namespace talus
