#include "common/error.hpp"

namespace talus {

std::string located(const std::string& file, const std::string& item, const std::string& message) {
  std::string out;
  if (!file.empty()) out += file + ": ";
  if (!item.empty()) out += item + ": ";
  return out + message;
}

}  // namespace talus
