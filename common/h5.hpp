// A small RAII layer over the HDF5 C API: files, groups, contiguous datasets of doubles, ints
// and strings, scalar and vector attributes, and appendable (chunked) datasets for frames.
// One dataset per field, row-major, no compound types. Errors throw talus::Error naming the
// file and the dataset.
#pragma once
#include <hdf5.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace talus::h5 {

// Throws std::bad_alloc when the HDF5 call that just failed ran out of memory (its error stack
// says so), else talus::Error(message). Clears the stack.
[[noreturn]] void throw_failure(const std::string& message);

using Dims = std::vector<hsize_t>;

// Owns one HDF5 identifier and closes it with the right function.
class Handle {
 public:
  Handle() = default;
  explicit Handle(hid_t id) : id_(id) {}
  Handle(Handle&& other) noexcept : id_(other.id_) { other.id_ = -1; }
  Handle& operator=(Handle&& other) noexcept;
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { reset(); }
  hid_t id() const { return id_; }
  bool valid() const { return id_ >= 0; }
  void reset();
  hid_t release() {  // gives up ownership without closing
    const hid_t id = id_;
    id_ = -1;
    return id;
  }

 private:
  hid_t id_ = -1;
};

class File {
 public:
  static File create(const std::string& path);     // truncates an existing file
  static File open_read(const std::string& path);  // error if missing or not HDF5
  static File open_write(const std::string& path);
  hid_t id() const { return handle_.id(); }
  const std::string& path() const { return path_; }
  void flush() const;
  void close();  // throws talus::Error when HDF5 cannot finish the file

 private:
  Handle handle_;
  std::string path_;
};

// Creates PATH.tmp, lets `fill` write it, closes it and renames it to PATH, by
// talus::write_atomically (common/atomic_file.hpp): on any error the temporary file is removed
// and the error passes on. A reader never sees half a file.
void write_atomically(const std::string& path, const std::function<void(const File&)>& fill);

// Datasets are addressed by a path relative to the file root ("mesh/nodes"); intermediate
// groups are created on write.
bool exists(const File& file, const std::string& path);
Dims shape(const File& file, const std::string& path);

void write(const File& file, const std::string& path, const std::vector<double>& data, const Dims& dims);
void write(const File& file, const std::string& path, const std::vector<int32_t>& data, const Dims& dims);
void write(const File& file, const std::string& path, const std::vector<std::string>& data);

std::vector<double> read_doubles(const File& file, const std::string& path, Dims* dims = nullptr);
std::vector<int32_t> read_ints(const File& file, const std::string& path, Dims* dims = nullptr);
// Rows [first, first + count) of a dataset of doubles along its first axis (all of every other
// axis), row-major. Throws talus::Error when the dataset is missing or has fewer rows.
std::vector<double> read_double_rows(const File& file, const std::string& path, hsize_t first, hsize_t count);
std::vector<std::string> read_strings(const File& file, const std::string& path);

// Selects the block `count` at `start` of the dataspace `file_space` and returns a memory
// dataspace of that shape, the pair H5Dread and H5Dwrite take for the block; a count of 0 on any
// axis selects nothing in either (a collective write in which this rank has no rows).
Handle select_block(hid_t file_space, const Dims& start, const Dims& count);

// Names of the members of a group, in creation-independent (alphabetical) order.
std::vector<std::string> list(const File& file, const std::string& group_path);
void create_group(const File& file, const std::string& path);

// Attributes on the object at `path` ("" or "/" for the root).
void set_attribute(const File& file, const std::string& path, const std::string& name, double value);
void set_attribute(const File& file, const std::string& path, const std::string& name, int64_t value);
void set_attribute(const File& file, const std::string& path, const std::string& name, const std::string& value);
void set_attribute(const File& file, const std::string& path, const std::string& name, const std::vector<double>& value);
bool has_attribute(const File& file, const std::string& path, const std::string& name);
// Names of the attributes on the object at `path`, alphabetical (none when it does not exist).
std::vector<std::string> list_attributes(const File& file, const std::string& path);
double get_double(const File& file, const std::string& path, const std::string& name);
int64_t get_int(const File& file, const std::string& path, const std::string& name);
std::string get_string(const File& file, const std::string& path, const std::string& name);
std::vector<double> get_doubles(const File& file, const std::string& path, const std::string& name);

// A dataset that grows along its first axis, one record of shape `record` at a time,
// e.g. frames of [N,2] positions. Each append extends and writes; flush the file to make
// the records durable.
class Appendable {
 public:
  Appendable() = default;
  // chunk_rows: records per HDF5 chunk (1 for large records such as frames, more for small ones);
  // record_chunk: at most this many rows of a record's first axis per chunk (0: all of them), so
  // that a large record is written piece by piece (write_rows) without a whole-record buffer.
  // allocate_early: the file space of new records is allocated as the dataset grows (extend),
  // not when they are written, and never filled: the parallel HDF5 can write only chunks that
  // have their space (solver/io/results_parallel.hpp).
  Appendable(const File& file, const std::string& path, const Dims& record, hid_t type = H5T_NATIVE_DOUBLE,
             hsize_t chunk_rows = 1, bool allocate_early = false, hsize_t record_chunk = 0);
  // An existing appendable dataset of `file` (opened for writing), cut back to its first
  // `keep` records so that appending continues from there. Throws talus::Error when the
  // dataset is missing, of another record shape, or shorter than `keep`.
  static Appendable reopen(const File& file, const std::string& path, const Dims& record, hsize_t keep,
                           hid_t type = H5T_NATIVE_DOUBLE);
  void append(const void* records, hsize_t rows = 1);
  // Grows the dataset by `rows` records left for another writer to fill (or write_rows).
  void extend(hsize_t rows = 1);
  // Writes rows [first, first + count) of the first axis of record `index` (already extended).
  void write_rows(hsize_t index, hsize_t first, hsize_t count, const void* rows);
  hsize_t size() const { return count_; }
  // The dataset allocates its file space as it grows (allocate_early above).
  bool allocated_early() const;

 private:
  // Writes `data` into the block `count` at `start` of the dataset.
  void write_block(const Dims& start, const Dims& count, const void* data);
  Handle dataset_;
  Dims record_;
  hid_t type_ = H5T_NATIVE_DOUBLE;
  hsize_t count_ = 0;
  std::string where_;
};

}  // namespace talus::h5
