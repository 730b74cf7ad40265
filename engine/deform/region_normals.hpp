#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/memory_bytes.hpp"
#include "deform/mesh_model.hpp"

namespace dfm::deform {

// Vertex normals of a mesh whose only moving vertices are a region's: the
// faces touching the region are summed anew, the rest of each affected
// vertex's fan is summed once at rest. Equal to mesh::compute_vertex_normals
// over the whole mesh up to rounding, at a cost proportional to the region.
class RegionNormals {
public:
    // `moving`: the vertices that may leave their rest positions.
    void build(const MeshModel& model, std::span<const std::uint32_t> moving);

    // Vertices whose normals change when the region moves, ascending.
    std::span<const std::uint32_t> vertices() const { return vertices_; }

    // One normal per entry of vertices(), from `positions` (the whole mesh).
    void compute(std::span<const glm::dvec3> positions, std::span<glm::dvec3> normals) const;

    std::size_t memory_bytes() const {
        return capacity_bytes(faces_, vertices_, slot_of_vertex_, rest_sum_);
    }

private:
    const MeshModel* model_ = nullptr;
    std::vector<std::uint32_t> faces_;           // faces with a moving vertex
    std::vector<std::uint32_t> vertices_;        // their vertices
    std::vector<std::uint32_t> slot_of_vertex_;  // per face corner: index into vertices_
    std::vector<glm::dvec3> rest_sum_;  // per entry of vertices_: the unchanging faces' sum
};

}  // namespace dfm::deform
