// The background mesh: the triangles of the domain's physical surface with compact node ids,
// counter-clockwise vertex order and element neighbours, as the solver's Model stores them.
#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "preproc/gmsh_geometry.hpp"

namespace talus::preproc {

struct BackgroundMesh {
  std::vector<Eigen::Vector2d> nodes;
  std::vector<std::array<int32_t, 3>> triangles;   // counter-clockwise
  std::vector<std::array<int32_t, 3>> neighbours;  // across the edge opposite local vertex k; -1: boundary
  std::vector<int32_t> node_of_tag;                // gmsh node tag -> node id, -1 if not in the mesh
  // The grid pattern's lattice (lattice.hpp): its nodes are none of gmsh's, and its curves'
  // segments are found by position (lattice_segments).
  bool lattice = false;

  int32_t node(NodeTag tag) const {
    return tag < node_of_tag.size() ? node_of_tag[tag] : -1;
  }
};

// Triangles are ordered along a Morton curve through their centroids and nodes are numbered in
// the order the triangles first name them (memory locality for the solver). Throws
// talus::Error when the domain holds elements other than triangles or overlapping surfaces.
BackgroundMesh background_mesh(const GeoMesh& geo, const PhysicalGroup& domain);

// Element neighbours from shared edges; returns false when an edge has more than two triangles.
bool find_neighbours(const std::vector<std::array<int32_t, 3>>& triangles,
                     std::vector<std::array<int32_t, 3>>& neighbours);

// The edges on the domain boundary (those with no neighbour), as node-id pairs.
std::vector<std::array<std::size_t, 2>> boundary_edges(const BackgroundMesh& mesh);

}  // namespace talus::preproc
