// Pieces of the model file layout shared by model.h5 and results.h5: the format tag, and the
// bodies / materials / settings groups that the solver copies into its results so that the
// postprocessor needs only results.h5.
#pragma once
#include <string>
#include <vector>

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
// (particles/*), their count as the root attribute `particles`. The frames and the history follow.
void write_results_start(const h5::File& file, const Model& metadata,
                         const std::vector<Eigen::Vector2d>& initial_position, const std::vector<int32_t>& body,
                         const std::vector<double>& mass, const std::vector<double>& volume);

}  // namespace talus
