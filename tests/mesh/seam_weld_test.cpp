#include <doctest/doctest.h>

#include <algorithm>
#include <set>
#include <tuple>

#include "mesh/seam_weld.hpp"
#include "mesh/summary.hpp"
#include "support/gltf_builder.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;
using dfm::mesh::Mesh;

namespace {

// A unit cube as a renderer stores it with a UV seam on every edge: four
// copies per face, 24 vertices, each corner in three copies.
Mesh seamed_cube() {
    Mesh m;
    const int faces[6][4][3] = {
        {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},
        {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}};
    for (const auto& f : faces) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const auto& c : f) m.positions.push_back(glm::dvec3(c[0], c[1], c[2]));
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
    }
    return m;
}

std::set<std::tuple<double, double, double>> position_set(const Mesh& m) {
    std::set<std::tuple<double, double, double>> out;
    for (const auto& p : m.positions) out.insert({p.x, p.y, p.z});
    return out;
}

}  // namespace

TEST_CASE("seam weld: a cube split at every edge welds to a closed manifold of 8 vertices") {
    const Mesh split = seamed_cube();
    Mesh surface;
    mesh::SeamWeld weld;
    mesh::weld_seams(split.positions, split.triangles, {}, surface, weld);
    CHECK(surface.vertex_count() == 8);
    CHECK(surface.face_count() == 12);
    const mesh::MeshSummary s = mesh::summarize(surface);
    CHECK(s.closed);
    CHECK(s.non_manifold_edges == 0);
    CHECK(s.components == 1);
    CHECK(weld.host_vertex_count() == 24);
    CHECK(weld.splits());
    for (std::uint32_t sv = 0; sv < 8; ++sv) {
        const auto copies = weld.copies_of(sv);
        CHECK(copies.size() == 3);
        CHECK(std::is_sorted(copies.begin(), copies.end()));
        for (std::uint32_t h : copies) {
            CHECK(weld.surface_of[h] == sv);
            CHECK(split.positions[h] == surface.positions[sv]);
        }
        // Surface vertices come in the order of their lowest copy.
        if (sv > 0) CHECK(weld.lowest_copy(sv - 1) < weld.lowest_copy(sv));
    }
    for (std::size_t t = 0; t < surface.face_count(); ++t) {
        for (int c = 0; c < 3; ++c) {
            CHECK(weld.surface_of[split.triangles[weld.host_face_of[t]][c]] ==
                  surface.triangles[t][c]);
        }
    }
}

TEST_CASE("seam weld: a sphere with every corner split gets its own vertices back") {
    const Mesh sphere = test::make_icosphere(2);
    const Mesh split = test::split_corners(sphere, [](std::size_t) { return true; });
    REQUIRE(split.vertex_count() > 2 * sphere.vertex_count());
    Mesh surface;
    mesh::SeamWeld weld;
    mesh::weld_seams(split.positions, split.triangles, {}, surface, weld);
    CHECK(surface.vertex_count() == sphere.vertex_count());
    CHECK(position_set(surface) == position_set(sphere));
    CHECK(mesh::summarize(surface).closed);
}

TEST_CASE("seam weld: two tetrahedra touching at one position stay two vertices there") {
    Mesh m;
    const glm::dvec3 tip(0, 0, 0);
    const auto add_tetra = [&](double side) {
        const auto b = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(tip);
        m.positions.push_back({side, 0, 0});
        m.positions.push_back({side, side, 0});
        m.positions.push_back({side, 0, side});
        // Outward winding does not matter to the weld; closed does.
        m.triangles.push_back({b, b + 1, b + 2});
        m.triangles.push_back({b, b + 3, b + 1});
        m.triangles.push_back({b, b + 2, b + 3});
        m.triangles.push_back({b + 1, b + 3, b + 2});
    };
    add_tetra(1.0);
    add_tetra(-1.0);
    Mesh surface;
    mesh::SeamWeld weld;
    mesh::weld_seams(m.positions, m.triangles, {}, surface, weld);
    CHECK(surface.vertex_count() == 8);
    CHECK(weld.surface_of[0] != weld.surface_of[4]);
    const mesh::MeshSummary s = mesh::summarize(surface);
    CHECK(s.non_manifold_edges == 0);
    CHECK(s.components == 2);
    CHECK(s.closed);
}

TEST_CASE("seam weld: none keeps every copy, tolerance joins copies a little apart") {
    Mesh split = seamed_cube();
    Mesh surface;
    mesh::SeamWeld weld;
    mesh::weld_seams(split.positions, split.triangles, {mesh::WeldMode::none, 0.0}, surface, weld);
    CHECK(surface.vertex_count() == 24);
    CHECK_FALSE(weld.splits());

    for (std::size_t v = 0; v < split.vertex_count(); v += 4) split.positions[v].x += 1e-7;
    mesh::weld_seams(split.positions, split.triangles, {}, surface, weld);
    CHECK(surface.vertex_count() > 8);
    mesh::weld_seams(split.positions, split.triangles, {mesh::WeldMode::tolerance, 1e-6}, surface,
                     weld);
    CHECK(surface.vertex_count() == 8);
    CHECK(mesh::summarize(surface).closed);
}
