// User-facing errors. Every bad input becomes one talus::Error whose message names the file,
// the item and what was expected; the driver prints it once and exits with status 1.
#pragma once
#include <stdexcept>
#include <string>

namespace talus {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "file: item: message", leaving out the parts that are empty.
std::string located(const std::string& file, const std::string& item, const std::string& message);

}  // namespace talus
