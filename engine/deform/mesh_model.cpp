#include "deform/mesh_model.hpp"

#include "core/memory_bytes.hpp"

#include <cmath>
#include <new>
#include <numeric>
#include <string>

namespace dfm::deform {

MeshModel::Memory MeshModel::memory() const {
    return {.mesh = capacity_bytes(mesh.positions, mesh.triangles),
            .adjacency = capacity_bytes(
                topology.edges, topology.face_counts, topology.face_neighbors,
                topology.boundary_edges, topology.non_manifold_edges, vertex_neighbors.offsets,
                vertex_neighbors.neighbors, vertex_face_offsets, vertex_faces),
            .dual = capacity_bytes(dual.neighbors, dual.weights, dual.heights, dual.has_row)};
}

MeshModel build_mesh_model(mesh::Mesh m) {
    MeshModel model;
    model.mesh = std::move(m);
    const mesh::Mesh& mesh = model.mesh;
    model.topology = mesh::build_edge_topology(mesh);
    model.vertex_neighbors =
        mesh::build_vertex_adjacency(mesh.vertex_count(), model.topology.edges);
    model.dual = dual::build_dual_laplacian(mesh, model.topology);
    model.diagonal = mesh::compute_bounds(mesh.positions).diagonal();

    model.vertex_face_offsets.assign(mesh.vertex_count() + 1, 0);
    for (const mesh::Triangle& t : mesh.triangles) {
        for (std::uint32_t v : t) ++model.vertex_face_offsets[v + 1];
    }
    std::partial_sum(model.vertex_face_offsets.begin(), model.vertex_face_offsets.end(),
                     model.vertex_face_offsets.begin());
    model.vertex_faces.resize(model.vertex_face_offsets.back());
    std::vector<std::uint32_t> fill(model.vertex_face_offsets.begin(),
                                    model.vertex_face_offsets.end() - 1);
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        for (std::uint32_t v : mesh.triangles[f]) model.vertex_faces[fill[v]++] = f;
    }
    return model;
}

Status bake_positions(const MeshModel& model, std::span<const glm::dvec3> positions,
                      MeshModel& out) {
    if (positions.size() != model.mesh.vertex_count()) {
        return Status(Errc::invalid_argument,
                      "expected " + std::to_string(model.mesh.vertex_count()) + " positions, got " +
                          std::to_string(positions.size()));
    }
    for (std::size_t v = 0; v < positions.size(); ++v) {
        const glm::dvec3& p = positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            return Status(Errc::invalid_argument,
                          "position of vertex " + std::to_string(v) + " is not finite");
        }
    }
    try {
        mesh::Mesh baked;
        baked.positions.assign(positions.begin(), positions.end());
        baked.triangles = model.mesh.triangles;
        out = build_mesh_model(std::move(baked));
        return Status::ok();
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, "out of memory while baking the edit");
    }
}

}  // namespace dfm::deform
