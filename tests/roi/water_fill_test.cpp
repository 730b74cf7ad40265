#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "deform/mesh_model.hpp"
#include "roi/water_fill.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

roi::SurfaceView view_of(const deform::MeshModel& m) {
    return {m.mesh.positions, m.mesh.triangles, &m.vertex_neighbors, m.vertex_face_offsets,
            m.vertex_faces};
}

roi::WaterFill fill(const deform::MeshModel& m, std::uint32_t first, std::uint32_t last) {
    roi::WaterFill out;
    const Status s = roi::water_fill(view_of(m), first, last, out);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return out;
}

// Every vertex strictly on first's side of the plane through `last`: the
// answer when that side of the surface is connected.
std::vector<std::uint32_t> near_side(const mesh::Mesh& m, std::uint32_t first, std::uint32_t last) {
    const glm::dvec3 n = glm::normalize(m.positions[last] - m.positions[first]);
    std::vector<std::uint32_t> out;
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v) {
        if (glm::dot(m.positions[v] - m.positions[last], n) < 0.0) out.push_back(v);
    }
    return out;
}

// The limb bent into an arch: two straight legs of length 3 standing at
// x = ±1, joined by a half circle of radius 1 over the origin.
mesh::Mesh make_arch() {
    const double pi = std::acos(-1.0);
    const double leg = 3.0;
    mesh::Mesh m = test::make_limb(12, 100, 0.1, 2.0 * leg + pi);
    for (glm::dvec3& p : m.positions) {
        // The tube's centre line and its outward normal at arc length p.y.
        glm::dvec3 centre, normal;
        if (p.y < leg) {
            centre = {1.0, p.y - leg, 0.0};
            normal = {1.0, 0.0, 0.0};
        } else if (p.y <= leg + pi) {
            const double a = p.y - leg;
            centre = {std::cos(a), std::sin(a), 0.0};
            normal = centre;
        } else {
            centre = {-1.0, leg + pi - p.y, 0.0};
            normal = {-1.0, 0.0, 0.0};
        }
        p = centre + p.x * normal + glm::dvec3(0.0, 0.0, p.z);
    }
    return m;
}

std::uint32_t nearest_vertex(const mesh::Mesh& m, glm::dvec3 q) {
    std::uint32_t best = 0;
    for (std::uint32_t v = 1; v < m.vertex_count(); ++v) {
        if (glm::length(m.positions[v] - q) < glm::length(m.positions[best] - q)) best = v;
    }
    return best;
}

}  // namespace

TEST_CASE("water_fill: a tilted plane across a limb takes the limb below it") {
    const auto model = deform::build_mesh_model(test::make_limb(16, 20, 0.1, 1.0));
    // first: the bottom cap's centre; last: a side vertex on ring 8.
    const std::uint32_t last = 1 + 8 * 16 + 3;
    const roi::WaterFill w = fill(model, 0, last);
    CHECK(w.vertices == near_side(model.mesh, 0, last));
    CHECK(w.vertices.size() > 16 * 6);
    CHECK(w.diagnosis.loops == 1);
    CHECK(w.diagnosis.bounded_by_last_loop);
    CHECK_FALSE(w.diagnosis.suspect);
}

TEST_CASE("water_fill: a vertex exactly on the plane counts as far") {
    const int segments = 16;
    const int rings = 20;
    const auto model = deform::build_mesh_model(test::make_limb(segments, rings, 0.1, 1.0));
    // last: the top cap's centre; the plane y = 1 holds the whole top ring.
    const auto top = static_cast<std::uint32_t>(model.mesh.vertex_count() - 1);
    const roi::WaterFill w = fill(model, 0, top);
    CHECK(w.vertices.size() == model.mesh.vertex_count() - segments - 1);
    for (std::uint32_t v : w.vertices) CHECK(model.mesh.positions[v].y < 1.0);
    CHECK(w.diagnosis.loops == 1);
    // `last` has no neighbour on the near side: the nearest crossing decides.
    CHECK(w.diagnosis.bounded_by_last_loop);
    CHECK(w.diagnosis.suspect);  // more than half the mesh
}

// The plane through `last` perpendicular to the chord from `first` leaves the
// sphere's centre on first's side, so on a sphere the fill always takes more
// than a hemisphere: one loop at `last`, yet suspect.
TEST_CASE("water_fill: an icosphere region is the side holding first, and suspect") {
    const auto model = deform::build_mesh_model(test::make_icosphere(3));
    const std::uint32_t first = nearest_vertex(model.mesh, {0.0, 1.0, 0.0});
    const std::uint32_t last = nearest_vertex(model.mesh, {std::sin(1.0), std::cos(1.0), 0.0});
    const roi::WaterFill w = fill(model, first, last);
    CHECK(w.vertices == near_side(model.mesh, first, last));
    CHECK(w.diagnosis.loops == 1);
    CHECK(w.diagnosis.bounded_by_last_loop);
    CHECK(2 * w.vertices.size() > model.mesh.vertex_count());
    CHECK(w.diagnosis.suspect);
}

TEST_CASE("water_fill: a plane cutting both legs of an arch is two loops, suspect") {
    const auto model = deform::build_mesh_model(make_arch());
    // first: the top of the arch; last: on the outside of the right leg. The
    // tilted plane through last also cuts the left leg lower down.
    const std::uint32_t first = nearest_vertex(model.mesh, {0.0, 1.1, 0.0});
    const std::uint32_t last = nearest_vertex(model.mesh, {1.1, -1.5, 0.0});
    const roi::WaterFill w = fill(model, first, last);
    CHECK(w.diagnosis.loops == 2);
    CHECK(w.diagnosis.bounded_by_last_loop);
    CHECK(w.diagnosis.suspect);
    // The region runs down both legs.
    double lowest_left = 0.0;
    for (std::uint32_t v : w.vertices) {
        if (model.mesh.positions[v].x < 0.0) {
            lowest_left = std::min(lowest_left, model.mesh.positions[v].y);
        }
    }
    CHECK(lowest_left < -2.0);
}

// From the foot of the right leg with last on the left leg, the tilted plane
// also crosses the arch's bend: the fill stops there, at one loop that is
// not the one through last.
TEST_CASE("water_fill: a region not bounded by the loop at last is suspect") {
    const auto model = deform::build_mesh_model(make_arch());
    const std::uint32_t first = nearest_vertex(model.mesh, {1.1, -2.9, 0.0});
    const std::uint32_t last = nearest_vertex(model.mesh, {-1.1, -2.0, 0.0});
    const roi::WaterFill w = fill(model, first, last);
    CHECK(w.diagnosis.loops == 1);
    CHECK(2 * w.vertices.size() < model.mesh.vertex_count());
    CHECK_FALSE(w.diagnosis.bounded_by_last_loop);
    CHECK(w.diagnosis.suspect);
}

TEST_CASE("water_fill: the fill is deterministic and never crosses the plane") {
    const auto model = deform::build_mesh_model(test::make_icosphere(4));
    const roi::WaterFill a = fill(model, 10, 500);
    const roi::WaterFill b = fill(model, 10, 500);
    CHECK(a.vertices == b.vertices);
    const auto& p = model.mesh.positions;
    const glm::dvec3 n = glm::normalize(p[500] - p[10]);
    std::vector<std::uint8_t> in(p.size(), 0);
    for (std::uint32_t v : a.vertices) in[v] = 1;
    for (std::uint32_t v : a.vertices) {
        CHECK(glm::dot(p[v] - p[500], n) < 0.0);
        // A neighbour left out lies on or beyond the plane.
        for (std::uint32_t w : model.vertex_neighbors.of(v)) {
            if (!in[w]) CHECK(glm::dot(p[w] - p[500], n) >= 0.0);
        }
    }
}

TEST_CASE("water_fill: bad input is named") {
    const auto model = deform::build_mesh_model(test::make_icosphere(1));
    roi::WaterFill w;
    Status s = roi::water_fill(view_of(model), 5, 5, w);
    CHECK(s.code() == Errc::invalid_argument);
    CHECK(s.message().find("same vertex 5") != std::string::npos);
    s = roi::water_fill(view_of(model), 1000, 5, w);
    CHECK(s.code() == Errc::out_of_range);
    CHECK(s.message().find("first vertex 1000") != std::string::npos);
    s = roi::water_fill(view_of(model), 1, 4000, w);
    CHECK(s.message().find("last vertex 4000") != std::string::npos);
    mesh::Mesh twin = test::make_icosphere(1);
    twin.positions[3] = twin.positions[4];
    const auto twin_model = deform::build_mesh_model(twin);
    s = roi::water_fill(view_of(twin_model), 3, 4, w);
    CHECK(s.message().find("region line") != std::string::npos);
    roi::SurfaceView no_adjacency = view_of(model);
    no_adjacency.neighbors = nullptr;
    CHECK(roi::water_fill(no_adjacency, 1, 2, w).code() == Errc::invalid_argument);
}
