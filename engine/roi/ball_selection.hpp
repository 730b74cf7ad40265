#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "mesh/adjacency.hpp"

namespace dfm::roi {

// Every vertex reachable from `center` along mesh edges without leaving the
// Euclidean ball of `radius` around the centre's position, ascending.
// The centre itself is always in.
Status select_ball(std::span<const glm::dvec3> positions, const mesh::VertexAdjacency& adjacency,
                   std::uint32_t center, double radius, std::vector<std::uint32_t>& out);

}  // namespace dfm::roi
