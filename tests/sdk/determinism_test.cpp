#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

// The same edit through the C API with one and with two workers (the
// factor's reductions are ordered), and in memory a context kept from an
// earlier session: the frames are the same bits.
using namespace dfm::test;

namespace {

// A 20-frame drag of the limb's tip on `context`, each frame solved; the
// last frame's positions as doubles. Everything but the context is
// destroyed before it returns.
std::vector<double> drag_in(dfm_context* context, const dfm::mesh::Mesh& shape) {
    dfm_mesh* mesh = make_c_mesh(context, shape);
    std::vector<std::uint32_t> region, tip;
    for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
        if (shape.positions[v].y > 0.3) region.push_back(v);
        if (shape.positions[v].y >= 1.9) tip.push_back(v);
    }
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &roi) == DFM_OK);
    const dfm_handle_group group = {tip.data(), tip.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* session = nullptr;
    REQUIRE_MESSAGE(dfm_session_create(mesh, &desc, &session) == DFM_OK, last_error());
    for (int f = 1; f <= 20; ++f) {
        double m[16];
        translation(0.03 * f, -0.01 * f, 0.02 * f, m);
        REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
        std::uint64_t generation = 0;
        REQUIRE_MESSAGE(dfm_session_solve(session, &generation) == DFM_OK, last_error());
    }
    std::vector<double> xyz(3 * shape.vertex_count());
    const dfm_vec3_output out = {xyz.data(), shape.vertex_count(), 0, DFM_SCALAR_FLOAT64};
    dfm_frame_info info = {};
    REQUIRE(dfm_session_read_positions(session, &out, &info) == DFM_OK);
    CHECK(info.converged);
    dfm_session_destroy(session);
    dfm_roi_destroy(roi);
    dfm_mesh_destroy(mesh);
    return xyz;
}

std::vector<double> drag(const dfm::mesh::Mesh& shape, std::uint32_t workers) {
    dfm_context_desc context_desc = {};
    context_desc.worker_count = workers;
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(&context_desc, &context) == DFM_OK);
    std::vector<double> xyz = drag_in(context, shape);
    dfm_context_destroy(context);
    return xyz;
}

}  // namespace

TEST_CASE("determinism: one and two workers give the same bits through the C API") {
    // Over 8192 unknowns, so that the second worker takes part everywhere
    // it can: the analysis beside the assembly, the factor's subtrees, the
    // rotation fit's halves and the solves.
    constexpr std::size_t segments = 96;
    const dfm::mesh::Mesh shape = dfm::test::make_limb(segments, 120, 0.2, 2.0);
    std::size_t region = 0;
    for (const glm::dvec3& p : shape.positions) region += p.y > 0.3 ? 1 : 0;
    REQUIRE(region - segments > 8192);  // less its boundary ring, which stays put
    const std::vector<double> one = drag(shape, 1);
    const std::vector<double> two = drag(shape, 2);
    REQUIRE(one.size() == two.size());
    CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)) == 0);
}

TEST_CASE("determinism: a session set up in the buffers its context kept gives the same bits") {
    // The second and third edits' large arrays (stencils, factor, normal
    // matrix, Anderson's history) are the first's, freed and kept by the
    // context, still holding its numbers: nothing may read them unwritten.
    const dfm::mesh::Mesh shape = dfm::test::make_limb(48, 96, 0.2, 2.0);
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    const std::vector<double> first = drag_in(context, shape);
    const std::vector<double> second = drag_in(context, shape);
    const dfm::mesh::Mesh smaller = dfm::test::make_limb(40, 80, 0.2, 2.0);
    const std::vector<double> other = drag_in(context, smaller);
    const std::vector<double> third = drag_in(context, shape);
    dfm_context_destroy(context);
    const std::vector<double> fresh = drag(smaller, 1);
    REQUIRE(first.size() == second.size());
    REQUIRE(first.size() == third.size());
    CHECK(std::memcmp(first.data(), second.data(), first.size() * sizeof(double)) == 0);
    CHECK(std::memcmp(first.data(), third.data(), first.size() * sizeof(double)) == 0);
    REQUIRE(other.size() == fresh.size());
    CHECK(std::memcmp(other.data(), fresh.data(), other.size() * sizeof(double)) == 0);
}
