#include "common/h5.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <new>
#include <numeric>
#include <type_traits>

#include "common/atomic_file.hpp"
#include "common/error.hpp"

namespace talus::h5 {
namespace {

// HDF5 prints its own error stack by default; Talus reports errors itself. And HDF5's exit
// handler would close again a file whose close failed (a full disk): it crashed in
// H5F__close_cb after Talus had reported the error. Every file Talus writes is closed, or
// failed and removed, before the process ends, so the handler is not installed.
struct SilenceHdf5 {
  SilenceHdf5() {
    H5dont_atexit();
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
};
const SilenceHdf5 silence_hdf5;

// Whether HDF5's error stack holds a failed allocation (major H5E_RESOURCE): memory ran out
// inside the library, which the caller reports as out of memory (std::bad_alloc), not as a
// file error.
herr_t find_resource_error(unsigned, const H5E_error2_t* error, void* found) {
  if (error->maj_num == H5E_RESOURCE) *static_cast<bool*>(found) = true;
  return 0;
}

[[noreturn]] void fail(const File& file, const std::string& item, const std::string& message) {
  throw_failure(located(file.path(), item, message));
}

hid_t check(hid_t id, const File& file, const std::string& item, const char* what) {
  if (id < 0) fail(file, item, what);
  return id;
}

}  // namespace

void throw_failure(const std::string& message) {
  bool out_of_memory = false;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, find_resource_error, &out_of_memory);
  H5Eclear2(H5E_DEFAULT);
  if (out_of_memory) throw std::bad_alloc();
  throw Error(message);
}

namespace {

std::string root_relative(const std::string& path) { return path.empty() ? "/" : path; }

Handle create_dataset(const File& file, const std::string& path, hid_t type, const Dims& dims) {
  if (exists(file, path)) H5Ldelete(file.id(), path.c_str(), H5P_DEFAULT);
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.id(), 1);
  hid_t id = H5Dcreate2(file.id(), path.c_str(), type, space.id(), lcpl.id(), H5P_DEFAULT, H5P_DEFAULT);
  return Handle(check(id, file, path, "cannot create dataset"));
}

template <class T>
void write_numbers(const File& file, const std::string& path, const std::vector<T>& data, const Dims& dims,
                   hid_t type) {
  const hsize_t count = std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<>());
  if (count != data.size()) fail(file, path, "internal error: data size does not match its shape");
  Handle dataset = create_dataset(file, path, type, dims);
  if (count > 0 && H5Dwrite(dataset.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    fail(file, path, "cannot write dataset");
}

// A damaged or hostile file can declare a dataset of any size. Talus writes its datasets
// uncompressed, so a dataset that would not fit in the file itself is refused before anything
// is allocated for it (instead of an allocation failure, or a read past the end of the file).
hsize_t checked_count(const File& file, const std::string& path, const Dims& dims, hid_t dataset) {
  hsize_t count = 1;
  for (hsize_t d : dims) {
    if (d != 0 && count > std::numeric_limits<hsize_t>::max() / d) fail(file, path, "dataset shape overflows");
    count *= d;
  }
  Handle type(H5Dget_type(dataset));
  const std::size_t element = type.valid() ? std::max<std::size_t>(H5Tget_size(type.id()), 1) : 1;
  std::error_code error;
  const std::uintmax_t bytes = std::filesystem::file_size(file.path(), error);
  if (!error && count > 0 && count > bytes / element)
    fail(file, path,
         "dataset of " + std::to_string(count) + " values is larger than the file (" + std::to_string(bytes) +
             " bytes): truncated or damaged");
  return count;
}

template <class T>
std::vector<T> read_numbers(const File& file, const std::string& path, Dims* dims, hid_t type) {
  if (!exists(file, path)) fail(file, path, "missing dataset");
  Dims local = shape(file, path);
  Handle dataset(check(H5Dopen2(file.id(), path.c_str(), H5P_DEFAULT), file, path, "cannot open dataset"));
  Handle file_type(H5Dget_type(dataset.id()));
  const H5T_class_t kind = file_type.valid() ? H5Tget_class(file_type.id()) : H5T_NO_CLASS;
  if (kind != H5T_INTEGER && kind != H5T_FLOAT) fail(file, path, "expected numbers");
  if (std::is_integral_v<T> && kind != H5T_INTEGER) fail(file, path, "expected integers, got floating-point numbers");
  const hsize_t count = checked_count(file, path, local, dataset.id());
  std::vector<T> data(count);
  if (count > 0 && H5Dread(dataset.id(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    fail(file, path, "cannot read dataset (truncated or of the wrong type)");
  if (dims) *dims = local;
  return data;
}

Handle open_object(const File& file, const std::string& path) {
  const std::string where = root_relative(path);
  hid_t id = H5Oopen(file.id(), where.c_str(), H5P_DEFAULT);
  return Handle(check(id, file, where, "missing object"));
}

void write_attribute(const File& file, const std::string& path, const std::string& name, hid_t type,
                     const Dims& dims, const void* value) {
  Handle object = open_object(file, path);
  if (H5Aexists(object.id(), name.c_str()) > 0) H5Adelete(object.id(), name.c_str());
  Handle space(dims.empty() ? H5Screate(H5S_SCALAR)
                            : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr));
  Handle attribute(H5Acreate2(object.id(), name.c_str(), type, space.id(), H5P_DEFAULT, H5P_DEFAULT));
  if (!attribute.valid() || H5Awrite(attribute.id(), type, value) < 0)
    fail(file, root_relative(path) + "@" + name, "cannot write attribute");
}

Handle open_attribute(const File& file, const std::string& path, const std::string& name) {
  Handle object = open_object(file, path);
  if (H5Aexists(object.id(), name.c_str()) <= 0) fail(file, root_relative(path) + "@" + name, "missing attribute");
  return Handle(H5Aopen(object.id(), name.c_str(), H5P_DEFAULT));
}

hssize_t attribute_size(const Handle& attribute) {
  Handle space(H5Aget_space(attribute.id()));
  return H5Sget_simple_extent_npoints(space.id());
}

}  // namespace

Handle& Handle::operator=(Handle&& other) noexcept {
  if (this != &other) {
    reset();
    id_ = other.id_;
    other.id_ = -1;
  }
  return *this;
}

void Handle::reset() {
  if (id_ < 0) return;
  switch (H5Iget_type(id_)) {
    case H5I_FILE: H5Fclose(id_); break;
    case H5I_GROUP: H5Gclose(id_); break;
    case H5I_DATASET: H5Dclose(id_); break;
    case H5I_DATASPACE: H5Sclose(id_); break;
    case H5I_DATATYPE: H5Tclose(id_); break;
    case H5I_ATTR: H5Aclose(id_); break;
    case H5I_GENPROP_LST: H5Pclose(id_); break;
    default: H5Oclose(id_); break;
  }
  id_ = -1;
}

File File::create(const std::string& path) {
  File file;
  file.path_ = path;
  file.handle_ = Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));
  if (!file.handle_.valid()) throw Error(located(path, "", "cannot create HDF5 file (is the folder writable?)"));
  return file;
}

File File::open_read(const std::string& path) {
  if (!std::filesystem::exists(path)) throw Error(located(path, "", "no such file"));
  if (H5Fis_hdf5(path.c_str()) <= 0) throw Error(located(path, "", "not an HDF5 file (or truncated)"));
  File file;
  file.path_ = path;
  file.handle_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT));
  if (!file.handle_.valid()) throw Error(located(path, "", "cannot open HDF5 file (truncated or damaged?)"));
  return file;
}

File File::open_write(const std::string& path) {
  File file;
  file.path_ = path;
  file.handle_ = Handle(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT));
  if (!file.handle_.valid()) throw Error(located(path, "", "cannot open HDF5 file for writing"));
  return file;
}

void File::flush() const {
  if (H5Fflush(handle_.id(), H5F_SCOPE_GLOBAL) < 0)
    throw Error(located(path_, "", "cannot write HDF5 file (disk full, or over the file size limit?)"));
}

void File::close() {
  if (!handle_.valid()) return;
  if (H5Fclose(handle_.release()) < 0) throw Error(located(path_, "", "cannot write HDF5 file (disk full, or over the file size limit?)"));
}

void write_atomically(const std::string& path, const std::function<void(const File&)>& fill) {
  talus::write_atomically(path, [&](const std::string& temporary) {
    File file = File::create(temporary);
    fill(file);
    file.close();
  });
}

bool exists(const File& file, const std::string& path) {
  // Check each prefix: H5Lexists fails on a path whose parent group is missing.
  std::size_t start = 0;
  while (true) {
    const std::size_t slash = path.find('/', start);
    const std::string prefix = path.substr(0, slash);
    if (!prefix.empty() && H5Lexists(file.id(), prefix.c_str(), H5P_DEFAULT) <= 0) return false;
    if (slash == std::string::npos) return true;
    start = slash + 1;
  }
}

Dims shape(const File& file, const std::string& path) {
  Handle dataset(check(H5Dopen2(file.id(), path.c_str(), H5P_DEFAULT), file, path, "missing dataset"));
  Handle space(H5Dget_space(dataset.id()));
  const int rank = H5Sget_simple_extent_ndims(space.id());
  Dims dims(std::max(rank, 0));
  if (rank > 0) H5Sget_simple_extent_dims(space.id(), dims.data(), nullptr);
  return dims;
}

void write(const File& file, const std::string& path, const std::vector<double>& data, const Dims& dims) {
  write_numbers(file, path, data, dims, H5T_NATIVE_DOUBLE);
}

void write(const File& file, const std::string& path, const std::vector<int32_t>& data, const Dims& dims) {
  write_numbers(file, path, data, dims, H5T_NATIVE_INT32);
}

void write(const File& file, const std::string& path, const std::vector<std::string>& data) {
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.id(), H5T_VARIABLE);
  H5Tset_cset(type.id(), H5T_CSET_UTF8);
  Handle dataset = create_dataset(file, path, type.id(), {data.size()});
  std::vector<const char*> pointers;
  for (const auto& s : data) pointers.push_back(s.c_str());
  if (!data.empty() && H5Dwrite(dataset.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()) < 0)
    fail(file, path, "cannot write strings");
}

std::vector<double> read_doubles(const File& file, const std::string& path, Dims* dims) {
  return read_numbers<double>(file, path, dims, H5T_NATIVE_DOUBLE);
}

std::vector<int32_t> read_ints(const File& file, const std::string& path, Dims* dims) {
  return read_numbers<int32_t>(file, path, dims, H5T_NATIVE_INT32);
}

Handle select_block(hid_t file_space, const Dims& start, const Dims& count) {
  Handle memory_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr));
  if (std::find(count.begin(), count.end(), hsize_t{0}) != count.end()) {
    H5Sselect_none(file_space);
    H5Sselect_none(memory_space.id());
  } else {
    H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr);
  }
  return memory_space;
}

std::vector<double> read_double_rows(const File& file, const std::string& path, hsize_t first, hsize_t count) {
  if (!exists(file, path)) fail(file, path, "missing dataset");
  const Dims dims = shape(file, path);
  if (dims.empty() || first + count > dims[0])
    fail(file, path, "expected at least " + std::to_string(first + count) + " rows");
  Handle dataset(check(H5Dopen2(file.id(), path.c_str(), H5P_DEFAULT), file, path, "cannot open dataset"));
  Dims start{first}, size{count};
  hsize_t values = count;
  for (std::size_t d = 1; d < dims.size(); ++d) {
    start.push_back(0);
    size.push_back(dims[d]);
    values *= dims[d];
  }
  std::vector<double> data(values);
  if (values == 0) return data;
  Handle file_space(H5Dget_space(dataset.id()));
  const Handle memory_space = select_block(file_space.id(), start, size);
  if (H5Dread(dataset.id(), H5T_NATIVE_DOUBLE, memory_space.id(), file_space.id(), H5P_DEFAULT, data.data()) < 0)
    fail(file, path, "cannot read rows (truncated or of the wrong type)");
  return data;
}

std::vector<std::string> read_strings(const File& file, const std::string& path) {
  if (!exists(file, path)) fail(file, path, "missing dataset");
  Handle dataset(check(H5Dopen2(file.id(), path.c_str(), H5P_DEFAULT), file, path, "cannot open dataset"));
  Handle file_type(H5Dget_type(dataset.id()));
  if (H5Tget_class(file_type.id()) != H5T_STRING) fail(file, path, "expected strings");
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.id(), H5T_VARIABLE);
  H5Tset_cset(type.id(), H5Tget_cset(file_type.id()));
  if (H5Tis_variable_str(file_type.id()) <= 0) fail(file, path, "expected variable-length strings");
  const Dims dims = shape(file, path);
  if (dims.size() > 1) fail(file, path, "expected a list of strings");
  const hsize_t count = dims.empty() ? 1 : checked_count(file, path, dims, dataset.id());
  std::vector<char*> pointers(count, nullptr);
  if (count > 0 && H5Dread(dataset.id(), type.id(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()) < 0)
    fail(file, path, "cannot read strings");
  std::vector<std::string> out;
  for (char* p : pointers) out.emplace_back(p ? p : "");
  Handle space(H5Dget_space(dataset.id()));
  if (count > 0) H5Dvlen_reclaim(type.id(), space.id(), H5P_DEFAULT, pointers.data());
  return out;
}

std::vector<std::string> list(const File& file, const std::string& group_path) {
  std::vector<std::string> names;
  const std::string where = root_relative(group_path);
  if (where != "/" && !exists(file, group_path)) return names;
  Handle group(check(H5Gopen2(file.id(), where.c_str(), H5P_DEFAULT), file, where, "missing group"));
  H5G_info_t info;
  H5Gget_info(group.id(), &info);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t size =
        H5Lget_name_by_idx(group.id(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    std::string name(static_cast<std::size_t>(size), '\0');
    H5Lget_name_by_idx(group.id(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), size + 1, H5P_DEFAULT);
    names.push_back(name);
  }
  return names;
}

void create_group(const File& file, const std::string& path) {
  if (exists(file, path)) return;
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.id(), 1);
  Handle group(H5Gcreate2(file.id(), path.c_str(), lcpl.id(), H5P_DEFAULT, H5P_DEFAULT));
  check(group.id(), file, path, "cannot create group");
}

void set_attribute(const File& file, const std::string& path, const std::string& name, double value) {
  write_attribute(file, path, name, H5T_NATIVE_DOUBLE, {}, &value);
}

void set_attribute(const File& file, const std::string& path, const std::string& name, int64_t value) {
  write_attribute(file, path, name, H5T_NATIVE_INT64, {}, &value);
}

void set_attribute(const File& file, const std::string& path, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.id(), H5T_VARIABLE);
  H5Tset_cset(type.id(), H5T_CSET_UTF8);
  const char* pointer = value.c_str();
  write_attribute(file, path, name, type.id(), {}, &pointer);
}

void set_attribute(const File& file, const std::string& path, const std::string& name,
                   const std::vector<double>& value) {
  write_attribute(file, path, name, H5T_NATIVE_DOUBLE, {value.size()}, value.data());
}

bool has_attribute(const File& file, const std::string& path, const std::string& name) {
  const std::string where = root_relative(path);
  if (where != "/" && !exists(file, path)) return false;
  return H5Aexists_by_name(file.id(), where.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

std::vector<std::string> list_attributes(const File& file, const std::string& path) {
  std::vector<std::string> names;
  const std::string where = root_relative(path);
  if (where != "/" && !exists(file, path)) return names;
  H5O_info_t info;
  if (H5Oget_info_by_name2(file.id(), where.c_str(), &info, H5O_INFO_NUM_ATTRS, H5P_DEFAULT) < 0) return names;
  for (hsize_t i = 0; i < info.num_attrs; ++i) {
    const ssize_t size =
        H5Aget_name_by_idx(file.id(), where.c_str(), H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (size < 0) continue;
    std::string name(static_cast<std::size_t>(size), '\0');
    H5Aget_name_by_idx(file.id(), where.c_str(), H5_INDEX_NAME, H5_ITER_INC, i, name.data(), size + 1, H5P_DEFAULT);
    names.push_back(name);
  }
  return names;
}

namespace {

// A one-value attribute read as `type` (HDF5 converts), or an Error saying `expected`.
template <class T>
T get_one(const File& file, const std::string& path, const std::string& name, hid_t type, const char* expected) {
  Handle attribute = open_attribute(file, path, name);
  T value = 0;
  if (attribute_size(attribute) != 1 || H5Aread(attribute.id(), type, &value) < 0)
    fail(file, root_relative(path) + "@" + name, expected);
  return value;
}

}  // namespace

double get_double(const File& file, const std::string& path, const std::string& name) {
  return get_one<double>(file, path, name, H5T_NATIVE_DOUBLE, "expected one number");
}

int64_t get_int(const File& file, const std::string& path, const std::string& name) {
  return get_one<int64_t>(file, path, name, H5T_NATIVE_INT64, "expected one integer");
}

std::string get_string(const File& file, const std::string& path, const std::string& name) {
  Handle attribute = open_attribute(file, path, name);
  Handle file_type(H5Aget_type(attribute.id()));
  if (H5Tget_class(file_type.id()) != H5T_STRING) fail(file, root_relative(path) + "@" + name, "expected a string");
  if (H5Tis_variable_str(file_type.id()) <= 0) fail(file, root_relative(path) + "@" + name, "expected a string");
  Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.id(), H5T_VARIABLE);
  H5Tset_cset(type.id(), H5Tget_cset(file_type.id()));
  char* pointer = nullptr;
  if (H5Aread(attribute.id(), type.id(), &pointer) < 0)
    fail(file, root_relative(path) + "@" + name, "cannot read string");
  std::string value = pointer ? pointer : "";
  H5free_memory(pointer);
  return value;
}

std::vector<double> get_doubles(const File& file, const std::string& path, const std::string& name) {
  Handle attribute = open_attribute(file, path, name);
  std::vector<double> value(static_cast<std::size_t>(attribute_size(attribute)));
  if (!value.empty() && H5Aread(attribute.id(), H5T_NATIVE_DOUBLE, value.data()) < 0)
    fail(file, root_relative(path) + "@" + name, "expected numbers");
  return value;
}

}  // namespace talus::h5
