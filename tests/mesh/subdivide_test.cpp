#include <doctest/doctest.h>

#include <glm/geometric.hpp>

#include "mesh/subdivide.hpp"
#include "mesh/summary.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::mesh;

TEST_CASE("Loop subdivision: four times the faces, old indices first, still closed") {
    const Mesh coarse = dfm::test::make_icosphere(1);
    const Mesh fine = subdivide_loop(coarse);
    const MeshSummary c = summarize(coarse);
    const MeshSummary f = summarize(fine);
    CHECK(f.vertices == c.vertices + c.edges);
    CHECK(f.faces == 4 * c.faces);
    CHECK(f.closed);
    CHECK(f.inconsistent_edges == 0);
    CHECK(f.vertices - f.edges + f.faces == 2);
    // Loop shrinks a sphere a little; old vertices stay where they were, radially.
    for (std::size_t v = 0; v < coarse.vertex_count(); ++v) {
        CHECK(glm::dot(glm::normalize(fine.positions[v]), coarse.positions[v]) ==
              doctest::Approx(1.0).epsilon(1e-12));
        CHECK(glm::length(fine.positions[v]) < 1.0);
        CHECK(glm::length(fine.positions[v]) > 0.8);
    }
}

TEST_CASE("Loop subdivision keeps an open grid's boundary on its border lines") {
    const Mesh fine = subdivide_loop(dfm::test::make_grid(3, 2));
    const MeshSummary s = summarize(fine);
    CHECK(s.boundary_edges == 2 * 2 * (3 + 2));
    CHECK(s.bounds.min == glm::dvec3(0.0));
    CHECK(s.bounds.max == glm::dvec3(3.0, 2.0, 0.0));
}
