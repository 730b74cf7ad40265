#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "dual/dual_laplacian.hpp"
#include "mesh/adjacency.hpp"
#include "mesh/mesh.hpp"

namespace dfm::deform {

// A mesh with everything an edit needs that depends only on the rest pose:
// topology, the dual Laplacian, vertex–face incidence and the rest diagonal.
// Shared by every edit session on the mesh; baking an edit makes a new one.
struct MeshModel {
    mesh::Mesh mesh;
    mesh::EdgeTopology topology;
    mesh::VertexAdjacency vertex_neighbors;
    dual::DualLaplacian dual;
    // Faces around each vertex, CSR: vertex_faces[vertex_face_offsets[v] ..].
    std::vector<std::uint32_t> vertex_face_offsets;
    std::vector<std::uint32_t> vertex_faces;
    double diagonal = 0.0;

    // Bytes held, by part (capacities of the arrays).
    struct Memory {
        std::size_t mesh = 0;       // positions and triangles
        std::size_t adjacency = 0;  // edges, face and vertex neighbours, vertex faces
        std::size_t dual = 0;       // the dual Laplacian's weights, heights and rows
    };
    Memory memory() const;

    std::span<const std::uint32_t> faces_of(std::uint32_t v) const {
        return std::span(vertex_faces)
            .subspan(vertex_face_offsets[v], vertex_face_offsets[v + 1] - vertex_face_offsets[v]);
    }
};

MeshModel build_mesh_model(mesh::Mesh mesh);

// Bakes an edit: a new model whose rest pose is `positions` (same triangles),
// with the dual Laplacian measured anew, so the next edit starts from the
// deformed shape. Fails on a size mismatch or a non-finite position.
Status bake_positions(const MeshModel& model, std::span<const glm::dvec3> positions,
                      MeshModel& out);

}  // namespace dfm::deform
