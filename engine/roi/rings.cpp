#include "roi/rings.hpp"

#include <algorithm>
#include <iterator>

#include "roi/boundary.hpp"
#include "roi/vertex_list.hpp"

namespace dfm::roi {

Status grow_rings(const mesh::VertexAdjacency& adjacency, std::span<const std::uint32_t> roi,
                  std::uint32_t rings, std::vector<std::uint32_t>& out) {
    out.clear();
    const std::size_t n = adjacency.offsets.empty() ? 0 : adjacency.offsets.size() - 1;
    if (Status s = check_roi(roi, n, "grow"); !s) return s;
    std::vector<std::uint8_t> in(n, 0);
    out.assign(roi.begin(), roi.end());
    for (std::uint32_t v : roi) in[v] = 1;
    // Breadth-first, one ring per pass over the newest ring.
    std::size_t ring_start = 0;
    for (std::uint32_t r = 0; r < rings && ring_start < out.size(); ++r) {
        const std::size_t ring_end = out.size();
        for (std::size_t i = ring_start; i < ring_end; ++i) {
            for (std::uint32_t w : adjacency.of(out[i])) {
                if (in[w]) continue;
                in[w] = 1;
                out.push_back(w);
            }
        }
        ring_start = ring_end;
    }
    std::sort(out.begin(), out.end());
    return Status::ok();
}

Status shrink_rings(const mesh::VertexAdjacency& adjacency, std::span<const std::uint32_t> roi,
                    std::uint32_t rings, std::vector<std::uint32_t>& out) {
    out.clear();
    const std::size_t n = adjacency.offsets.empty() ? 0 : adjacency.offsets.size() - 1;
    if (Status s = check_roi(roi, n, "shrink"); !s) return s;
    out.assign(roi.begin(), roi.end());
    std::vector<std::uint32_t> boundary;
    std::vector<std::uint32_t> kept;
    for (std::uint32_t r = 0; r < rings && !out.empty(); ++r) {
        if (Status s = boundary_vertices(adjacency, out, boundary); !s) return s;
        if (boundary.empty()) break;  // a whole closed component: nothing borders it
        kept.clear();
        std::set_difference(out.begin(), out.end(), boundary.begin(), boundary.end(),
                            std::back_inserter(kept));
        out.swap(kept);
    }
    return Status::ok();
}

}  // namespace dfm::roi
