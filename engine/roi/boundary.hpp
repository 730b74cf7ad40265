#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "mesh/adjacency.hpp"

namespace dfm::roi {

// The ROI's vertices with a neighbour outside it, ascending: where the
// edited region meets the fixed part. `roi` must be strictly ascending and
// in range (check_roi); time linear in the ROI.
Status boundary_vertices(const mesh::VertexAdjacency& adjacency, std::span<const std::uint32_t> roi,
                         std::vector<std::uint32_t>& out);

}  // namespace dfm::roi
