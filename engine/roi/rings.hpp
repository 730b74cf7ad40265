#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "mesh/adjacency.hpp"

namespace dfm::roi {

// The ROI and every vertex within `rings` edges of it, ascending. `roi` must
// be strictly ascending and in range (check_roi); time linear in the result.
Status grow_rings(const mesh::VertexAdjacency& adjacency, std::span<const std::uint32_t> roi,
                  std::uint32_t rings, std::vector<std::uint32_t>& out);

// The ROI without every vertex within `rings` edges of a vertex outside it
// (shrinking by one ring drops the boundary vertices), ascending. Same
// preconditions; time linear in rings × the ROI.
Status shrink_rings(const mesh::VertexAdjacency& adjacency, std::span<const std::uint32_t> roi,
                    std::uint32_t rings, std::vector<std::uint32_t>& out);

}  // namespace dfm::roi
