#include "common/atomic_file.hpp"

#include <filesystem>
#include <fstream>

#include "common/error.hpp"

namespace talus {

void write_atomically(const std::string& path, const std::function<void(const std::string& temporary_path)>& fill) {
  const std::string temporary = path + ".tmp";
  try {
    fill(temporary);
    std::error_code error;
    std::filesystem::rename(temporary, path, error);
    if (error) throw Error(located(path, "", "cannot replace with " + temporary + ": " + error.message()));
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void write_stream_atomically(const std::string& path, const std::function<void(std::ostream& out)>& fill) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(located(temporary, "", "cannot open for writing"));
    fill(out);
    out.flush();
    if (!out) throw Error(located(temporary, "", "write failed (disk full?)"));
    out.close();
    if (!out) throw Error(located(temporary, "", "close failed (disk full?)"));
  });
}

void write_text_atomically(const std::string& path, const std::string& content) {
  write_stream_atomically(path, [&](std::ostream& out) { out << content; });
}

}  // namespace talus
