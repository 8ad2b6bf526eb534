#include "solver/parallel/packing.hpp"

#include <cstring>
#include <string_view>
#include <type_traits>

namespace talus::solver {

std::vector<std::size_t> field_widths(const Particles& P) {
  std::vector<std::size_t> widths;
  const std::size_t n = P.size();
  P.for_each_field([&](const FieldInfo&, const auto& column) { widths.push_back(width_of(column, n)); });
  return widths;
}

void set_width(std::vector<std::size_t>& widths, const char* member, std::size_t width) {
  const Particles none;
  std::size_t f = 0;
  none.for_each_field([&](const FieldInfo& info, const auto&) {
    if (std::string_view(info.name) == member) widths[f] = width;
    ++f;
  });
}

void pack(const Particles& P, const std::vector<std::size_t>& widths, std::size_t p, std::string& out) {
  std::size_t f = 0;
  P.for_each_field([&](const FieldInfo&, const auto& column) {
    const std::size_t w = widths[f++];
    if (w == 0) return;
    using T = typename std::decay_t<decltype(column)>::value_type;
    out.append(reinterpret_cast<const char*>(column.data() + p * w), w * sizeof(T));
  });
}

std::size_t packed_size(const std::vector<std::size_t>& widths) {
  Particles P;
  std::size_t bytes = 0, f = 0;
  P.for_each_field([&](const FieldInfo&, const auto& column) {
    using T = typename std::decay_t<decltype(column)>::value_type;
    bytes += widths[f++] * sizeof(T);
  });
  return bytes;
}

void unpack_all(const char* begin, const char* end, const std::vector<std::size_t>& widths, Particles& Q) {
  const std::size_t size = packed_size(widths);
  if (size == 0) return;
  const std::size_t count = static_cast<std::size_t>(end - begin) / size;
  std::size_t f = 0, offset = 0;
  Q.for_each_field([&](const FieldInfo&, auto& column) {
    const std::size_t w = widths[f++];
    if (w == 0) return;
    using T = typename std::decay_t<decltype(column)>::value_type;
    const std::size_t old = column.size();
    column.resize(old + count * w);
    for (std::size_t p = 0; p < count; ++p)
      std::memcpy(static_cast<void*>(column.data() + old + p * w), begin + p * size + offset, w * sizeof(T));
    offset += w * sizeof(T);
  });
}

void append_particles(const Particles& P, const std::vector<std::size_t>& widths, const std::vector<std::size_t>& which,
                      Particles& Q) {
  std::size_t f = 0;
  Q.for_each_field_with(P, [&](const FieldInfo&, auto& column, const auto& from) {
    const std::size_t w = widths[f++];
    if (w == 0) return;
    column.reserve(column.size() + which.size() * w);
    for (std::size_t p : which) column.insert(column.end(), from.begin() + p * w, from.begin() + (p + 1) * w);
  });
}

}  // namespace talus::solver
