#include "mesh/adjacency.hpp"

#include <algorithm>
#include <numeric>

namespace dfm::mesh {

namespace {

struct HalfEdge {
    std::uint64_t key;     // (min << 32) | max of the endpoints
    std::uint32_t corner;  // face * 3 + local edge index
};

std::uint32_t edge_origin(const Mesh& mesh, std::uint32_t corner) {
    return mesh.triangles[corner / 3][corner % 3];
}

}  // namespace

EdgeTopology build_edge_topology(const Mesh& mesh) {
    const std::size_t m = mesh.face_count();
    std::vector<HalfEdge> half(3 * m);
    for (std::size_t f = 0; f < m; ++f) {
        const Triangle& t = mesh.triangles[f];
        for (std::uint32_t i = 0; i < 3; ++i) {
            const std::uint64_t a = t[i];
            const std::uint64_t b = t[(i + 1) % 3];
            half[3 * f + i] = {std::min(a, b) << 32 | std::max(a, b),
                               static_cast<std::uint32_t>(3 * f + i)};
        }
    }
    std::sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
        return x.key != y.key ? x.key < y.key : x.corner < y.corner;
    });

    EdgeTopology topo;
    topo.face_neighbors.assign(m, {no_index, no_index, no_index});
    for (std::size_t i = 0; i < half.size();) {
        std::size_t j = i;
        while (j < half.size() && half[j].key == half[i].key) ++j;
        const auto edge = static_cast<std::uint32_t>(topo.edges.size());
        topo.edges.push_back({static_cast<std::uint32_t>(half[i].key >> 32),
                              static_cast<std::uint32_t>(half[i].key & 0xffffffffu)});
        topo.face_counts.push_back(static_cast<std::uint32_t>(j - i));
        if (j - i == 1) {
            topo.boundary_edges.push_back(edge);
        } else if (j - i == 2) {
            const std::uint32_t c0 = half[i].corner;
            const std::uint32_t c1 = half[i + 1].corner;
            topo.face_neighbors[c0 / 3][c0 % 3] = c1 / 3;
            topo.face_neighbors[c1 / 3][c1 % 3] = c0 / 3;
            if (edge_origin(mesh, c0) == edge_origin(mesh, c1)) ++topo.inconsistent_edges;
        } else {
            topo.non_manifold_edges.push_back(edge);
        }
        i = j;
    }
    return topo;
}

VertexAdjacency build_vertex_adjacency(std::size_t vertex_count,
                                       std::span<const std::array<std::uint32_t, 2>> edges) {
    VertexAdjacency adj;
    adj.offsets.assign(vertex_count + 1, 0);
    for (const auto& e : edges) {
        ++adj.offsets[e[0] + 1];
        ++adj.offsets[e[1] + 1];
    }
    std::partial_sum(adj.offsets.begin(), adj.offsets.end(), adj.offsets.begin());
    adj.neighbors.resize(adj.offsets.back());
    std::vector<std::uint32_t> fill(adj.offsets.begin(), adj.offsets.end() - 1);
    // Edges come sorted by (a, b) with a < b, so every vertex first receives
    // its lower neighbours in ascending order, then its higher ones: each
    // list ends up sorted without a sort.
    for (const auto& e : edges) {
        adj.neighbors[fill[e[0]]++] = e[1];
        adj.neighbors[fill[e[1]]++] = e[0];
    }
    return adj;
}

VertexAdjacency build_vertex_adjacency(const Mesh& mesh) {
    return build_vertex_adjacency(mesh.vertex_count(), build_edge_topology(mesh).edges);
}

namespace {

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

}  // namespace

Components find_components(const Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    std::vector<std::uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<bool> used(n, false);
    for (const Triangle& t : mesh.triangles) {
        for (std::uint32_t v : t) used[v] = true;
        for (int i = 1; i < 3; ++i) {
            const std::uint32_t a = find_root(parent, t[0]);
            const std::uint32_t b = find_root(parent, t[i]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    Components c;
    c.vertex_component.assign(n, no_index);
    std::vector<std::uint32_t> id_of_root(n, no_index);
    for (std::uint32_t v = 0; v < n; ++v) {
        if (!used[v]) {
            ++c.isolated_vertices;
            continue;
        }
        const std::uint32_t r = find_root(parent, v);
        if (id_of_root[r] == no_index) id_of_root[r] = static_cast<std::uint32_t>(c.count++);
        c.vertex_component[v] = id_of_root[r];
    }
    return c;
}

}  // namespace dfm::mesh
