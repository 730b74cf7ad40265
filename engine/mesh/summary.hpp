#pragma once

#include <cstddef>

#include "mesh/mesh.hpp"

namespace dfm::mesh {

// What a host or a user wants to know about a mesh before editing it.
struct MeshSummary {
    std::size_t vertices = 0;
    std::size_t faces = 0;
    std::size_t edges = 0;
    std::size_t boundary_edges = 0;
    std::size_t non_manifold_edges = 0;
    std::size_t inconsistent_edges = 0;
    std::size_t components = 0;
    std::size_t isolated_vertices = 0;
    std::size_t degenerate_faces = 0;  // zero area, relative to the diagonal
    bool closed = false;               // no boundary and no non-manifold edge
    Bounds bounds;
    double diagonal = 0.0;
};

// A triangle counts as degenerate when its area is below this fraction of
// the squared bounding-box diagonal.
inline constexpr double degenerate_area_ratio = 1e-14;

MeshSummary summarize(const Mesh& mesh);

}  // namespace dfm::mesh
