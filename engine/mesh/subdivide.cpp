#include "mesh/subdivide.hpp"

#include <algorithm>

#include "mesh/adjacency.hpp"

namespace dfm::mesh {

namespace {

std::uint32_t find_edge(const EdgeTopology& topo, std::uint32_t a, std::uint32_t b) {
    const std::array<std::uint32_t, 2> key{std::min(a, b), std::max(a, b)};
    return static_cast<std::uint32_t>(std::lower_bound(topo.edges.begin(), topo.edges.end(), key) -
                                      topo.edges.begin());
}

double loop_beta(std::size_t valence) {
    if (valence == 3) return 3.0 / 16.0;
    return 3.0 / (8.0 * static_cast<double>(valence));
}

}  // namespace

Mesh subdivide_loop(const Mesh& mesh) {
    const EdgeTopology topo = build_edge_topology(mesh);
    const std::size_t n = mesh.vertex_count();
    const std::size_t e_count = topo.edges.size();

    std::vector<std::uint32_t> face_edges(3 * mesh.face_count());
    std::vector<glm::dvec3> opposite_sum(e_count, glm::dvec3(0.0));
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const Triangle& t = mesh.triangles[f];
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t e = find_edge(topo, t[i], t[(i + 1) % 3]);
            face_edges[3 * f + i] = e;
            opposite_sum[e] += mesh.positions[t[(i + 2) % 3]];
        }
    }

    std::vector<std::uint8_t> on_boundary(n, 0);
    std::vector<glm::dvec3> ring_sum(n, glm::dvec3(0.0));
    std::vector<std::uint32_t> valence(n, 0);
    std::vector<glm::dvec3> boundary_sum(n, glm::dvec3(0.0));
    for (std::size_t e = 0; e < e_count; ++e) {
        const auto [a, b] = topo.edges[e];
        ring_sum[a] += mesh.positions[b];
        ring_sum[b] += mesh.positions[a];
        ++valence[a];
        ++valence[b];
        if (topo.face_counts[e] != 2) {
            on_boundary[a] = on_boundary[b] = 1;
            boundary_sum[a] += mesh.positions[b];
            boundary_sum[b] += mesh.positions[a];
        }
    }

    Mesh out;
    out.positions.resize(n + e_count);
    for (std::size_t v = 0; v < n; ++v) {
        const glm::dvec3& p = mesh.positions[v];
        if (valence[v] == 0) {
            out.positions[v] = p;
        } else if (on_boundary[v]) {
            out.positions[v] = 0.75 * p + 0.125 * boundary_sum[v];
        } else {
            const double beta = loop_beta(valence[v]);
            out.positions[v] =
                (1.0 - static_cast<double>(valence[v]) * beta) * p + beta * ring_sum[v];
        }
    }
    for (std::size_t e = 0; e < e_count; ++e) {
        const glm::dvec3 ab = mesh.positions[topo.edges[e][0]] + mesh.positions[topo.edges[e][1]];
        out.positions[n + e] =
            topo.face_counts[e] == 2 ? 0.375 * ab + 0.125 * opposite_sum[e] : 0.5 * ab;
    }
    out.triangles.reserve(4 * mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        const Triangle& t = mesh.triangles[f];
        const auto ab = static_cast<std::uint32_t>(n + face_edges[3 * f]);
        const auto bc = static_cast<std::uint32_t>(n + face_edges[3 * f + 1]);
        const auto ca = static_cast<std::uint32_t>(n + face_edges[3 * f + 2]);
        out.triangles.push_back({t[0], ab, ca});
        out.triangles.push_back({t[1], bc, ab});
        out.triangles.push_back({t[2], ca, bc});
        out.triangles.push_back({ab, bc, ca});
    }
    return out;
}

}  // namespace dfm::mesh
