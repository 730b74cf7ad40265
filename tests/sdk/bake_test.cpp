#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"

using namespace dfm::test;

namespace {

std::vector<double> rest_positions(dfm_mesh* mesh, std::size_t n) {
    std::vector<double> xyz(3 * n);
    const dfm_vec3_output out = {xyz.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_mesh_read_positions(mesh, &out) == DFM_OK);
    return xyz;
}

std::vector<double> frame_positions(dfm_session* session, std::size_t n, dfm_frame_info* info) {
    std::vector<double> xyz(3 * n);
    const dfm_vec3_output out = {xyz.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_session_read_positions(session, &out, info) == DFM_OK);
    return xyz;
}

std::uint64_t move_and_wait(dfm_session* session, double x) {
    double m[16];
    translation(x, 0, 0, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_wait(session, g, -1, nullptr) == DFM_OK, last_error());
    return g;
}

}  // namespace

TEST_CASE("bake: the newest finished frame is baked exactly, whatever is staged since") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    move_and_wait(limb.session, 0.3);
    dfm_frame_info shown = {};
    const std::vector<double> displayed = frame_positions(limb.session, n, &shown);
    // The host stages a new drag position but bakes what it showed.
    double m[16];
    translation(-0.4, 0.2, 0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_bake(limb.session) == DFM_OK, last_error());
    CHECK(rest_positions(limb.mesh, n) == displayed);
}

TEST_CASE("bake: baking the untouched start state changes no vertex") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    const std::vector<double> rest = rest_positions(limb.mesh, n);
    REQUIRE(dfm_session_wait(limb.session, 0, -1, nullptr) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_bake(limb.session) == DFM_OK, last_error());
    CHECK(rest_positions(limb.mesh, n) == rest);
    REQUIRE(dfm_session_wait(limb.session, 0, -1, nullptr) == DFM_OK);
    REQUIRE(dfm_session_bake(limb.session) == DFM_OK);
    CHECK(rest_positions(limb.mesh, n) == rest);
}

TEST_CASE("bake: a chosen generation is baked while it is the newest finished frame") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    const std::uint64_t first = move_and_wait(limb.session, 0.1);
    const std::uint64_t second = move_and_wait(limb.session, 0.25);
    const std::vector<double> displayed = frame_positions(limb.session, n, nullptr);
    CHECK(dfm_session_bake_generation(limb.session, first) == DFM_ERROR_NOT_FOUND);
    CHECK(message_has("the newest finished frame (that is generation 2)"));
    REQUIRE_MESSAGE(dfm_session_bake_generation(limb.session, second) == DFM_OK, last_error());
    CHECK(rest_positions(limb.mesh, n) == displayed);
}

TEST_CASE("bake: generations keep growing across bakes, so a host's poll sees new frames") {
    LimbEdit limb;
    std::uint64_t g = 0;
    for (int i = 1; i <= 4; ++i) g = move_and_wait(limb.session, 0.05 * i);
    REQUIRE(g == 4);
    REQUIRE(dfm_session_bake(limb.session) == DFM_OK);
    dfm_frame_info info = {};
    bool is_new = true;
    REQUIRE(dfm_session_poll(limb.session, 4, &info, &is_new) == DFM_OK);
    CHECK(info.generation == 4);
    CHECK_FALSE(is_new);
    CHECK(dfm_session_wait(limb.session, 4, -1, nullptr) == DFM_OK);
    const std::uint64_t next = move_and_wait(limb.session, 0.1);
    CHECK(next == 5);
    REQUIRE(dfm_session_poll(limb.session, 4, &info, &is_new) == DFM_OK);
    CHECK(is_new);
    CHECK(info.generation == 5);
    CHECK_FALSE(info.preparing);
    REQUIRE(dfm_session_bake(limb.session) == DFM_OK);
    CHECK(move_and_wait(limb.session, 0.1) == 6);
}

TEST_CASE("bake: undo and redo that bring a session's own pose back let it bake again") {
    LimbEdit limb;
    move_and_wait(limb.session, 0.2);
    // A second session on the same mesh bakes: the first one's pose is gone.
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    dfm_session_desc desc = {};
    desc.roi = limb.roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* other = nullptr;
    REQUIRE(dfm_session_create(limb.mesh, &desc, &other) == DFM_OK);
    move_and_wait(other, -0.2);
    REQUIRE(dfm_session_bake(other) == DFM_OK);
    CHECK(dfm_session_bake(limb.session) == DFM_ERROR_BUSY);
    CHECK(message_has("rest pose changed"));
    // Undo brings the first session's pose back: it may bake again.
    REQUIRE(dfm_mesh_undo_bake(limb.mesh) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_bake(limb.session) == DFM_OK, last_error());
    // That bake forgot the redo; an undo and a redo of its own come back to it.
    CHECK(dfm_mesh_redo_bake(limb.mesh) == DFM_ERROR_NOT_FOUND);
    REQUIRE(dfm_mesh_undo_bake(limb.mesh) == DFM_OK);
    REQUIRE(dfm_mesh_redo_bake(limb.mesh) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, 0, -1, nullptr) == DFM_OK);
    CHECK(dfm_session_bake(limb.session) == DFM_OK);
    dfm_session_destroy(other);
}

TEST_CASE("bake: a frame of identity transforms after a drag is baked as solved, near the rest") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    const std::vector<double> rest = rest_positions(limb.mesh, n);
    move_and_wait(limb.session, 0.4);
    move_and_wait(limb.session, 0.0);
    REQUIRE(dfm_session_bake(limb.session) == DFM_OK);
    const std::vector<double> baked = rest_positions(limb.mesh, n);
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(limb.mesh, &info) == DFM_OK);
    double largest = 0.0;
    for (std::size_t i = 0; i < baked.size(); ++i)
        largest = std::max(largest, std::abs(baked[i] - rest[i]));
    MESSAGE("largest move of a baked identity frame: " << largest / info.diagonal
                                                       << " of the diagonal");
    // A few tolerances (1e-5 of the diagonal) from the rest pose, not on it.
    CHECK(largest > 0.0);
    CHECK(largest < 1e-3 * info.diagonal);
    REQUIRE(dfm_mesh_undo_bake(limb.mesh) == DFM_OK);
    CHECK(rest_positions(limb.mesh, n) == rest);
}
