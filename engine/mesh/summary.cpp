#include "mesh/summary.hpp"

#include "mesh/adjacency.hpp"

namespace dfm::mesh {

MeshSummary summarize(const Mesh& mesh) {
    MeshSummary s;
    s.vertices = mesh.vertex_count();
    s.faces = mesh.face_count();
    const EdgeTopology topo = build_edge_topology(mesh);
    s.edges = topo.edges.size();
    s.boundary_edges = topo.boundary_edges.size();
    s.non_manifold_edges = topo.non_manifold_edges.size();
    s.inconsistent_edges = topo.inconsistent_edges;
    const Components comps = find_components(mesh);
    s.components = comps.count;
    s.isolated_vertices = comps.isolated_vertices;
    s.closed = s.faces > 0 && s.boundary_edges == 0 && s.non_manifold_edges == 0;
    s.bounds = compute_bounds(mesh.positions);
    s.diagonal = s.bounds.diagonal();
    const double min_area = degenerate_area_ratio * s.diagonal * s.diagonal;
    for (std::size_t f = 0; f < s.faces; ++f) {
        if (triangle_area(mesh, f) <= min_area) ++s.degenerate_faces;
    }
    return s;
}

}  // namespace dfm::mesh
