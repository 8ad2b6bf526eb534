#include "workflow/stamps.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common/atomic_file.hpp"

namespace talus::stamps {
namespace {

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

uint64_t hash(const std::string& text, uint64_t seed) { return Fingerprint(seed).add(text).value(); }

uint64_t hash_file(const std::string& path, uint64_t seed) {
  Fingerprint f(seed);
  if (!f.add_file(path)) return hash("missing:" + path, seed);
  return f.value();
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
  write_stream_atomically(stamp_path(folder), [&](std::ostream& out) {
    for (const auto& [name, value] : stamps) out << name << " " << std::hex << value << "\n";
  });
}

void forget(const std::string& folder) {
  std::error_code ignored;
  std::filesystem::remove(stamp_path(folder), ignored);
}

}  // namespace talus::stamps
