#include <doctest/doctest.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::test;

namespace {

struct FrameLog {
    std::mutex mutex;
    std::vector<dfm_frame_info> frames;
    std::vector<std::thread::id> threads;
    dfm_session* session = nullptr;
    std::atomic<int> wrong_session{0};

    static void on_frame(void* user, dfm_session* session, const dfm_frame_info* info) {
        auto* self = static_cast<FrameLog*>(user);
        std::lock_guard<std::mutex> lock(self->mutex);
        if (self->session != nullptr && session != self->session) ++self->wrong_session;
        self->frames.push_back(*info);
        self->threads.push_back(std::this_thread::get_id());
    }
};

struct Limb {
    dfm::mesh::Mesh shape;
    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_roi* roi = nullptr;
    std::vector<std::uint32_t> tip;

    Limb(int segments, int rings) : shape(make_limb(segments, rings, 0.2, 2.0)) {
        REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
        mesh = make_c_mesh(context, shape);
        std::vector<std::uint32_t> region;
        for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
            if (shape.positions[v].y > 0.5) region.push_back(v);
            if (shape.positions[v].y >= 1.8) tip.push_back(v);
        }
        REQUIRE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &roi) == DFM_OK);
    }
    ~Limb() {
        dfm_roi_destroy(roi);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
    }
    dfm_session_desc desc(const dfm_handle_group* group) const {
        dfm_session_desc d = {};
        d.struct_size = sizeof d;
        d.roi = roi;
        d.groups = group;
        d.group_count = 1;
        return d;
    }
};

}  // namespace

TEST_CASE("setup: create returns with the rest pose, the set-up ends on the worker") {
    Limb limb(32, 60);
    const std::size_t n = limb.shape.vertex_count();
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    FrameLog log;
    dfm_session_desc desc = limb.desc(&group);
    desc.on_frame = &FrameLog::on_frame;
    desc.on_frame_user = &log;
    dfm_session* session = nullptr;
    {
        // The callback may run before create has returned the handle.
        std::lock_guard<std::mutex> lock(log.mutex);
        REQUIRE_MESSAGE(dfm_session_create(limb.mesh, &desc, &session) == DFM_OK, last_error());
        log.session = session;
    }
    // Whether or not the set-up has ended yet, the frame is whole and at rest.
    std::vector<double> rest(3 * n), now(3 * n);
    const dfm_vec3_output out_rest = {rest.data(), n, 0, DFM_SCALAR_FLOAT64};
    const dfm_vec3_output out_now = {now.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_mesh_read_positions(limb.mesh, &out_rest) == DFM_OK);
    dfm_frame_info first = {};
    REQUIRE(dfm_session_read_positions(session, &out_now, &first) == DFM_OK);
    CHECK(now == rest);
    CHECK(first.generation == 0);
    CHECK(first.status == DFM_OK);
    if (first.preparing) CHECK_FALSE(first.converged);
    // Targets submitted now wait for the set-up and are then solved.
    double m[16];
    translation(0.3, 0, 0, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
    dfm_frame_info done = {};
    REQUIRE_MESSAGE(dfm_session_wait(session, g, -1, &done) == DFM_OK, last_error());
    CHECK_FALSE(done.preparing);
    CHECK(done.generation == g);
    CHECK(done.converged);
    dfm_session_destroy(session);

    // The worker announced the end of the set-up, then the solve, on its own thread.
    REQUIRE(log.frames.size() >= 2);
    CHECK(log.wrong_session == 0);
    CHECK(log.frames.front().generation == 0);
    CHECK_FALSE(log.frames.front().preparing);
    CHECK(log.frames.back().generation == g);
    CHECK_FALSE(log.frames.back().partial);
    for (const std::thread::id& id : log.threads) CHECK(id != std::this_thread::get_id());
}

TEST_CASE("setup: a wait that says the set-up has ended finds the frame that ends it") {
    // A host polls with a zero timeout: DFM_OK only once the newest frame
    // no longer says `preparing`, never in between.
    Limb limb(64, 120);
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    const dfm_session_desc desc = limb.desc(&group);
    int early = 0;
    for (int round = 0; round < 16; ++round) {
        dfm_session* session = nullptr;
        REQUIRE_MESSAGE(dfm_session_create(limb.mesh, &desc, &session) == DFM_OK, last_error());
        dfm_result waited = DFM_ERROR_BUSY;
        dfm_frame_info info = {};
        while (waited == DFM_ERROR_BUSY) waited = dfm_session_wait(session, 0, 0, &info);
        REQUIRE_MESSAGE(waited == DFM_OK, last_error());
        dfm_frame_info polled = {};
        REQUIRE(dfm_session_poll(session, 0, &polled, nullptr) == DFM_OK);
        if (info.preparing || polled.preparing) ++early;
        dfm_session_destroy(session);
    }
    CHECK(early == 0);
}

TEST_CASE("setup: cancel and destroy right after create, while the set-up runs") {
    Limb limb(32, 60);
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    const dfm_session_desc desc = limb.desc(&group);
    for (int round = 0; round < 6; ++round) {
        dfm_session* session = nullptr;
        REQUIRE(dfm_session_create(limb.mesh, &desc, &session) == DFM_OK);
        double m[16];
        translation(0.1 * round, 0, 0, m);
        REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
        std::uint64_t g = 0;
        REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
        if (round % 2 == 0) {
            REQUIRE(dfm_session_cancel(session) == DFM_OK);
            const dfm_result waited = dfm_session_wait(session, g, -1, nullptr);
            CHECK((waited == DFM_OK || waited == DFM_ERROR_CANCELLED));
            REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
            CHECK(dfm_session_wait(session, g, -1, nullptr) == DFM_OK);
        }
        dfm_session_destroy(session);
    }
}

TEST_CASE("setup: destroy stops a running set-up part way, which reports it was cancelled") {
    // A 25k-vertex limb, the ROI about 19k of them: the set-up runs for
    // hundreds of milliseconds; destroy comes microseconds after create.
    Limb limb(128, 200);
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    for (int round = 0; round < 3; ++round) {
        FrameLog log;
        dfm_session_desc desc = limb.desc(&group);
        desc.on_frame = &FrameLog::on_frame;
        desc.on_frame_user = &log;
        dfm_session* session = nullptr;
        REQUIRE_MESSAGE(dfm_session_create(limb.mesh, &desc, &session) == DFM_OK, last_error());
        dfm_session_destroy(session);
        // The worker published how its set-up ended before it was joined:
        // stopped by the destroy, not finished.
        REQUIRE(log.frames.size() == 1);
        CHECK(log.frames.back().status == DFM_ERROR_CANCELLED);
        CHECK_FALSE(log.frames.back().converged);
        CHECK(log.frames.back().generation == 0);
    }
}

TEST_CASE("setup: two sessions set up at once on two threads, each with its own frames") {
    Limb limb(24, 40);
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    const dfm_session_desc desc = limb.desc(&group);
    std::atomic<int> failures{0};
    auto edit = [&](double x) {
        dfm_session* session = nullptr;
        if (dfm_session_create(limb.mesh, &desc, &session) != DFM_OK) {
            ++failures;
            return;
        }
        double m[16];
        translation(x, 0, 0, m);
        std::uint64_t g = 0;
        if (dfm_session_set_group_transform(session, 0, m) != DFM_OK ||
            dfm_session_submit(session, &g) != DFM_OK ||
            dfm_session_wait(session, g, -1, nullptr) != DFM_OK) {
            ++failures;
        }
        dfm_session_destroy(session);
    };
    std::thread a(edit, 0.2), b(edit, -0.2);
    a.join();
    b.join();
    CHECK(failures == 0);
}
