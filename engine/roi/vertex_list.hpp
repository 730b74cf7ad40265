#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "core/status.hpp"

namespace dfm::roi {

// An explicit vertex list as a ROI: sorted ascending, duplicates dropped.
// Fails, naming the entry, when an index is not below `vertex_count`.
Status select_vertices(std::span<const std::uint32_t> list, std::size_t vertex_count,
                       std::vector<std::uint32_t>& out);

// Whether `roi` is a ROI as the ROI tools return it: strictly ascending and
// below `vertex_count`. `what` names the set in the message.
Status check_roi(std::span<const std::uint32_t> roi, std::size_t vertex_count,
                 std::string_view what);

}  // namespace dfm::roi
