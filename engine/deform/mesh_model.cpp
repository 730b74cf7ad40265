#include "deform/mesh_model.hpp"

#include <numeric>

namespace dfm::deform {

MeshModel build_mesh_model(mesh::Mesh m) {
    MeshModel model;
    model.mesh = std::move(m);
    const mesh::Mesh& mesh = model.mesh;
    model.topology = mesh::build_edge_topology(mesh);
    model.vertex_neighbors = mesh::build_vertex_adjacency(mesh.vertex_count(), model.topology.edges);
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

}  // namespace dfm::deform
