// settings/seismic and settings/base_motion of model.h5 and results.h5 (docs/model-format.md),
// each written only when the scene has the table, so a model without them is unchanged.
#pragma once
#include "common/h5.hpp"
#include "common/scene/seismic.hpp"

namespace talus {

void write_seismic(const h5::File& file, const SeismicSettings& seismic, const BaseMotion& motion);
// Absent groups give the defaults (off). Throws talus::Error naming the file and the item.
void read_seismic(const h5::File& file, SeismicSettings& seismic, BaseMotion& motion);

// boundary_conditions/absorbing_{nodes, lengths, normals, impedances, input} of model.h5, only
// when there are absorbing boundaries. `node_count` bounds the node ids on reading.
void write_absorbing(const h5::File& file, const AbsorbingNodes& absorbing);
AbsorbingNodes read_absorbing(const h5::File& file, std::size_t node_count);

}  // namespace talus
