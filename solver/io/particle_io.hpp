// Particle fields to and from HDF5 datasets, one per registered field (particles.hpp): an
// [N] dataset for a scalar field, [N, width] for a vector one.
#pragma once
#include <cmath>
#include <string>
#include <type_traits>

#include "common/error.hpp"
#include "common/h5.hpp"
#include "solver/step/particles.hpp"

namespace talus::solver {

// Scalar type and width of a field's element type.
template <class T>
struct FieldElement {  // Eigen fixed-size vectors
  using Scalar = double;
  static constexpr int width = T::RowsAtCompileTime;
  static double get(const T& value, int k) { return value[k]; }
  static void set(T& value, int k, double x) { value[k] = x; }
};
template <>
struct FieldElement<double> {
  using Scalar = double;
  static constexpr int width = 1;
  static double get(double value, int) { return value; }
  static void set(double& value, int, double x) { value = x; }
};
template <>
struct FieldElement<int32_t> {
  using Scalar = int32_t;
  static constexpr int width = 1;
  static int32_t get(int32_t value, int) { return value; }
  static void set(int32_t& value, int, int32_t x) { value = x; }
};

// Writes `column` of n particles as `path`; an empty column writes nothing.
template <class T>
void write_column(const h5::File& file, const std::string& path, const std::vector<T>& column, std::size_t n) {
  using E = FieldElement<T>;
  if (column.empty()) return;
  std::vector<typename E::Scalar> flat;
  flat.reserve(column.size() * E::width);
  for (const T& value : column)
    for (int k = 0; k < E::width; ++k) flat.push_back(E::get(value, k));
  const hsize_t width = flat.size() / n;
  h5::write(file, path, flat, width == 1 ? h5::Dims{n} : h5::Dims{n, width});
}

// Reads `path` into `column`, which must already have the expected size (n rows of its width);
// throws talus::Error naming the file and the dataset on another shape or a non-finite value.
template <class T>
void read_column(const h5::File& file, const std::string& path, std::vector<T>& column, std::size_t n) {
  using E = FieldElement<T>;
  if (column.empty()) return;
  const hsize_t width = column.size() * E::width / n;
  h5::Dims dims;
  std::vector<typename E::Scalar> flat;
  if constexpr (std::is_same_v<typename E::Scalar, double>) flat = h5::read_doubles(file, path, &dims);
  else flat = h5::read_ints(file, path, &dims);
  const h5::Dims expected = width == 1 ? h5::Dims{n} : h5::Dims{n, width};
  if (dims != expected)
    throw Error(located(file.path(), path, "expected shape [" + std::to_string(n) +
                                               (width == 1 ? "" : "," + std::to_string(width)) + "]"));
  std::size_t k = 0;
  for (T& value : column)
    for (int c = 0; c < E::width; ++c, ++k) {
      if constexpr (std::is_same_v<typename E::Scalar, double>)
        if (!std::isfinite(flat[k]))
          throw Error(located(file.path(), path, "non-finite value in row " + std::to_string(k / width)));
      E::set(value, c, flat[k]);
    }
}

}  // namespace talus::solver
