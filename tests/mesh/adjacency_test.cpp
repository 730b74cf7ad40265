#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "mesh/adjacency.hpp"
#include "mesh/summary.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::mesh;

namespace {

// Every face neighbour must share the edge it sits across, and the relation
// must be symmetric.
void check_face_neighbors(const Mesh& m, const EdgeTopology& topo) {
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t g = topo.face_neighbors[f][i];
            if (g == no_index) continue;
            const std::uint32_t a = m.triangles[f][i];
            const std::uint32_t b = m.triangles[f][(i + 1) % 3];
            const Triangle& t = m.triangles[g];
            CHECK(std::count(t.begin(), t.end(), a) == 1);
            CHECK(std::count(t.begin(), t.end(), b) == 1);
            const auto& back = topo.face_neighbors[g];
            CHECK(std::count(back.begin(), back.end(), static_cast<std::uint32_t>(f)) == 1);
        }
    }
}

}  // namespace

TEST_CASE("icosphere: closed, one component, Euler characteristic 2") {
    for (int k = 0; k < 4; ++k) {
        CAPTURE(k);
        const Mesh m = dfm::test::make_icosphere(k);
        const EdgeTopology topo = build_edge_topology(m);
        CHECK(m.vertex_count() - topo.edges.size() + m.face_count() == 2);
        CHECK(topo.boundary_edges.empty());
        CHECK(topo.non_manifold_edges.empty());
        CHECK(topo.inconsistent_edges == 0);
        for (const auto& n : topo.face_neighbors) {
            CHECK(std::none_of(n.begin(), n.end(), [](std::uint32_t g) { return g == no_index; }));
        }
        check_face_neighbors(m, topo);
        const MeshSummary s = summarize(m);
        CHECK(s.closed);
        CHECK(s.components == 1);
        CHECK(s.degenerate_faces == 0);
        CHECK(s.diagonal == doctest::Approx(2.0 * std::sqrt(3.0)).epsilon(0.2));
    }
}

TEST_CASE("vertex adjacency is sorted, symmetric and matches valences") {
    const Mesh m = dfm::test::make_icosphere(2);
    const VertexAdjacency adj = build_vertex_adjacency(m);
    REQUIRE(adj.offsets.size() == m.vertex_count() + 1);
    std::size_t valence5 = 0;
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v) {
        const auto n = adj.of(v);
        CHECK(std::is_sorted(n.begin(), n.end()));
        CHECK(std::adjacent_find(n.begin(), n.end()) == n.end());
        CHECK(n.size() >= 5);
        if (n.size() == 5) ++valence5;
        for (std::uint32_t w : n) {
            const auto back = adj.of(w);
            CHECK(std::binary_search(back.begin(), back.end(), v));
        }
    }
    CHECK(valence5 == 12);
}

TEST_CASE("open grid: boundary edges, border faces lack neighbours") {
    const Mesh m = dfm::test::make_grid(4, 3);
    const EdgeTopology topo = build_edge_topology(m);
    CHECK(topo.boundary_edges.size() == 2 * (4 + 3));
    CHECK(topo.non_manifold_edges.empty());
    std::size_t missing = 0;
    for (const auto& n : topo.face_neighbors) missing += std::count(n.begin(), n.end(), no_index);
    CHECK(missing == topo.boundary_edges.size());
    check_face_neighbors(m, topo);
    const MeshSummary s = summarize(m);
    CHECK_FALSE(s.closed);
    CHECK(s.diagonal == doctest::Approx(5.0));
}

TEST_CASE("limb: closed capped cylinder facing outward") {
    const Mesh m = dfm::test::make_limb(12, 8, 0.2, 2.0);
    const MeshSummary s = summarize(m);
    CHECK(s.vertices == 2 + 12 * 9);
    CHECK(s.faces == 2 * 12 * 8 + 2 * 12);
    CHECK(s.closed);
    CHECK(s.inconsistent_edges == 0);
    // Outward: the signed volume is positive.
    double volume = 0.0;
    for (const Triangle& t : m.triangles) {
        volume +=
            glm::dot(m.positions[t[0]], glm::cross(m.positions[t[1]], m.positions[t[2]])) / 6.0;
    }
    CHECK(volume > 0.0);
}

TEST_CASE("non-manifold edges, flipped faces, components and isolated vertices are counted") {
    Mesh m = dfm::test::make_grid(1, 1);
    m.positions.push_back({0.5, 0.5, 1.0});
    m.triangles.push_back({0, 3, 4});  // a third face on the diagonal edge (0, 3)
    EdgeTopology topo = build_edge_topology(m);
    REQUIRE(topo.non_manifold_edges.size() == 1);
    CHECK(topo.edges[topo.non_manifold_edges[0]] == std::array<std::uint32_t, 2>{0, 3});

    Mesh sphere = dfm::test::make_icosphere(1);
    std::swap(sphere.triangles[0][1], sphere.triangles[0][2]);
    CHECK(build_edge_topology(sphere).inconsistent_edges == 3);

    Mesh two = dfm::test::make_icosphere(0);
    const auto offset = static_cast<std::uint32_t>(two.vertex_count());
    const Mesh second = dfm::test::make_icosphere(0);
    for (const auto& p : second.positions) two.positions.push_back(p + glm::dvec3(3, 0, 0));
    for (const auto& t : second.triangles) {
        two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
    }
    two.positions.push_back({9, 9, 9});
    const Components c = find_components(two);
    CHECK(c.count == 2);
    CHECK(c.isolated_vertices == 1);
    CHECK(c.vertex_component[0] == 0);
    CHECK(c.vertex_component[offset] == 1);
    CHECK(c.vertex_component.back() == no_index);
}

TEST_CASE("degenerate faces are counted, not fatal") {
    Mesh m = dfm::test::make_grid(2, 1);
    m.positions[1] = {0.5, 0.0, 0.0};
    m.positions.push_back({1.0, 0.0, 0.0});
    m.triangles.push_back({0, 1, 6});  // collinear: zero area
    const MeshSummary s = summarize(m);
    CHECK(s.degenerate_faces == 1);
    CHECK(s.faces == 5);
}
