#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/status.hpp"
#include "mesh/adjacency.hpp"
#include "mesh/mesh.hpp"

namespace dfm::roi {

// What the ROI tools read of a mesh: positions, triangles, vertex–vertex
// adjacency and vertex–face incidence (CSR: the faces of v are
// vertex_faces[vertex_face_offsets[v] .. vertex_face_offsets[v + 1])).
// deform::MeshModel holds all of them; the view owns nothing.
struct SurfaceView {
    std::span<const glm::dvec3> positions;
    std::span<const mesh::Triangle> triangles;
    const mesh::VertexAdjacency* neighbors = nullptr;
    std::span<const std::uint32_t> vertex_face_offsets;
    std::span<const std::uint32_t> vertex_faces;
};

// What a host needs to judge a Water-Filling region before editing.
struct WaterFillDiagnosis {
    // Cut loops bounding the region: the region's edges that cross the plane
    // (one end in the region, the other on or beyond the plane), grouped into
    // connected loops through the faces they cross.
    std::size_t loops = 0;
    // The plane–surface loop passing nearest to `last` is one of them.
    bool bounded_by_last_loop = false;
    // More than one loop, not the loop at `last`, or more than half the
    // mesh: the fill most likely leaked past the limb the user meant.
    bool suspect = false;
};

struct WaterFill {
    std::vector<std::uint32_t> vertices;  // ascending; `first` is always in
    WaterFillDiagnosis diagnosis;
};

// The paper's Water-Filling (§3.1). The region line runs from `first` to
// `last`; the cutting plane passes through `last` with the line's direction
// as its normal. The fill starts at `first` and walks mesh edges, never
// stepping onto a vertex on the far side: signed distance to the plane
// >= 0, so a vertex exactly on the plane (`last` among them) is never in.
// Deterministic; time linear in the region (plus one byte per mesh vertex
// for the visited marks). Fails when an index is out of range, first equals
// last or the two positions coincide.
Status water_fill(const SurfaceView& surface, std::uint32_t first, std::uint32_t last,
                  WaterFill& out);

}  // namespace dfm::roi
