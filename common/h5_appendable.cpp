// h5::Appendable: datasets that grow by records (results.h5's frames and history), apart from
// common/h5.cpp to keep each file short.
#include <algorithm>

#include "common/error.hpp"
#include "common/h5.hpp"

namespace talus::h5 {

Appendable::Appendable(const File& file, const std::string& path, const Dims& record, hid_t type,
                       hsize_t chunk_rows, bool allocate_early, hsize_t record_chunk)
    : record_(record), type_(type), where_(file.path() + ": " + path) {
  Dims dims{0}, max_dims{H5S_UNLIMITED}, chunk{std::max<hsize_t>(chunk_rows, 1)};
  for (hsize_t d : record) {
    dims.push_back(d);
    max_dims.push_back(d);
    chunk.push_back(std::max<hsize_t>(d, 1));
  }
  if (record_chunk > 0 && chunk.size() > 1) chunk[1] = std::min(chunk[1], record_chunk);
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), max_dims.data()));
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE));
  H5Pset_chunk(dcpl.id(), static_cast<int>(chunk.size()), chunk.data());
  if (allocate_early) {  // and not filled: every record is written in whole after it is allocated
    H5Pset_alloc_time(dcpl.id(), H5D_ALLOC_TIME_EARLY);
    H5Pset_fill_time(dcpl.id(), H5D_FILL_TIME_NEVER);
  }
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE));
  H5Pset_create_intermediate_group(lcpl.id(), 1);
  dataset_ = Handle(H5Dcreate2(file.id(), path.c_str(), type, space.id(), lcpl.id(), dcpl.id(), H5P_DEFAULT));
  if (!dataset_.valid()) throw_failure(where_ + ": cannot create appendable dataset");
}

void Appendable::append(const void* records, hsize_t rows) {
  if (rows == 0) return;
  extend(rows);
  Dims start{count_ - rows}, count{rows};
  for (hsize_t d : record_) {
    start.push_back(0);
    count.push_back(d);
  }
  write_block(start, count, records);
}

void Appendable::write_rows(hsize_t index, hsize_t first, hsize_t count, const void* rows) {
  if (count == 0) return;
  if (record_.empty() || index >= count_ || first + count > record_[0])
    throw Error(where_ + ": internal error: rows outside the dataset");
  Dims start{index, first}, size{1, count};
  for (std::size_t d = 1; d < record_.size(); ++d) {
    start.push_back(0);
    size.push_back(record_[d]);
  }
  write_block(start, size, rows);
}

void Appendable::write_block(const Dims& start, const Dims& count, const void* data) {
  Handle file_space(H5Dget_space(dataset_.id()));
  const Handle memory_space = select_block(file_space.id(), start, count);
  if (H5Dwrite(dataset_.id(), type_, memory_space.id(), file_space.id(), H5P_DEFAULT, data) < 0)
    throw_failure(where_ + ": cannot write record");
}

void Appendable::extend(hsize_t rows) {
  if (rows == 0) return;
  Dims dims{count_ + rows};
  dims.insert(dims.end(), record_.begin(), record_.end());
  if (H5Dset_extent(dataset_.id(), dims.data()) < 0) throw_failure(where_ + ": cannot extend dataset");
  count_ += rows;
}

bool Appendable::allocated_early() const {
  Handle dcpl(H5Dget_create_plist(dataset_.id()));
  H5D_alloc_time_t when = H5D_ALLOC_TIME_DEFAULT;
  return dcpl.valid() && H5Pget_alloc_time(dcpl.id(), &when) >= 0 && when == H5D_ALLOC_TIME_EARLY;
}

Appendable Appendable::reopen(const File& file, const std::string& path, const Dims& record, hsize_t keep,
                              hid_t type) {
  Appendable appendable;
  appendable.record_ = record;
  appendable.type_ = type;
  appendable.where_ = file.path() + ": " + path;
  auto fail = [&](const std::string& message) { throw Error(located(file.path(), path, message)); };
  if (!exists(file, path)) fail("missing dataset");
  const Dims dims = shape(file, path);
  Dims expected{dims.empty() ? 0 : dims[0]};
  expected.insert(expected.end(), record.begin(), record.end());
  if (dims != expected) fail("unexpected shape");
  if (dims[0] < keep)
    fail("has " + std::to_string(dims[0]) + " records, fewer than the " + std::to_string(keep) + " expected");
  appendable.dataset_ = Handle(H5Dopen2(file.id(), path.c_str(), H5P_DEFAULT));
  if (!appendable.dataset_.valid()) fail("cannot open dataset");
  Dims cut = expected;
  cut[0] = keep;
  if (H5Dset_extent(appendable.dataset_.id(), cut.data()) < 0) fail("cannot truncate dataset");
  appendable.count_ = keep;
  return appendable;
}

}  // namespace talus::h5
