#include "workflow/stamps.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace talus::stamps {
namespace {

constexpr uint64_t kPrime = 1099511628211ull;

std::string stamp_path(const std::string& folder) {
  return (std::filesystem::path(folder) / ".talus-stamps").string();
}

std::map<std::string, uint64_t> read_all(const std::string& folder) {
  std::map<std::string, uint64_t> stamps;
  std::ifstream in(stamp_path(folder));
  std::string stage;
  uint64_t value;
  while (in >> stage >> std::hex >> value) stamps[stage] = value;
  return stamps;
}

}  // namespace

uint64_t hash(const std::string& text, uint64_t seed) {
  uint64_t h = seed;
  for (unsigned char c : text) h = (h ^ c) * kPrime;
  return h;
}

uint64_t hash_file(const std::string& path, uint64_t seed) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return hash("missing:" + path, seed);
  uint64_t h = seed;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ static_cast<unsigned char>(buffer[i])) * kPrime;
    if (!in) break;
  }
  return h;
}

uint64_t program() {
  static const uint64_t value = hash_file("/proc/self/exe");
  return value;
}

uint64_t recorded(const std::string& folder, const std::string& stage) {
  const auto stamps = read_all(folder);
  const auto found = stamps.find(stage);
  return found == stamps.end() ? 0 : found->second;
}

void record(const std::string& folder, const std::string& stage, uint64_t fingerprint) {
  auto stamps = read_all(folder);
  stamps[stage] = fingerprint;
  const std::string temporary = stamp_path(folder) + ".tmp";
  {
    std::ofstream out(temporary);
    for (const auto& [name, value] : stamps) out << name << " " << std::hex << value << "\n";
  }
  std::filesystem::rename(temporary, stamp_path(folder));
}

void forget(const std::string& folder) {
  std::error_code ignored;
  std::filesystem::remove(stamp_path(folder), ignored);
}

}  // namespace talus::stamps
