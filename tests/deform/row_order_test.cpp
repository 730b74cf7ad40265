// The default method's rows and unknowns in the surface's order
// (row_order.hpp): the same rows, clusters and unknowns, the rows patch by
// patch, the unknowns numbered as the rows first name them.
#include <doctest/doctest.h>

#include <map>

#include "deform/mesh_model.hpp"
#include "deform/rigidity_rows.hpp"
#include "deform/row_order.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

// A grid whose vertices are numbered out of order, as a scan's can be:
// vertex v of make_grid is vertex (v · 7919) mod n here.
mesh::Mesh scrambled_grid(int nx, int ny) {
    const mesh::Mesh grid = test::make_grid(nx, ny);
    const std::size_t n = grid.vertex_count();
    const auto renamed = [n](std::uint32_t v) {
        return static_cast<std::uint32_t>((std::uint64_t{v} * 7919u) % n);
    };
    mesh::Mesh out;
    out.positions.resize(n);
    for (std::uint32_t v = 0; v < n; ++v) out.positions[renamed(v)] = grid.positions[v];
    for (const mesh::Triangle& t : grid.triangles)
        out.triangles.push_back({renamed(t[0]), renamed(t[1]), renamed(t[2])});
    return out;
}

}  // namespace

TEST_CASE("row order: the same rows and unknowns, the rows patch by patch, the unknowns as named") {
    const deform::MeshModel model = deform::build_mesh_model(scrambled_grid(60, 40));
    REQUIRE(model.mesh.vertex_count() % 7919 != 0);
    // The unknowns: every vertex off the grid's border, numbered in the
    // host's order; two soft handles.
    deform::UnknownMap unknowns;
    unknowns.unknown_of_vertex.assign(model.mesh.vertex_count(), mesh::no_index);
    std::vector<std::uint8_t> border(model.mesh.vertex_count(), 0);
    for (std::size_t e = 0; e < model.topology.edges.size(); ++e) {
        if (model.topology.face_counts[e] == 1)
            border[model.topology.edges[e][0]] = border[model.topology.edges[e][1]] = 1;
    }
    for (std::uint32_t v = 0; v < model.mesh.vertex_count(); ++v) {
        if (border[v]) continue;
        unknowns.unknown_of_vertex[v] = static_cast<std::uint32_t>(unknowns.count());
        unknowns.vertex_of_unknown.push_back(v);
    }
    std::vector<std::uint32_t> soft = {3, 1000, 3};
    const std::vector<std::uint32_t> soft_vertices = {unknowns.vertex_of_unknown[3],
                                                      unknowns.vertex_of_unknown[1000],
                                                      unknowns.vertex_of_unknown[3]};
    const deform::UnknownMap before_unknowns = unknowns;
    deform::SystemRows rows = deform::collect_rows(model, unknowns);
    deform::RotationClusters clusters = deform::coarse_clusters(model, rows);
    REQUIRE(clusters.patch_count() > 100);
    // Each face's row as it was: its entries and its patch.
    std::map<std::uint32_t, std::size_t> row_of_face;
    for (std::size_t r = 0; r < rows.size(); ++r) row_of_face[rows.faces[r]] = r;
    REQUIRE(row_of_face.size() == rows.size());
    const deform::SystemRows before = rows;
    std::vector<std::uint32_t> patch_before(rows.size());
    for (std::size_t r = 0; r < rows.size(); ++r) patch_before[r] = clusters.patch_of(r);

    deform::order_by_patch(clusters, rows, unknowns, soft);

    // The unknowns: the same vertices, each numbered once.
    REQUIRE(unknowns.count() == before_unknowns.count());
    for (std::uint32_t v = 0; v < model.mesh.vertex_count(); ++v) {
        CHECK((unknowns.unknown_of_vertex[v] == mesh::no_index) ==
              (before_unknowns.unknown_of_vertex[v] == mesh::no_index));
    }
    for (std::uint32_t u = 0; u < unknowns.count(); ++u)
        CHECK(unknowns.unknown_of_vertex[unknowns.vertex_of_unknown[u]] == u);
    for (std::size_t k = 0; k < soft.size(); ++k)
        CHECK(unknowns.vertex_of_unknown[soft[k]] == soft_vertices[k]);
    // The rows: each face's row once, its entries as they were with its
    // unknowns renumbered, in its patch; the patches in turn, each one's
    // rows in their old order; every unknown numbered as first named.
    REQUIRE(rows.size() == before.size());
    CHECK(rows.centroid_faces == before.centroid_faces);
    std::vector<std::uint8_t> seen(rows.size(), 0);
    std::uint32_t named = 0;
    std::size_t last_old = 0;
    for (std::size_t r = 0; r < rows.size(); ++r) {
        CAPTURE(r);
        const std::size_t old = row_of_face.at(rows.faces[r]);
        CHECK(seen[old] == 0);
        seen[old] = 1;
        CHECK(clusters.patch_of(r) == patch_before[old]);
        if (r > 0) {
            CHECK(clusters.patch_of(r) >= clusters.patch_of(r - 1));
            if (clusters.patch_of(r) == clusters.patch_of(r - 1)) CHECK(old > last_old);
        }
        last_old = old;
        REQUIRE(rows.entry_offsets[r + 1] - rows.entry_offsets[r] ==
                before.entry_offsets[old + 1] - before.entry_offsets[old]);
        for (std::uint32_t e = 0; e < rows.entry_offsets[r + 1] - rows.entry_offsets[r]; ++e) {
            const deform::RowEntry& now = rows.entries[rows.entry_offsets[r] + e];
            const deform::RowEntry& was = before.entries[before.entry_offsets[old] + e];
            CHECK(now.vertex == was.vertex);
            CHECK(now.coefficient == was.coefficient);
            CHECK(now.unknown == unknowns.unknown_of_vertex[now.vertex]);
            if (now.unknown != mesh::no_index && now.unknown >= named) {
                CHECK(now.unknown == named);
                ++named;
            }
        }
    }
    CHECK(named == unknowns.count());
}
