// libFuzzer target over the model reader: the input written as a .h5 file and read with
// read_model. Anything but a Talus model must end in talus::Error: any other exception, crash,
// sanitizer report or leak is a finding. (The HDF5 C library itself is not instrumented.)
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/error.hpp"
#include "common/model/model.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path =
      (std::filesystem::temp_directory_path() / ("talus-fuzz-" + std::to_string(getpid()) + "-model.h5")).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), size);
  try {
    talus::read_model(path);
  } catch (const talus::Error&) {
  }
  return 0;
}
