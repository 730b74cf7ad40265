#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"

using namespace dfm::test;

namespace {

std::vector<double> read_all(dfm_session* s, dfm_frame_info* info, std::size_t n) {
    std::vector<double> xyz(3 * n);
    const dfm_vec3_output out = {xyz.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE_MESSAGE(dfm_session_read_positions(s, &out, info) == DFM_OK, last_error());
    return xyz;
}

}  // namespace

TEST_CASE("session: a synchronous edit moves the tip and keeps the base") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    dfm_frame_info info = {};
    std::vector<double> rest = read_all(limb.session, &info, n);
    CHECK(info.generation == 0);
    double m[16];
    translation(0.3, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t generation = 0;
    REQUIRE_MESSAGE(dfm_session_solve(limb.session, &generation) == DFM_OK, last_error());
    CHECK(generation == 1);
    std::vector<double> moved = read_all(limb.session, &info, n);
    CHECK(info.generation == 1);
    CHECK(info.converged);
    CHECK_FALSE(info.partial);
    CHECK(info.status == DFM_OK);
    CHECK(info.iterations >= 1);
    for (std::uint32_t v : limb.tip) {
        CHECK(moved[3 * v] == doctest::Approx(rest[3 * v] + 0.3).epsilon(0.02));
    }
    for (std::uint32_t v = 0; v < n; ++v) {
        if (limb.shape.positions[v].y < 0.45) CHECK(moved[3 * v] == rest[3 * v]);
    }
    // Normals follow: the tip cap's centre normal tilts no more than a little,
    // and each normal has unit length.
    std::vector<float> normals(3 * n);
    const dfm_vec3_output nout = {normals.data(), n, 0, DFM_SCALAR_FLOAT32};
    REQUIRE(dfm_session_read_normals(limb.session, &nout, nullptr) == DFM_OK);
    for (std::size_t v = 0; v < n; ++v) {
        const double len =
            std::sqrt(normals[3 * v] * normals[3 * v] + normals[3 * v + 1] * normals[3 * v + 1] +
                      normals[3 * v + 2] * normals[3 * v + 2]);
        CHECK(len == doctest::Approx(1.0).epsilon(1e-4));
    }
    std::size_t handles = 0;
    REQUIRE(dfm_session_get_handle_count(limb.session, &handles) == DFM_OK);
    CHECK(handles == limb.tip.size());
}

TEST_CASE("session: explicit targets through a strided float array") {
    LimbEdit limb;
    struct HostTarget {
        float xyz[3];
        float weight;
    };
    std::vector<HostTarget> targets;
    for (std::uint32_t v : limb.tip) {
        const glm::dvec3& p = limb.shape.positions[v];
        targets.push_back(
            {{static_cast<float>(p.x), static_cast<float>(p.y) + 0.25f, static_cast<float>(p.z)},
             1.0f});
    }
    const dfm_vec3_input in = {targets.data(), targets.size(), sizeof(HostTarget),
                               DFM_SCALAR_FLOAT32};
    REQUIRE(dfm_session_set_targets(limb.session, &in) == DFM_OK);
    REQUIRE(dfm_session_solve(limb.session, nullptr) == DFM_OK);
    const std::size_t n = limb.shape.vertex_count();
    dfm_frame_info info = {};
    const std::vector<double> moved = read_all(limb.session, &info, n);
    CHECK(info.converged);
    for (std::uint32_t v : limb.tip) {
        CHECK(moved[3 * v + 1] == doctest::Approx(limb.shape.positions[v].y + 0.25).epsilon(0.02));
    }
}

TEST_CASE("session: asynchronous results equal synchronous results bit for bit") {
    LimbEdit sync_edit, async_edit;
    const std::size_t n = sync_edit.shape.vertex_count();
    const double steps[][3] = {{0.1, 0, 0}, {0.2, 0.05, 0}, {0.2, 0.1, 0.1}};
    for (const auto& step : steps) {
        double m[16];
        translation(step[0], step[1], step[2], m);
        REQUIRE(dfm_session_set_group_transform(sync_edit.session, 0, m) == DFM_OK);
        REQUIRE(dfm_session_set_group_transform(async_edit.session, 0, m) == DFM_OK);
        std::uint64_t gs = 0, ga = 0;
        REQUIRE(dfm_session_solve(sync_edit.session, &gs) == DFM_OK);
        REQUIRE(dfm_session_submit(async_edit.session, &ga) == DFM_OK);
        CHECK(gs == ga);
        dfm_frame_info waited = {};
        REQUIRE_MESSAGE(dfm_session_wait(async_edit.session, ga, -1, &waited) == DFM_OK,
                        last_error());
        CHECK(waited.generation == ga);
        dfm_frame_info a = {}, s = {};
        const std::vector<double> ps = read_all(sync_edit.session, &s, n);
        const std::vector<double> pa = read_all(async_edit.session, &a, n);
        CHECK(std::memcmp(ps.data(), pa.data(), ps.size() * sizeof(double)) == 0);
        CHECK(a.checksum == s.checksum);
        CHECK(a.iterations == s.iterations);
    }
}

TEST_CASE("session: a frame read through the ROI call matches its checksum") {
    LimbEdit limb;
    double m[16];
    translation(0.0, 0.2, 0.1, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, g, -1, nullptr) == DFM_OK);
    std::size_t count = 0;
    REQUIRE(dfm_roi_count(limb.roi, &count) == DFM_OK);
    std::vector<double> xyz(3 * count);
    const dfm_vec3_output out = {xyz.data(), count, 0, DFM_SCALAR_FLOAT64};
    dfm_frame_info info = {};
    REQUIRE(dfm_session_read_roi_positions(limb.session, &out, &info) == DFM_OK);
    CHECK(info.generation == g);
    CHECK(fnv1a_words(xyz.data(), xyz.size()) == info.checksum);
    bool is_new = false;
    dfm_frame_info polled = {};
    REQUIRE(dfm_session_poll(limb.session, g - 1, &polled, &is_new) == DFM_OK);
    CHECK(is_new);
    REQUIRE(dfm_session_poll(limb.session, g, &polled, &is_new) == DFM_OK);
    CHECK_FALSE(is_new);
    const dfm_vec3_output small = {xyz.data(), count - 1, 0, DFM_SCALAR_FLOAT64};
    CHECK(dfm_session_read_roi_positions(limb.session, &small, &info) ==
          DFM_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("session: a held frame view is whole and blocks only a second hold and a bake") {
    LimbEdit limb;
    double m[16];
    translation(0.2, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, g, -1, nullptr) == DFM_OK);
    dfm_frame_view view = {};
    dfm_frame_info info = {};
    REQUIRE(dfm_session_acquire_frame(limb.session, &view, &info) == DFM_OK);
    CHECK(info.generation == g);
    std::size_t count = 0;
    REQUIRE(dfm_roi_count(limb.roi, &count) == DFM_OK);
    REQUIRE(view.roi_count == count);
    CHECK(fnv1a_words(view.roi_positions_f64, 3 * count) == info.checksum);
    std::vector<std::uint32_t> roi(count);
    REQUIRE(dfm_roi_read(limb.roi, roi.data(), count) == DFM_OK);
    CHECK(std::memcmp(roi.data(), view.roi_vertices, count * sizeof(std::uint32_t)) == 0);
    for (std::size_t i = 0; i < count; ++i) {
        CHECK(view.roi_positions[3 * i] == static_cast<float>(view.roi_positions_f64[3 * i]));
    }
    CHECK(view.normal_count > count);
    // The worker keeps publishing while the view is held.
    translation(0.3, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, g, -1, nullptr) == DFM_OK);
    CHECK(fnv1a_words(view.roi_positions_f64, 3 * count) == info.checksum);
    dfm_frame_view second = {};
    CHECK(dfm_session_acquire_frame(limb.session, &second, nullptr) == DFM_ERROR_BUSY);
    CHECK(dfm_session_bake(limb.session) == DFM_ERROR_BUSY);
    REQUIRE(dfm_session_release_frame(limb.session) == DFM_OK);
    CHECK(dfm_session_release_frame(limb.session) == DFM_ERROR_INVALID_ARGUMENT);
    REQUIRE(dfm_session_acquire_frame(limb.session, &view, &info) == DFM_OK);
    CHECK(info.generation == g);
    REQUIRE(dfm_session_release_frame(limb.session) == DFM_OK);
    CHECK(dfm_session_acquire_frame(limb.session, nullptr, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("session: the held frame is the session's: another thread may give it back") {
    LimbEdit limb;
    REQUIRE(dfm_session_wait(limb.session, 0, -1, nullptr) == DFM_OK);
    dfm_frame_view view = {};
    REQUIRE(dfm_session_acquire_frame(limb.session, &view, nullptr) == DFM_OK);
    dfm_result acquired_elsewhere = DFM_OK, released_elsewhere = DFM_ERROR_INTERNAL;
    std::thread other([&] {
        dfm_frame_view second = {};
        acquired_elsewhere = dfm_session_acquire_frame(limb.session, &second, nullptr);
        released_elsewhere = dfm_session_release_frame(limb.session);
    });
    other.join();
    CHECK(acquired_elsewhere == DFM_ERROR_BUSY);
    CHECK(released_elsewhere == DFM_OK);
    CHECK(dfm_session_release_frame(limb.session) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_session_acquire_frame(limb.session, &view, nullptr) == DFM_OK);
    CHECK(dfm_session_release_frame(limb.session) == DFM_OK);
}

TEST_CASE("session: a finite transform whose targets overflow is refused when staged") {
    LimbEdit limb;
    double m[16];
    translation(0.2, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    double huge[16];
    translation(0.0, 0.0, 0.0, huge);
    huge[0] = huge[5] = huge[10] = std::numeric_limits<double>::max();
    CHECK(dfm_session_set_group_transform(limb.session, 0, huge) == DFM_ERROR_NUMERICAL);
    CHECK(message_has("of group 0 beyond the finite numbers"));
    // Nothing was staged: the submit solves the earlier transform.
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    dfm_frame_info info = {};
    REQUIRE(dfm_session_wait(limb.session, g, -1, &info) == DFM_OK);
    CHECK(info.status == DFM_OK);
    CHECK(info.converged);
}

TEST_CASE("session: session misuse is refused with a code and a message") {
    LimbEdit limb;
    dfm_session* s = nullptr;
    const std::uint32_t outside[] = {0};  // the base's centre, below the ROI
    const dfm_handle_group bad_group = {outside, 1};
    dfm_session_desc desc = {};
    desc.roi = limb.roi;
    desc.groups = &bad_group;
    desc.group_count = 1;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("outside the ROI"));
    CHECK(s == nullptr);
    const std::uint32_t far[] = {1u << 30};
    const dfm_handle_group far_group = {far, 1};
    desc.groups = &far_group;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_OUT_OF_RANGE);
    const dfm_handle_group empty = {nullptr, 0};
    desc.groups = &empty;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_ARGUMENT);
    desc.group_count = 0;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_ARGUMENT);
    desc.roi = nullptr;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_session_create(limb.mesh, nullptr, &s) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_session_create(nullptr, &desc, &s) == DFM_ERROR_INVALID_HANDLE);
    const dfm_handle_group twice[] = {{limb.tip.data(), limb.tip.size()}, {limb.tip.data(), 1}};
    desc.roi = limb.roi;
    desc.groups = twice;
    desc.group_count = 2;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("handle group 1 entry 0"));
    CHECK(message_has("is in group 0 too"));
    const std::uint32_t repeated[] = {limb.tip[0], limb.tip[1], limb.tip[0]};
    const dfm_handle_group repeating = {repeated, 3};
    desc.groups = &repeating;
    desc.group_count = 1;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("handle group 0 entry 2"));
    CHECK(message_has("repeats entry 0 of the same group"));
    desc.groups = twice;
    desc.group_count = 1;
    desc.solver.tolerance = -1.0;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_ARGUMENT);

    double m[16];
    translation(0, 0, 0, m);
    CHECK(dfm_session_set_group_transform(limb.session, 1, m) == DFM_ERROR_OUT_OF_RANGE);
    CHECK(dfm_session_set_group_transform(limb.session, 0, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    m[13] = std::numeric_limits<double>::infinity();
    CHECK(dfm_session_set_group_transform(limb.session, 0, m) == DFM_ERROR_NUMERICAL);
    CHECK(message_has("element 13"));
    // All zeros, or a translation in the bottom row (a row-major matrix):
    // not an affine transform acting on column vectors.
    const double zero[16] = {};
    CHECK(dfm_session_set_group_transform(limb.session, 0, zero) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("must be 0 0 0 1 for an affine transform; found 0 0 0 0"));
    translation(0, 0, 0, m);
    m[3] = 0.25;
    CHECK(dfm_session_set_group_transform(limb.session, 0, m) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("found 0.25 0 0 1"));
    std::vector<float> targets(3 * limb.tip.size(), 0.f);
    dfm_vec3_input in = {targets.data(), limb.tip.size() - 1, 0, DFM_SCALAR_FLOAT32};
    CHECK(dfm_session_set_targets(limb.session, &in) == DFM_ERROR_INVALID_ARGUMENT);
    in.count = limb.tip.size();
    targets[4] = std::numeric_limits<float>::quiet_NaN();
    CHECK(dfm_session_set_targets(limb.session, &in) == DFM_ERROR_NUMERICAL);
    CHECK(dfm_session_set_targets(limb.session, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_session_wait(limb.session, 5, 0, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("never submitted"));
    dfm_solver_settings settings = {};
    settings.handle_weight = 3.0;
    CHECK(dfm_session_set_solver(limb.session, &settings) == DFM_ERROR_UNSUPPORTED);
    settings = dfm_solver_settings{};
    settings.tolerance = -2;
    CHECK(dfm_session_set_solver(limb.session, &settings) == DFM_ERROR_INVALID_ARGUMENT);
    settings.tolerance = 1e-3;
    settings.max_iterations = 3;
    CHECK(dfm_session_set_solver(limb.session, &settings) == DFM_OK);
    CHECK(dfm_session_set_solver(limb.session, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    dfm_frame_info info = {};
    CHECK(dfm_session_poll(limb.session, 0, nullptr, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    const dfm_vec3_output none = {nullptr, 1000000, 0, DFM_SCALAR_FLOAT32};
    CHECK(dfm_session_read_positions(limb.session, &none, &info) == DFM_ERROR_INVALID_ARGUMENT);

    dfm_session* gone = limb.session;
    dfm_session_destroy(gone);
    limb.session = nullptr;
    std::uint64_t g = 0;
    CHECK(dfm_session_submit(gone, &g) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_session_poll(gone, 0, &info, nullptr) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_session_cancel(gone) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_session_bake(gone) == DFM_ERROR_INVALID_HANDLE);
    dfm_session_destroy(gone);
}

TEST_CASE("session: a non-converging solve reports it and the host keeps going") {
    dfm_solver_settings solver = {};
    solver.max_iterations = 1;
    solver.tolerance = 1e-14;
    LimbEdit limb(16, 20, solver);
    double m[16];
    translation(0.5, 0, 0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_solve(limb.session, &g) == DFM_OK);
    dfm_frame_info info = {};
    REQUIRE(dfm_session_poll(limb.session, 0, &info, nullptr) == DFM_OK);
    CHECK_FALSE(info.converged);
    CHECK(info.iterations == 1);
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    CHECK(dfm_session_wait(limb.session, g, -1, &info) == DFM_OK);
}

TEST_CASE("session: cancel drops queued work and the session stays usable") {
    LimbEdit limb;
    double m[16];
    std::uint64_t g = 0;
    for (int i = 1; i <= 20; ++i) {
        translation(0.01 * i, 0, 0, m);
        REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
        REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    }
    REQUIRE(dfm_session_cancel(limb.session) == DFM_OK);
    dfm_frame_info info = {};
    REQUIRE(dfm_session_poll(limb.session, 0, &info, nullptr) == DFM_OK);
    const dfm_result waited = dfm_session_wait(limb.session, g, -1, nullptr);
    // The last generation either finished before the cancel or was cancelled.
    CHECK((waited == DFM_OK || waited == DFM_ERROR_CANCELLED));
    if (waited == DFM_ERROR_CANCELLED) CHECK(info.generation < g);
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, g, -1, &info) == DFM_OK);
    CHECK(info.generation == g);
    CHECK(info.converged);
}

TEST_CASE("session: bake and undo and redo move the rest pose and stale sessions cannot bake") {
    LimbEdit limb;
    const std::size_t n = limb.shape.vertex_count();
    std::vector<double> rest(3 * n), baked_rest(3 * n), now(3 * n);
    const dfm_vec3_output out_rest = {rest.data(), n, 0, DFM_SCALAR_FLOAT64};
    const dfm_vec3_output out_now = {now.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_rest) == DFM_OK);
    CHECK(dfm_mesh_undo_bake(limb.mesh) == DFM_ERROR_NOT_FOUND);
    double m[16];
    translation(0.3, 0, 0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, g, -1, nullptr) == DFM_OK);
    REQUIRE(dfm_session_bake(limb.session) == DFM_OK);
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(limb.mesh, &info) == DFM_OK);
    CHECK(info.bake_count == 1);
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    const std::uint32_t tip = limb.tip.front();
    CHECK(now[3 * tip] == doctest::Approx(rest[3 * tip] + 0.3).epsilon(0.02));
    baked_rest = now;
    // The session restarted on the baked pose: identity transforms, no move.
    dfm_frame_info frame = {};
    REQUIRE(dfm_session_read_positions(limb.session, &out_now, &frame) == DFM_OK);
    CHECK(now == baked_rest);
    // A second edit on top of the first.
    translation(0, 0.1, 0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    REQUIRE(dfm_session_wait(limb.session, g, -1, nullptr) == DFM_OK);
    REQUIRE(dfm_session_bake(limb.session) == DFM_OK);
    REQUIRE(dfm_mesh_undo_bake(limb.mesh) == DFM_OK);
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    CHECK(now == baked_rest);
    CHECK(dfm_session_bake(limb.session) == DFM_ERROR_BUSY);
    REQUIRE(dfm_mesh_undo_bake(limb.mesh) == DFM_OK);
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    CHECK(now == rest);
    REQUIRE(dfm_mesh_redo_bake(limb.mesh) == DFM_OK);
    REQUIRE(dfm_mesh_get_info(limb.mesh, &info) == DFM_OK);
    CHECK(info.bake_count == 1);
    CHECK(info.redo_count == 1);
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_now) == DFM_OK);
    CHECK(now == baked_rest);
    REQUIRE(dfm_mesh_redo_bake(limb.mesh) == DFM_OK);
    CHECK(dfm_mesh_redo_bake(limb.mesh) == DFM_ERROR_NOT_FOUND);
    // Picking follows the rest pose: the tip moved up by 0.1 and right by 0.3.
    const double origin[3] = {0.3, 10, 0}, down[3] = {0, -1, 0};
    dfm_hit hit = {};
    REQUIRE(dfm_mesh_pick_ray(limb.mesh, origin, down, &hit) == DFM_OK);
    CHECK(hit.hit);
    CHECK(hit.point[1] == doctest::Approx(2.1).epsilon(0.02));
}

TEST_CASE("session: destroying a session whose worker is mid-solve returns and frees it") {
    dfm_solver_settings solver = {};
    solver.tolerance = 1e-12;
    solver.max_iterations = 100000;
    LimbEdit limb(32, 60, solver);
    double m[16];
    translation(0.6, 0.3, 0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(limb.session, &g) == DFM_OK);
    dfm_session_destroy(limb.session);
    limb.session = nullptr;
}
