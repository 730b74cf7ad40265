#include "roi/boundary.hpp"

#include <algorithm>

#include "roi/vertex_list.hpp"

namespace dfm::roi {

Status boundary_vertices(const mesh::VertexAdjacency& adjacency, std::span<const std::uint32_t> roi,
                         std::vector<std::uint32_t>& out) {
    out.clear();
    const std::size_t n = adjacency.offsets.empty() ? 0 : adjacency.offsets.size() - 1;
    if (Status s = check_roi(roi, n, "boundary"); !s) return s;
    // Membership by binary search keeps the cost in the ROI, not the mesh.
    const auto inside = [&](std::uint32_t w) {
        return std::binary_search(roi.begin(), roi.end(), w);
    };
    for (std::uint32_t v : roi) {
        const auto around = adjacency.of(v);
        if (std::any_of(around.begin(), around.end(),
                        [&](std::uint32_t w) { return !inside(w); })) {
            out.push_back(v);
        }
    }
    return Status::ok();
}

}  // namespace dfm::roi
