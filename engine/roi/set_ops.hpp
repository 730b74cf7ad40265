#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/status.hpp"

namespace dfm::roi {

// Vertices in a or b, ascending. Both must be strictly ascending and below
// vertex_count (check_roi); time linear in |a| + |b|.
Status roi_union(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b,
                 std::size_t vertex_count, std::vector<std::uint32_t>& out);

// Vertices in a and not in b, ascending; same preconditions.
Status roi_difference(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b,
                      std::size_t vertex_count, std::vector<std::uint32_t>& out);

}  // namespace dfm::roi
