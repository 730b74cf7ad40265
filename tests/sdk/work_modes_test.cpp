#include <doctest/doctest.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/host_job_queue.hpp"
#include "sdk/sdk_fixture.hpp"
#include "sdk/thread_creation.hpp"
#include "support/procedural_meshes.hpp"

// Where a context's work runs (dfm_work_mode): the bundled pool, the host's
// job system, or the host's own steps. The same edits give the same bits
// in each; the host's modes start no thread; destroying the context ends
// the host's part.
using namespace dfm::test;

namespace {

// Sessions on the upper part of one limb, all on one context.
struct Crowd {
    dfm::mesh::Mesh shape = make_limb(24, 40, 0.2, 2.0);
    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_roi* roi = nullptr;
    std::vector<std::uint32_t> tip;
    std::vector<dfm_session*> sessions;

    Crowd(const dfm_context_desc& desc, std::size_t count) {
        REQUIRE_MESSAGE(dfm_context_create(&desc, &context) == DFM_OK, last_error());
        mesh = make_c_mesh(context, shape);
        roi = make_limb_roi(shape, mesh, tip);
        const dfm_handle_group group = {tip.data(), tip.size()};
        dfm_session_desc sd = {};
        sd.roi = roi;
        sd.groups = &group;
        sd.group_count = 1;
        sessions.resize(count, nullptr);
        for (dfm_session*& s : sessions) {
            REQUIRE_MESSAGE(dfm_session_create(mesh, &sd, &s) == DFM_OK, last_error());
        }
    }
    ~Crowd() {
        for (dfm_session* s : sessions) dfm_session_destroy(s);
        dfm_roi_destroy(roi);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
    }
    Crowd(const Crowd&) = delete;
    Crowd& operator=(const Crowd&) = delete;

    // Session i's tip at frame f of its own drag; the new generation.
    std::uint64_t submit(std::size_t i, int f) {
        double m[16];
        translation(0.04 * f * (1.0 + 0.1 * i), -0.01 * f, 0.02 * f * (i % 2 == 0 ? 1 : -1), m);
        REQUIRE(dfm_session_set_group_transform(sessions[i], 0, m) == DFM_OK);
        std::uint64_t g = 0;
        REQUIRE_MESSAGE(dfm_session_submit(sessions[i], &g) == DFM_OK, last_error());
        return g;
    }

    // Every session's ROI positions, in order.
    std::vector<double> roi_positions() {
        std::size_t n = 0;
        REQUIRE(dfm_roi_count(roi, &n) == DFM_OK);
        std::vector<double> all;
        for (dfm_session* s : sessions) {
            std::vector<double> xyz(3 * n);
            const dfm_vec3_output out = {xyz.data(), n, 0, DFM_SCALAR_FLOAT64};
            dfm_frame_info info = {};
            REQUIRE(dfm_session_read_roi_positions(s, &out, &info) == DFM_OK);
            CHECK(info.converged);
            CHECK_FALSE(info.partial);
            all.insert(all.end(), xyz.begin(), xyz.end());
        }
        return all;
    }
};

dfm_context_desc pool_desc(std::uint32_t workers) {
    dfm_context_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.worker_count = workers;
    return desc;
}

dfm_context_desc job_system_desc(HostJobQueue& host, std::uint32_t workers) {
    dfm_context_desc desc = pool_desc(workers);
    desc.work_mode = DFM_WORK_JOB_SYSTEM;
    desc.job_system = host.hooks();
    return desc;
}

dfm_context_desc stepped_desc() {
    dfm_context_desc desc = pool_desc(0);
    desc.work_mode = DFM_WORK_HOST_STEPPED;
    return desc;
}

constexpr std::size_t crowd_size = 4;
constexpr int drag_frames = 6;

// A drag of every session, each frame's targets waited for.
std::vector<double> drag_waiting(const dfm_context_desc& desc) {
    Crowd crowd(desc, crowd_size);
    for (int f = 1; f <= drag_frames; ++f) {
        std::vector<std::uint64_t> generations;
        for (std::size_t i = 0; i < crowd_size; ++i) generations.push_back(crowd.submit(i, f));
        for (std::size_t i = 0; i < crowd_size; ++i) {
            REQUIRE_MESSAGE(
                dfm_session_wait(crowd.sessions[i], generations[i], -1, nullptr) == DFM_OK,
                last_error());
        }
    }
    return crowd.roi_positions();
}

}  // namespace

TEST_CASE("work modes: the same edits give the same bits on the pool, a job system and steps") {
    const std::vector<double> one = drag_waiting(pool_desc(1));
    const std::vector<double> two = drag_waiting(pool_desc(2));
    CHECK(std::memcmp(one.data(), two.data(), one.size() * sizeof(double)) == 0);
    {
        HostJobQueue host(3);
        const std::vector<double> jobs = drag_waiting(job_system_desc(host, 2));
        CHECK(std::memcmp(one.data(), jobs.data(), one.size() * sizeof(double)) == 0);
    }
    // Stepped by waits, which run the work while they wait.
    const std::vector<double> waits = drag_waiting(stepped_desc());
    CHECK(std::memcmp(one.data(), waits.data(), one.size() * sizeof(double)) == 0);

    // Stepped with a budget spent at once: every step runs one iteration (or
    // one set-up), so every solve stops and resumes between iterations.
    Crowd crowd(stepped_desc(), crowd_size);
    std::size_t steps = 0;
    std::size_t runs_needed = crowd_size;  // the set-ups
    for (int f = 1; f <= drag_frames; ++f) {
        std::vector<std::uint64_t> generations;
        for (std::size_t i = 0; i < crowd_size; ++i) generations.push_back(crowd.submit(i, f));
        runs_needed += crowd_size;
        bool left = true;
        while (left) {
            REQUIRE(dfm_context_step(crowd.context, 1, &left) == DFM_OK);
            ++steps;
        }
        for (std::size_t i = 0; i < crowd_size; ++i) {
            dfm_frame_info info = {};
            REQUIRE(dfm_session_wait(crowd.sessions[i], generations[i], 0, &info) == DFM_OK);
            CHECK(info.generation == generations[i]);
        }
    }
    CHECK(steps > 2 * runs_needed);  // solves did stop part way
    const std::vector<double> stepped = crowd.roi_positions();
    CHECK(std::memcmp(one.data(), stepped.data(), one.size() * sizeof(double)) == 0);
}

TEST_CASE("work modes: with the host's job system or steps the library starts no thread") {
    HostJobQueue host(2);
    for (const bool jobs : {true, false}) {
        CAPTURE(jobs);
        const std::size_t before = threads_created();
        {
            Crowd crowd(jobs ? job_system_desc(host, 2) : stepped_desc(), crowd_size);
            for (int f = 1; f <= 2; ++f) {
                for (std::size_t i = 0; i < crowd_size; ++i) {
                    const std::uint64_t g = crowd.submit(i, f);
                    REQUIRE(dfm_session_wait(crowd.sessions[i], g, -1, nullptr) == DFM_OK);
                }
            }
            uint64_t g = 0;
            REQUIRE(dfm_session_solve(crowd.sessions[0], &g) == DFM_OK);
        }
        CHECK(threads_created() == before);
    }
    // The pool, for contrast: its threads, and only those.
    const std::size_t before = threads_created();
    {
        Crowd crowd(pool_desc(2), crowd_size);
        CHECK(threads_created() == before + 2);
    }
}

TEST_CASE("work modes: a descriptor of struct_size 0, the 0.2 layout, keeps its mode") {
    // The pool: its threads, and no stepping.
    dfm_context_desc pool = {};
    pool.worker_count = 2;
    std::size_t before = threads_created();
    {
        Crowd crowd(pool, 1);
        CHECK(threads_created() == before + 2);
        CHECK(dfm_context_step(crowd.context, 0, nullptr) == DFM_ERROR_UNSUPPORTED);
    }

    // The host's job system runs the work, and the library starts no thread.
    HostJobQueue host(2);
    dfm_context_desc jobs = {};
    jobs.worker_count = 2;
    jobs.work_mode = DFM_WORK_JOB_SYSTEM;
    jobs.job_system = host.hooks();
    before = threads_created();
    {
        Crowd crowd(jobs, crowd_size);
        for (std::size_t i = 0; i < crowd_size; ++i) {
            const std::uint64_t g = crowd.submit(i, 1);
            REQUIRE(dfm_session_wait(crowd.sessions[i], g, -1, nullptr) == DFM_OK);
        }
        while (host.outstanding() > 0) std::this_thread::yield();
        CHECK(host.jobs_run() >= 2 * crowd_size);  // the set-ups and the solves
    }
    CHECK(threads_created() == before);
    dfm_context* context = reinterpret_cast<dfm_context*>(0x1);
    jobs.job_system = {};
    CHECK(dfm_context_create(&jobs, &context) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("job_system.enqueue is NULL"));
    CHECK(context == nullptr);

    // Stepped: the work runs inside the steps alone.
    dfm_context_desc stepped = {};
    stepped.work_mode = DFM_WORK_HOST_STEPPED;
    before = threads_created();
    {
        Crowd crowd(stepped, crowd_size);
        std::vector<std::uint64_t> generations;
        for (std::size_t i = 0; i < crowd_size; ++i) generations.push_back(crowd.submit(i, 1));
        for (std::size_t i = 0; i < crowd_size; ++i) {
            CHECK(dfm_session_wait(crowd.sessions[i], generations[i], 0, nullptr) ==
                  DFM_ERROR_BUSY);
        }
        bool left = true;
        while (left) REQUIRE(dfm_context_step(crowd.context, 0, &left) == DFM_OK);
        for (std::size_t i = 0; i < crowd_size; ++i) {
            CHECK(dfm_session_wait(crowd.sessions[i], generations[i], 0, nullptr) == DFM_OK);
        }
    }
    CHECK(threads_created() == before);
    stepped.worker_count = 2;
    CHECK(dfm_context_create(&stepped, &context) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("DFM_WORK_HOST_STEPPED"));
}

TEST_CASE("work modes: destroying the context ends the host's part, and no job runs after") {
    HostJobQueue host(2);
    for (const bool jobs : {true, false}) {
        CAPTURE(jobs);
        Crowd crowd(jobs ? job_system_desc(host, 2) : stepped_desc(), crowd_size);
        for (dfm_session* s : crowd.sessions)
            REQUIRE(dfm_session_wait(s, 0, -1, nullptr) == DFM_OK);
        std::vector<std::uint64_t> generations;
        for (std::size_t i = 0; i < crowd_size; ++i) generations.push_back(crowd.submit(i, 1));
        dfm_context_destroy(crowd.context);
        crowd.context = nullptr;
        // Every job handed over has done its part (its dfm_job_run may still
        // be returning), and none waits.
        CHECK(host.waiting() == 0);
        while (host.outstanding() > 0) std::this_thread::yield();
        const std::size_t jobs_run = host.jobs_run();
        for (std::size_t i = 0; i < crowd_size; ++i) {
            const dfm_result waited =
                dfm_session_wait(crowd.sessions[i], generations[i], -1, nullptr);
            CHECK((waited == DFM_OK || waited == DFM_ERROR_CANCELLED));
            std::uint64_t g = 0;
            CHECK(dfm_session_submit(crowd.sessions[i], &g) == DFM_ERROR_CANCELLED);
            CHECK(g == 0);
            CHECK(message_has("destroyed"));
            REQUIRE_MESSAGE(dfm_session_solve(crowd.sessions[i], &g) == DFM_OK, last_error());
            CHECK(g > generations[i]);
        }
        CHECK(host.jobs_run() == jobs_run);
    }
}

TEST_CASE("work modes: a set-up that had not run when the context went reports it was cancelled") {
    HostJobQueue host(0);  // holds the jobs: nothing runs until run_held()
    Crowd crowd(job_system_desc(host, 1), 2);
    std::atomic<bool> destroyed{false};
    std::thread destroyer([&] {
        dfm_context_destroy(crowd.context);
        destroyed = true;
    });
    // The set-ups are cancelled at once; destroy waits for the job out.
    while (host.outstanding() == 0) std::this_thread::yield();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK_FALSE(destroyed.load());
    host.run_held();
    destroyer.join();
    crowd.context = nullptr;
    for (dfm_session* s : crowd.sessions) {
        dfm_frame_info info = {};
        REQUIRE(dfm_session_wait(s, 0, -1, &info) == DFM_OK);
        CHECK(info.status == DFM_ERROR_CANCELLED);
        CHECK_FALSE(info.preparing);
        CHECK(dfm_session_solve(s, nullptr) == DFM_ERROR_CANCELLED);
    }
}

TEST_CASE("work modes: sessions destroyed while their jobs are queued or running") {
    HostJobQueue host(2);
    Crowd crowd(job_system_desc(host, 2), 0);
    const dfm_handle_group group = {crowd.tip.data(), crowd.tip.size()};
    dfm_session_desc sd = {};
    sd.roi = crowd.roi;
    sd.groups = &group;
    sd.group_count = 1;
    for (int round = 0; round < 8; ++round) {
        std::vector<dfm_session*> sessions(3, nullptr);
        for (dfm_session*& s : sessions) REQUIRE(dfm_session_create(crowd.mesh, &sd, &s) == DFM_OK);
        if (round % 2 == 1) {
            for (dfm_session* s : sessions) REQUIRE(dfm_session_wait(s, 0, -1, nullptr) == DFM_OK);
        }
        for (dfm_session* s : sessions) {
            double m[16];
            translation(0.1 * round, 0, 0, m);
            REQUIRE(dfm_session_set_group_transform(s, 0, m) == DFM_OK);
            REQUIRE(dfm_session_submit(s, nullptr) == DFM_OK);
        }
        for (dfm_session* s : sessions) dfm_session_destroy(s);
    }
}

TEST_CASE("work modes: descriptors are checked, and only a stepped context steps") {
    dfm_context* context = reinterpret_cast<dfm_context*>(0x1);
    dfm_context_desc desc = pool_desc(0);
    desc.work_mode = static_cast<dfm_work_mode>(7);
    CHECK(dfm_context_create(&desc, &context) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(context == nullptr);
    CHECK(message_has("unknown mode 7"));
    desc.work_mode = DFM_WORK_JOB_SYSTEM;
    CHECK(dfm_context_create(&desc, &context) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("job_system.enqueue is NULL"));
    HostJobQueue host(0);
    desc.work_mode = DFM_WORK_POOL;
    desc.job_system = host.hooks();
    CHECK(dfm_context_create(&desc, &context) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("job_system is set"));
    desc = stepped_desc();
    desc.worker_count = 2;
    CHECK(dfm_context_create(&desc, &context) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("DFM_WORK_HOST_STEPPED"));

    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    bool left = true;
    CHECK(dfm_context_step(context, 0, &left) == DFM_ERROR_UNSUPPORTED);
    CHECK_FALSE(left);
    dfm_context_destroy(context);
    CHECK(dfm_context_step(context, 0, nullptr) == DFM_ERROR_INVALID_HANDLE);
    desc = stepped_desc();
    REQUIRE(dfm_context_create(&desc, &context) == DFM_OK);
    CHECK(dfm_context_step(context, 0, &left) == DFM_OK);
    CHECK_FALSE(left);
    dfm_context_destroy(context);
    dfm_job_run(nullptr);
}
