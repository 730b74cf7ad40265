#include <doctest/doctest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::test;

namespace {

std::size_t sum_of_parts(const dfm_session_memory& m) {
    return m.factor + m.normal_matrix + m.iteration + m.frames + m.staging;
}

std::size_t sum_of_parts(const dfm_mesh_memory& m) {
    return m.rest_pose + m.adjacency + m.model + m.history + m.pick_scene;
}

// A session on the limb's vertices above `low`, its set-up ended.
dfm_session* session_above(const LimbEdit& limb, double low) {
    std::vector<std::uint32_t> region;
    for (std::uint32_t v = 0; v < limb.shape.vertex_count(); ++v) {
        if (limb.shape.positions[v].y > low) region.push_back(v);
    }
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(limb.mesh, region.data(), region.size(), &roi) == DFM_OK);
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    dfm_session_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* session = nullptr;
    REQUIRE_MESSAGE(dfm_session_create(limb.mesh, &desc, &session) == DFM_OK, last_error());
    dfm_roi_destroy(roi);
    REQUIRE(dfm_session_wait(session, 0, -1, nullptr) == DFM_OK);
    return session;
}

}  // namespace

TEST_CASE("memory: a session reports its parts, a larger ROI holds a larger factor") {
    LimbEdit limb(32, 60);
    dfm_session* small = session_above(limb, 1.4);
    dfm_session* large = session_above(limb, 0.2);
    dfm_session_memory a = {}, b = {};
    REQUIRE_MESSAGE(dfm_session_get_memory(small, &a) == DFM_OK, last_error());
    REQUIRE(dfm_session_get_memory(large, &b) == DFM_OK);
    for (const dfm_session_memory* m : {&a, &b}) {
        CHECK(m->factor > 0);
        CHECK(m->normal_matrix > 0);
        CHECK(m->iteration > 0);
        CHECK(m->frames > 0);
        CHECK(m->staging > 0);
        CHECK(m->total == sum_of_parts(*m));
    }
    CHECK(b.factor > 2 * a.factor);
    CHECK(b.normal_matrix > a.normal_matrix);
    CHECK(b.iteration > a.iteration);
    CHECK(b.frames > a.frames);
    // Five frame slots and the start frame, each with the ROI's positions in double and float.
    size_t roi_count = 0;
    dfm_frame_view view = {};
    REQUIRE(dfm_session_acquire_frame(large, &view, nullptr) == DFM_OK);
    roi_count = view.roi_count;
    REQUIRE(dfm_session_release_frame(large) == DFM_OK);
    CHECK(b.frames >= 6 * roi_count * (3 * sizeof(double) + 3 * sizeof(float)));

    // A solve keeps the arrays it was set up with: the report stays put.
    double m[16];
    translation(0.3, 0, 0, m);
    REQUIRE(dfm_session_set_group_transform(large, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(large, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(large, g, -1, nullptr) == DFM_OK);
    dfm_session_memory after = {};
    REQUIRE(dfm_session_get_memory(large, &after) == DFM_OK);
    CHECK(after.factor == b.factor);
    CHECK(after.normal_matrix == b.normal_matrix);
    CHECK(after.total == sum_of_parts(after));
    dfm_session_destroy(small);
    dfm_session_destroy(large);
}

TEST_CASE("memory: a mesh reports its parts, its history and its pick scene once built") {
    LimbEdit limb(32, 60);
    const std::size_t n = limb.shape.vertex_count();
    const std::size_t f = limb.shape.face_count();
    dfm_mesh_memory before = {};
    REQUIRE_MESSAGE(dfm_mesh_get_memory(limb.mesh, &before) == DFM_OK, last_error());
    CHECK(before.rest_pose >= n * 3 * sizeof(double) + f * 3 * sizeof(uint32_t));
    CHECK(before.adjacency > 0);
    CHECK(before.model > 0);
    CHECK(before.history == 0);
    CHECK(before.pick_scene == 0);
    CHECK(before.total == sum_of_parts(before));

    const double origin[3] = {0.0, 1.0, 5.0};
    const double direction[3] = {0.0, 0.0, -1.0};
    dfm_hit hit = {};
    REQUIRE(dfm_mesh_pick_ray(limb.mesh, origin, direction, &hit) == DFM_OK);
    REQUIRE(hit.hit);
    dfm_mesh_memory picked = {};
    REQUIRE(dfm_mesh_get_memory(limb.mesh, &picked) == DFM_OK);
    CHECK(picked.pick_scene >= n * 3 * sizeof(float) + f * 3 * sizeof(uint32_t));
    CHECK(picked.total == sum_of_parts(picked));

    // A bake keeps the earlier rest pose for undo.
    dfm_session* session = session_above(limb, 0.5);
    double m[16];
    translation(0.2, 0, 0, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(session, g, -1, nullptr) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_bake(session) == DFM_OK, last_error());
    dfm_session_destroy(session);
    dfm_mesh_memory baked = {};
    REQUIRE(dfm_mesh_get_memory(limb.mesh, &baked) == DFM_OK);
    CHECK(baked.history >= before.rest_pose + before.adjacency + before.model);
    CHECK(baked.total == sum_of_parts(baked));
}

TEST_CASE("memory: NULL, destroyed and foreign handles are refused") {
    LimbEdit limb;
    dfm_session_memory sm = {};
    dfm_mesh_memory mm = {};
    CHECK(dfm_session_get_memory(limb.session, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_get_memory(limb.mesh, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_session_get_memory(nullptr, &sm) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_mesh_get_memory(nullptr, &mm) == DFM_ERROR_INVALID_HANDLE);
    // A mesh handle is not a session handle.
    CHECK(dfm_session_get_memory(reinterpret_cast<dfm_session*>(limb.mesh), &sm) ==
          DFM_ERROR_INVALID_HANDLE);
    dfm_session* stale = limb.session;
    dfm_session_destroy(limb.session);
    limb.session = nullptr;
    sm.total = 7;
    CHECK(dfm_session_get_memory(stale, &sm) == DFM_ERROR_INVALID_HANDLE);
    CHECK(sm.total == 0);
    CHECK(message_has("dfm_session_get_memory"));
}
