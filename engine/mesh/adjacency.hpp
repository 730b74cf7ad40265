#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/mesh.hpp"

namespace dfm::mesh {

// Every undirected edge once, with the faces around it. Faces' neighbours
// follow each face's edge order (v0v1, v1v2, v2v0), which the dual Laplacian
// relies on for a consistent orientation.
struct EdgeTopology {
    std::vector<std::array<std::uint32_t, 2>> edges;  // a < b, sorted
    std::vector<std::uint32_t> face_counts;           // faces on each edge
    // Per face, the face across each edge; no_index on a boundary or
    // non-manifold edge.
    std::vector<std::array<std::uint32_t, 3>> face_neighbors;
    std::vector<std::uint32_t> boundary_edges;      // indices into edges: one face
    std::vector<std::uint32_t> non_manifold_edges;  // indices into edges: three or more faces
    std::size_t inconsistent_edges = 0;  // two faces that run along it in the same direction
};

EdgeTopology build_edge_topology(const Mesh& mesh);

// Vertex–vertex adjacency in CSR form: the neighbours of v, ascending, are
// neighbors[offsets[v] .. offsets[v + 1]).
struct VertexAdjacency {
    std::vector<std::uint32_t> offsets;
    std::vector<std::uint32_t> neighbors;

    std::span<const std::uint32_t> of(std::uint32_t v) const {
        return std::span(neighbors).subspan(offsets[v], offsets[v + 1] - offsets[v]);
    }
};

VertexAdjacency build_vertex_adjacency(std::size_t vertex_count,
                                       std::span<const std::array<std::uint32_t, 2>> edges);
VertexAdjacency build_vertex_adjacency(const Mesh& mesh);

// Connected components of the surface, numbered in order of their lowest
// vertex. Vertices in no triangle belong to none (no_index).
struct Components {
    std::vector<std::uint32_t> vertex_component;
    std::size_t count = 0;
    std::size_t isolated_vertices = 0;
};

Components find_components(const Mesh& mesh);

}  // namespace dfm::mesh
