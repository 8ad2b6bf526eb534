// Writing a file whole or not at all. The content goes to a temporary file beside the target
// (PATH.tmp, in the same folder, so on the same file system), which then replaces PATH by one
// rename: a reader sees the old file or the new one, never half of one. On any failure the
// temporary file is removed, PATH is left as it was, and the error passes on (a talus::Error
// naming the file for the failures seen here: opening, writing, closing, renaming).
#pragma once
#include <functional>
#include <ostream>
#include <string>

namespace talus {

// `fill` writes the whole file at `temporary_path`, by any means (HDF5, a stream), and throws
// when it cannot; then the temporary file replaces `path`.
void write_atomically(const std::string& path, const std::function<void(const std::string& temporary_path)>& fill);

// The same for a file written through a stream: `fill` writes to `out` (the temporary file,
// opened in binary mode); the opening, the writes and the close are checked.
void write_stream_atomically(const std::string& path, const std::function<void(std::ostream& out)>& fill);

// A file holding exactly `content`.
void write_text_atomically(const std::string& path, const std::string& content);

}  // namespace talus
