#include <doctest/doctest.h>

#include <cstring>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

// The same edit through the C API with one and with two workers: the
// factor's reductions are ordered, so the frames are the same bits.
using namespace dfm::test;

namespace {

// A 20-frame drag of the limb's tip, each frame solved; the last frame's
// positions as doubles.
std::vector<double> drag(const dfm::mesh::Mesh& shape, std::uint32_t workers) {
    dfm_context_desc context_desc = {};
    context_desc.worker_count = workers;
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(&context_desc, &context) == DFM_OK);
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
    dfm_context_destroy(context);
    return xyz;
}

}  // namespace

TEST_CASE("determinism: one and two workers give the same bits through the C API") {
    // Large enough that the factor splits into subtrees for the second worker.
    const dfm::mesh::Mesh shape = dfm::test::make_limb(48, 96, 0.2, 2.0);
    const std::vector<double> one = drag(shape, 1);
    const std::vector<double> two = drag(shape, 2);
    REQUIRE(one.size() == two.size());
    CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)) == 0);
}
