#include "roi/ball_selection.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

namespace dfm::roi {

Status select_ball(std::span<const glm::dvec3> positions, const mesh::VertexAdjacency& adjacency,
                   std::uint32_t center, double radius, std::vector<std::uint32_t>& out) {
    out.clear();
    if (center >= positions.size()) {
        return Status(Errc::out_of_range, "ball centre " + std::to_string(center) +
                                              " is out of range (the mesh has " +
                                              std::to_string(positions.size()) + " vertices)");
    }
    if (!(radius >= 0.0) || !std::isfinite(radius)) {
        return Status(Errc::invalid_argument, "ball radius must be finite and not negative");
    }
    const glm::dvec3 c = positions[center];
    std::vector<std::uint8_t> seen(positions.size(), 0);
    out.push_back(center);
    seen[center] = 1;
    for (std::size_t head = 0; head < out.size(); ++head) {
        for (std::uint32_t w : adjacency.of(out[head])) {
            if (seen[w] || glm::length(positions[w] - c) > radius) continue;
            seen[w] = 1;
            out.push_back(w);
        }
    }
    std::sort(out.begin(), out.end());
    return Status::ok();
}

}  // namespace dfm::roi
