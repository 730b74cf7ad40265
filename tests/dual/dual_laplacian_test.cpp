#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "dual/dual_laplacian.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

// A V with the rows of A built by dual_row, for comparison with -h n.
glm::dvec3 row_times_positions(const mesh::Mesh& m, const dual::DualLaplacian& d, std::uint32_t f) {
    const dual::DualRow row = dual::dual_row(m, d, f);
    glm::dvec3 sum(0.0);
    for (std::uint32_t k = 0; k < row.size; ++k)
        sum += row.coefficients[k] * m.positions[row.vertices[k]];
    return sum;
}

mesh::Mesh bumpy_sphere() {
    mesh::Mesh m = test::make_icosphere(3);
    for (glm::dvec3& p : m.positions) p *= 1.0 + 0.1 * std::sin(7.0 * p.x) * std::cos(5.0 * p.y);
    return m;
}

}  // namespace

TEST_CASE("dual: A V reproduces -h n, rows sum to zero, at most six vertices") {
    const mesh::Mesh m = bumpy_sphere();
    const dual::DualLaplacian d = dual::build_dual_laplacian(m, mesh::build_edge_topology(m));
    std::vector<glm::dvec3> c(m.face_count());
    dual::compute_centroids(m, m.positions, c);
    CHECK(d.boundary_faces == 0);
    CHECK(d.degenerate_rings == 0);
    for (std::uint32_t f = 0; f < m.face_count(); ++f) {
        REQUIRE(d.has_row[f]);
        const glm::dvec3 expected = -d.heights[f] * dual::ring_normal(d, c, f);
        const glm::dvec3 av = row_times_positions(m, d, f);
        CHECK(glm::length(av - expected) <= 1e-12 * std::max(1e-3, glm::length(expected)));
        CHECK(glm::length(dual::dual_coordinate(d, c, f) - expected) <= 1e-12);
        const dual::DualRow row = dual::dual_row(m, d, f);
        CHECK(row.size == 6);
        double sum = 0.0;
        for (std::uint32_t k = 0; k < row.size; ++k) sum += row.coefficients[k];
        CHECK(std::abs(sum) < 1e-14);
        CHECK(d.weights[f].x + d.weights[f].y + d.weights[f].z ==
              doctest::Approx(1.0).epsilon(1e-14));
    }
}

TEST_CASE("dual: weights and |h| are invariant under rigid motion, h scales with the mesh") {
    const mesh::Mesh m = bumpy_sphere();
    const dual::DualLaplacian d = dual::build_dual_laplacian(m, mesh::build_edge_topology(m));
    mesh::Mesh moved = m;
    const glm::dmat4 rot = glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1, 2, 3)));
    const double scale = 2.5;
    for (glm::dvec3& p : moved.positions) {
        p = scale * glm::dvec3(rot * glm::dvec4(p, 1.0)) + glm::dvec3(3, -1, 2);
    }
    const dual::DualLaplacian e =
        dual::build_dual_laplacian(moved, mesh::build_edge_topology(moved));
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        CHECK(glm::length(d.weights[f] - e.weights[f]) < 1e-9);
        CHECK(e.heights[f] == doctest::Approx(scale * d.heights[f]).epsilon(1e-9));
    }
}

TEST_CASE("dual: an open grid has rows only where faces have three neighbours, no NaN") {
    mesh::Mesh m = test::make_grid(6, 5);
    for (glm::dvec3& p : m.positions) p.z = 0.1 * std::sin(p.x) * std::cos(p.y);
    const dual::DualLaplacian d = dual::build_dual_laplacian(m, mesh::build_edge_topology(m));
    std::size_t rows = 0;
    for (std::size_t f = 0; f < m.face_count(); ++f) {
        const auto& n = d.neighbors[f];
        const bool three =
            n[0] != mesh::no_index && n[1] != mesh::no_index && n[2] != mesh::no_index;
        CHECK(bool(d.has_row[f]) == three);
        rows += d.has_row[f];
        CHECK(std::isfinite(d.heights[f]));
        CHECK(std::isfinite(d.weights[f].x + d.weights[f].y + d.weights[f].z));
    }
    CHECK(rows > 0);
    CHECK(d.boundary_faces == m.face_count() - rows);
}

TEST_CASE("dual: a 1-ring with collinear centroids has no row and no NaN") {
    // A centre triangle with a neighbour on each edge, folded so that the
    // neighbours' centroids all lie on the line y = 0.5, z = 0.
    mesh::Mesh m;
    m.positions = {{0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {-0.5, 0.5, 0}, {2.5, 0.5, 0}, {1, 1.5, 0}};
    m.triangles = {{0, 1, 2}, {1, 0, 5}, {2, 1, 4}, {0, 2, 3}};
    const dual::DualLaplacian d = dual::build_dual_laplacian(m, mesh::build_edge_topology(m));
    CHECK_FALSE(d.has_row[0]);
    CHECK(d.degenerate_rings == 1);
    std::vector<glm::dvec3> c(m.face_count());
    dual::compute_centroids(m, m.positions, c);
    CHECK(dual::ring_normal(d, c, 0) == glm::dvec3(0.0));
}

TEST_CASE("dual: the coordinate from four centroids has the bits of the one over all centroids") {
    const mesh::Mesh m = bumpy_sphere();
    const dual::DualLaplacian d = dual::build_dual_laplacian(m, mesh::build_edge_topology(m));
    std::vector<glm::dvec3> moved = m.positions;
    for (glm::dvec3& p : moved) p += glm::dvec3(0.3 * p.y * p.y, -0.2 * p.x, 0.1 * p.z * p.x);
    const std::vector<glm::dvec3>* const poses[] = {&m.positions, &moved};
    for (const std::vector<glm::dvec3>* positions : poses) {
        std::vector<glm::dvec3> centroids(m.face_count());
        dual::compute_centroids(m, *positions, centroids);
        for (std::uint32_t f = 0; f < m.face_count(); ++f) {
            const glm::dvec3 all = dual::dual_coordinate(d, centroids, f);
            const glm::dvec3 four = dual::dual_coordinate_at(m, d, *positions, f);
            REQUIRE(std::memcmp(&all, &four, sizeof all) == 0);
        }
    }
}
