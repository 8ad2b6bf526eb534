// Pieces of the model file layout shared by model.h5 and results.h5: the format tag, and the
// bodies / materials / settings groups that the solver copies into its results so that the
// postprocessor needs only results.h5.
#pragma once
#include <string>
#include <vector>

#include "common/error.hpp"

#include "common/h5.hpp"
#include "common/model/model.hpp"

namespace talus {

// Rows of a fixed-size Eigen vector type as one row-major array, for an [N, width] dataset.
template <class Vec>
std::vector<double> flatten(const std::vector<Vec>& rows) {
  std::vector<double> flat;
  flat.reserve(rows.size() * Vec::RowsAtCompileTime);
  for (const auto& row : rows)
    for (int k = 0; k < Vec::RowsAtCompileTime; ++k) flat.push_back(row[k]);
  return flat;
}

// The rows of an [rows, width] dataset as fixed-size Eigen vectors; throws talus::Error naming
// the file and dataset on another shape.
template <class Vec>
std::vector<Vec> unflatten(const std::vector<double>& flat, const h5::Dims& dims, const h5::File& file,
                           const std::string& path, std::size_t rows) {
  constexpr int width = Vec::RowsAtCompileTime;
  if (dims.size() != 2 || dims[0] != rows || dims[1] != static_cast<hsize_t>(width))
    throw Error(located(file.path(), path,
                        "expected shape [" + std::to_string(rows) + "," + std::to_string(width) + "]"));
  std::vector<Vec> out(rows);
  for (std::size_t i = 0; i < rows; ++i)
    for (int k = 0; k < width; ++k) out[i][k] = flat[i * width + k];
  return out;
}
// One value per row: a shape such as [N,0] has N rows but no values (found by fuzzing).
void check_count(const h5::File& file, const std::string& path, const h5::Dims& dims, std::size_t rows);
void check_finite(const h5::File& file, const std::string& path, const std::vector<double>& values);

// /materials: the names, and per material a group with its model and parameters (materials_io.cpp).
void write_materials(const h5::File& file, const std::vector<Material>& materials);
std::vector<Material> read_materials(const h5::File& file);
// model.h5's /particles/properties/<material>.<parameter>, one dataset per property, NaN at the
// particles of other materials (none: no group).
void write_properties(const h5::File& file, const Model& model);
// Reads them into model.properties and checks them (properties_problem); needs the materials,
// bodies and particles' bodies read first.
void read_properties(const h5::File& file, Model& model);

// results.h5's /particles/<parameter> (attribute `unit`) for each parameter of the properties of
// `metadata`: each particle's value, its own or its material's, NaN for a material without it.
void write_property_values(const h5::File& file, const Model& metadata, const std::vector<int32_t>& body);

inline constexpr int kResultsFormatVersion = 1;

void write_format_tag(const h5::File& file, const std::string& kind, int version);
// Throws talus::Error with both versions when the file is of another version.
void check_format_tag(const h5::File& file, const std::string& kind, int version);

// Root attribute `scene`, /bodies, /materials, /settings/{run,contact,post}.
void write_metadata(const h5::File& file, const Model& model);
// Fills scene_name, bodies, materials, run, contact and post of `model`.
void read_metadata(const h5::File& file, Model& model);

// The start of results.h5, all that is known before the first step, for every writer of it (the
// solver's, and postproc::write_results for tests and tools): the format tag, the metadata of
// `metadata`, and per particle its initial position, body, mass and initial volume
// (particles/*), their count as the root attribute `particles`, and with per-particle properties
// (metadata.properties) each parameter's values as /particles/<parameter>. The frames and the
// history follow.
void write_results_start(const h5::File& file, const Model& metadata,
                         const std::vector<Eigen::Vector2d>& initial_position, const std::vector<int32_t>& body,
                         const std::vector<double>& mass, const std::vector<double>& volume);

}  // namespace talus
