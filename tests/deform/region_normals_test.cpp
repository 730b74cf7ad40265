#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>

#include "deform/mesh_model.hpp"
#include "deform/region_normals.hpp"
#include "mesh/normals.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

TEST_CASE("region normals: the affected vertices and their normals are the whole mesh's") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_icosphere(3));
    const std::size_t n = model.mesh.vertex_count();
    // A cap of the sphere moves, given in no particular order.
    std::vector<std::uint32_t> moving;
    for (std::uint32_t v = 0; v < n; ++v) {
        if (model.mesh.positions[v].y > 0.6) moving.push_back(v);
    }
    std::reverse(moving.begin(), moving.end());
    REQUIRE(moving.size() > 10);
    REQUIRE(moving.size() < n / 2);

    deform::RegionNormals region;
    region.build(model, moving);

    // Affected: exactly the vertices of the faces that have a moving vertex.
    std::vector<std::uint8_t> is_moving(n, 0), expected(n, 0);
    for (std::uint32_t v : moving) is_moving[v] = 1;
    for (const mesh::Triangle& t : model.mesh.triangles) {
        if (is_moving[t[0]] || is_moving[t[1]] || is_moving[t[2]]) {
            for (std::uint32_t v : t) expected[v] = 1;
        }
    }
    std::vector<std::uint32_t> expected_vertices;
    for (std::uint32_t v = 0; v < n; ++v) {
        if (expected[v]) expected_vertices.push_back(v);
    }
    const std::span<const std::uint32_t> vertices = region.vertices();
    CHECK(std::vector<std::uint32_t>(vertices.begin(), vertices.end()) == expected_vertices);

    // The region twisted and stretched: each affected vertex's normal is the
    // one computed over the whole deformed mesh.
    std::vector<glm::dvec3> positions = model.mesh.positions;
    for (std::uint32_t v : moving) {
        glm::dvec3& p = positions[v];
        const double a = 0.8 * p.y;
        p = glm::dvec3(std::cos(a) * p.x - std::sin(a) * p.z, 1.5 * p.y,
                       std::sin(a) * p.x + std::cos(a) * p.z);
    }
    std::vector<glm::dvec3> normals(vertices.size());
    region.compute(positions, normals);
    std::vector<glm::dvec3> whole;
    mesh::compute_vertex_normals(model.mesh, positions, whole);
    std::size_t wrong = 0;
    for (std::size_t k = 0; k < vertices.size(); ++k) {
        if (!(glm::length(normals[k] - whole[vertices[k]]) < 1e-12)) ++wrong;
    }
    CHECK(wrong == 0);
}
