#include "common/error.hpp"

#include <cstdio>

namespace talus {

std::string escaped(const std::string& text) {
  std::string out;
  for (const unsigned char c : text) {
    if (c >= 0x20 && c != 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    }
  }
  return out;
}

std::string located(const std::string& file, const std::string& item, const std::string& message) {
  std::string out;
  // The file and the item come from input (a path, a physical group's name).
  if (!file.empty()) out += escaped(file) + ": ";
  if (!item.empty()) out += escaped(item) + ": ";
  return out + message;
}

}  // namespace talus
