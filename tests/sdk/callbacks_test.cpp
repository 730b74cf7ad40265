#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/host_job_queue.hpp"
#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

// The host's callbacks that may call the library (dfm_job_system.enqueue,
// dfm_frame_ready_fn, dfm_log_fn) run with no lock of the library's held
// that a call which does not wait for the work takes: each callback here
// calls back into the objects it was called for, first from another thread
// it waits for (which a held lock would block) and then itself.
using namespace dfm::test;

namespace {

// Far longer than any of the calls takes, under the sanitizers on a busy
// machine; a call still blocked then is blocked by a lock the callback's
// thread holds.
constexpr auto patience = std::chrono::seconds(20);

// Calls a callback makes back into the library, on another thread and on
// its own; counts what blocked or failed.
class Reentry {
public:
    // At most `limit` callbacks call back (each starts a thread).
    explicit Reentry(int limit) : limit_(limit) {}
    ~Reentry() {
        for (std::thread& t : blocked_threads_) t.join();
    }
    Reentry(const Reentry&) = delete;
    Reentry& operator=(const Reentry&) = delete;

    // `calls` returns whether every call it made succeeded.
    void operator()(const std::function<bool()>& calls) {
        if (taken_.fetch_add(1) >= limit_ || blocked_ > 0) return;
        struct Done {
            std::mutex mutex;
            std::condition_variable changed;
            bool returned = false;
            bool ok = false;
        };
        auto done = std::make_shared<Done>();
        std::thread other([calls, done] {
            const bool ok = calls();
            std::lock_guard<std::mutex> lock(done->mutex);
            done->returned = true;
            done->ok = ok;
            done->changed.notify_all();
        });
        bool returned = false;
        bool ok = false;
        {
            std::unique_lock<std::mutex> lock(done->mutex);
            returned = done->changed.wait_for(lock, patience, [&] { return done->returned; });
            ok = done->ok;
        }
        if (!returned) {
            // Joined once the callback has returned and the lock is let go.
            ++blocked_;
            std::lock_guard<std::mutex> lock(mutex_);
            blocked_threads_.push_back(std::move(other));
            return;
        }
        other.join();
        if (!ok) ++failed_;
        // The same calls on the callback's own thread: only now, since with
        // a lock held they would wait for themselves.
        if (!calls()) ++failed_;
        ++completed_;
    }

    int completed() const { return completed_; }
    int blocked() const { return blocked_; }
    int failed() const { return failed_; }

private:
    const int limit_;
    std::atomic<int> taken_{0};
    std::atomic<int> completed_{0};
    std::atomic<int> blocked_{0};
    std::atomic<int> failed_{0};
    std::mutex mutex_;
    std::vector<std::thread> blocked_threads_;
};

// What a host reads or measures of a mesh from inside a callback.
bool touch_mesh(dfm_mesh* mesh) {
    dfm_mesh_info info = {};
    dfm_mesh_memory memory = {};
    return dfm_mesh_get_info(mesh, &info) == DFM_OK && dfm_mesh_get_memory(mesh, &memory) == DFM_OK;
}

// And of a session: every call that does not wait for the work.
bool touch_session(dfm_session* session, dfm_mesh* mesh) {
    dfm_frame_info info = {};
    dfm_session_memory memory = {};
    dfm_solve_report report = {};
    dfm_quality quality = {};
    std::size_t handles = 0;
    return dfm_session_poll(session, 0, &info, nullptr) == DFM_OK &&
           dfm_session_get_memory(session, &memory) == DFM_OK &&
           dfm_session_get_solve_report(session, &report, nullptr) == DFM_OK &&
           dfm_session_measure_quality(session, &quality, nullptr) == DFM_OK &&
           dfm_session_get_handle_count(session, &handles) == DFM_OK && touch_mesh(mesh);
}

// One limb edit on a context made from `desc`; the session from
// session_desc(), created by the test.
struct Edit {
    dfm::mesh::Mesh shape;
    dfm_context* context = nullptr;
    dfm_mesh* mesh = nullptr;
    dfm_roi* roi = nullptr;
    std::vector<std::uint32_t> tip;
    dfm_handle_group group = {};
    dfm_session* session = nullptr;

    Edit(const dfm_context_desc& desc, int segments, int rings)
        : shape(make_limb(segments, rings, 0.2, 2.0)) {
        REQUIRE_MESSAGE(dfm_context_create(&desc, &context) == DFM_OK, last_error());
        mesh = make_c_mesh(context, shape);
        roi = make_limb_roi(shape, mesh, tip);
        group = {tip.data(), tip.size()};
    }
    ~Edit() {
        dfm_session_destroy(session);
        dfm_roi_destroy(roi);
        dfm_mesh_destroy(mesh);
        dfm_context_destroy(context);
    }
    Edit(const Edit&) = delete;
    Edit& operator=(const Edit&) = delete;

    dfm_session_desc session_desc() const {
        dfm_session_desc d = {};
        d.struct_size = sizeof d;
        d.roi = roi;
        d.groups = &group;
        d.group_count = 1;
        return d;
    }

    // A drag of three frames, each waited for; a synchronous solve; a
    // bake, whose restart is waited for: every path on which the library
    // hands over work or publishes frames. `run_work` runs what was handed
    // over before each wait, for a host that holds its jobs. Returns the
    // generation of the last frame.
    std::uint64_t drag_solve_bake(const std::function<void()>& run_work) {
        run_work();
        REQUIRE_MESSAGE(dfm_session_wait(session, 0, -1, nullptr) == DFM_OK, last_error());
        for (int f = 1; f <= 3; ++f) {
            double m[16];
            translation(0.1 * f, 0.0, 0.05 * f, m);
            REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
            std::uint64_t g = 0;
            REQUIRE_MESSAGE(dfm_session_submit(session, &g) == DFM_OK, last_error());
            run_work();
            REQUIRE_MESSAGE(dfm_session_wait(session, g, -1, nullptr) == DFM_OK, last_error());
        }
        REQUIRE_MESSAGE(dfm_session_solve(session, nullptr) == DFM_OK, last_error());
        REQUIRE_MESSAGE(dfm_session_bake(session) == DFM_OK, last_error());
        dfm_frame_info info = {};
        REQUIRE(dfm_session_poll(session, 0, &info, nullptr) == DFM_OK);
        run_work();
        REQUIRE_MESSAGE(dfm_session_wait(session, info.generation, -1, nullptr) == DFM_OK,
                        last_error());
        return info.generation;
    }
};

// A job system whose enqueue calls back into the edit it was handed a job
// of (the mesh from the start, the session once created), then queues the
// job: for its own threads, or held until the test runs it.
struct ProbingJobSystem {
    explicit ProbingJobSystem(std::size_t threads) : queue(threads) {}

    HostJobQueue queue;
    dfm_job_system inner = queue.hooks();
    Reentry reentry{64};
    std::atomic<dfm_mesh*> mesh{nullptr};
    std::atomic<dfm_session*> session{nullptr};

    static void enqueue(void* user, dfm_job* job) {
        auto* self = static_cast<ProbingJobSystem*>(user);
        dfm_mesh* m = self->mesh;
        dfm_session* s = self->session;
        if (m != nullptr) {
            self->reentry([m, s] { return s != nullptr ? touch_session(s, m) : touch_mesh(m); });
        }
        self->inner.enqueue(self->inner.user, job);
    }
};

}  // namespace

TEST_CASE("callbacks: a job system's enqueue may call back into the edit, and wait for others") {
    // Held jobs (run by the test between calls) make every hand-over happen
    // inside the call that queues the work: create, submit, a solve's
    // loops, a bake's restart; a mesh of 8,600 unknowns makes the loops
    // split over the two workers. Two threads make the hand-overs happen
    // anywhere.
    for (const std::size_t threads : {0, 2}) {
        CAPTURE(threads);
        const bool held = threads == 0;
        // Declared first, so destroyed last: its threads run jobs until
        // the context has gone.
        ProbingJobSystem host(threads);
        dfm_context_desc desc = {};
        desc.struct_size = sizeof desc;
        desc.worker_count = 2;
        desc.work_mode = DFM_WORK_JOB_SYSTEM;
        desc.job_system = {&ProbingJobSystem::enqueue, &host};
        {
            Edit edit(desc, held ? 96 : 24, held ? 120 : 40);
            host.mesh = edit.mesh;
            const dfm_session_desc sd = edit.session_desc();
            REQUIRE_MESSAGE(dfm_session_create(edit.mesh, &sd, &edit.session) == DFM_OK,
                            last_error());
            host.session = edit.session;
            edit.drag_solve_bake([&] { host.queue.run_held(); });
            host.mesh = nullptr;
            host.session = nullptr;
        }
        CHECK(host.reentry.blocked() == 0);
        CHECK(host.reentry.failed() == 0);
        CHECK(host.reentry.completed() >= (held ? 6 : 1));
    }
}

namespace {

// An on_frame that calls back into its session.
struct ProbingFrames {
    Reentry reentry{64};
    dfm_mesh* mesh = nullptr;
    std::mutex mutex;
    std::vector<std::uint64_t> done;  // the finished frames whose callback is done

    static void on_frame(void* user, dfm_session* session, const dfm_frame_info* info) {
        auto* self = static_cast<ProbingFrames*>(user);
        dfm_mesh* m = self->mesh;
        self->reentry([session, m] { return touch_session(session, m); });
        if (info->partial) return;
        std::lock_guard<std::mutex> lock(self->mutex);
        self->done.push_back(info->generation);
    }
    std::size_t done_with(std::uint64_t generation) {
        std::lock_guard<std::mutex> lock(mutex);
        return static_cast<std::size_t>(std::count(done.begin(), done.end(), generation));
    }
};

}  // namespace

TEST_CASE("callbacks: on_frame may call back into its session, and wait for others, in each mode") {
    HostJobQueue jobs(2);
    for (const dfm_work_mode mode : {DFM_WORK_POOL, DFM_WORK_JOB_SYSTEM, DFM_WORK_HOST_STEPPED}) {
        CAPTURE(mode);
        dfm_context_desc desc = {};
        desc.struct_size = sizeof desc;
        desc.work_mode = mode;
        desc.worker_count = mode == DFM_WORK_HOST_STEPPED ? 1 : 2;
        if (mode == DFM_WORK_JOB_SYSTEM) desc.job_system = jobs.hooks();
        ProbingFrames frames;
        {
            Edit edit(desc, 24, 40);
            frames.mesh = edit.mesh;
            dfm_session_desc sd = edit.session_desc();
            sd.on_frame = &ProbingFrames::on_frame;
            sd.on_frame_user = &frames;
            REQUIRE_MESSAGE(dfm_session_create(edit.mesh, &sd, &edit.session) == DFM_OK,
                            last_error());
            const std::uint64_t last = edit.drag_solve_bake([] {});
            // A wait returns once its frame is published, maybe before the
            // frame's callback has run: destroying the session meanwhile
            // would leave the callback's calls a dead handle. The last
            // generation has two frames: the solve's, and the one that ends
            // the restarted set-up.
            while (frames.done_with(last) < 2) std::this_thread::yield();
        }
        CHECK(frames.reentry.blocked() == 0);
        CHECK(frames.reentry.failed() == 0);
        CHECK(frames.reentry.completed() >= 5);  // the set-ups, the drag, the solve
    }
}

namespace {

// An on_frame whose first preview lets the test bake, waits a while (the
// bake meanwhile stops the solve that published the preview) and then
// calls back into its session and mesh.
struct BakeDuringSolve {
    Reentry reentry{1};
    dfm_mesh* mesh = nullptr;
    std::mutex mutex;
    std::condition_variable changed;
    bool previewed = false;

    static void on_frame(void* user, dfm_session* session, const dfm_frame_info* info) {
        auto* self = static_cast<BakeDuringSolve*>(user);
        if (!info->partial) return;
        {
            std::lock_guard<std::mutex> lock(self->mutex);
            if (self->previewed) return;
            self->previewed = true;
        }
        self->changed.notify_all();
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        dfm_mesh* m = self->mesh;
        self->reentry([session, m] { return touch_session(session, m); });
    }
};

}  // namespace

TEST_CASE("callbacks: a bake stops a running solve whose on_frame calls back into the edit") {
    dfm_context_desc desc = {};
    desc.struct_size = sizeof desc;
    BakeDuringSolve frames;
    Edit edit(desc, 48, 80);
    frames.mesh = edit.mesh;
    dfm_session_desc sd = edit.session_desc();
    // A solve long enough to publish previews.
    sd.solver.tolerance = 1e-13;
    sd.solver.max_iterations = 100000;
    sd.on_frame = &BakeDuringSolve::on_frame;
    sd.on_frame_user = &frames;
    REQUIRE_MESSAGE(dfm_session_create(edit.mesh, &sd, &edit.session) == DFM_OK, last_error());
    REQUIRE(dfm_session_wait(edit.session, 0, -1, nullptr) == DFM_OK);
    double m[16];
    translation(0.6, -0.3, 0.4, m);
    REQUIRE(dfm_session_set_group_transform(edit.session, 0, m) == DFM_OK);
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(edit.session, &g) == DFM_OK);
    {
        std::unique_lock<std::mutex> lock(frames.mutex);
        frames.changed.wait(lock, [&] { return frames.previewed; });
    }
    REQUIRE_MESSAGE(dfm_session_bake(edit.session) == DFM_OK, last_error());
    CHECK(dfm_session_wait(edit.session, g, -1, nullptr) == DFM_ERROR_CANCELLED);
    CHECK(frames.reentry.blocked() == 0);
    CHECK(frames.reentry.failed() == 0);
    CHECK(frames.reentry.completed() == 1);
}

namespace {

// A log that calls back into the objects the message is about.
struct ProbingLog {
    Reentry reentry{16};
    std::atomic<dfm_mesh*> mesh{nullptr};
    std::atomic<dfm_session*> session{nullptr};
    std::atomic<int> heard{0};

    static void log(void* user, dfm_log_level, dfm_log_id, const char*) {
        auto* self = static_cast<ProbingLog*>(user);
        ++self->heard;
        dfm_mesh* m = self->mesh;
        dfm_session* s = self->session;
        self->reentry([m, s] { return s != nullptr ? touch_session(s, m) : touch_mesh(m); });
    }
};

}  // namespace

TEST_CASE("callbacks: the log may call back into the objects of the call that logs") {
    ProbingLog heard;
    dfm_context_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.log = &ProbingLog::log;
    desc.log_user = &heard;
    Edit edit(desc, 24, 40);
    heard.mesh = edit.mesh;

    // A load warning: a triangle that repeats a vertex is dropped.
    const std::vector<float> xyz = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const std::uint32_t tris[] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 2, 0, 3, 0, 0, 1};
    dfm_mesh_desc md = {};
    md.struct_size = sizeof md;
    md.positions = {xyz.data(), 4, 0, DFM_SCALAR_FLOAT32};
    md.indices = tris;
    md.triangle_count = 5;
    dfm_mesh* tetra = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(edit.context, &md, &tetra) == DFM_OK, last_error());
    dfm_mesh_destroy(tetra);
    CHECK(heard.heard == 1);

    // A synchronous solve capped before the tolerance.
    dfm_session_desc sd = edit.session_desc();
    sd.solver.max_iterations = 1;
    sd.solver.tolerance = 1e-14;
    REQUIRE_MESSAGE(dfm_session_create(edit.mesh, &sd, &edit.session) == DFM_OK, last_error());
    heard.session = edit.session;
    double m[16];
    translation(0.4, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(edit.session, 0, m) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_solve(edit.session, nullptr) == DFM_OK, last_error());
    CHECK(heard.heard == 2);

    CHECK(heard.reentry.blocked() == 0);
    CHECK(heard.reentry.failed() == 0);
    CHECK(heard.reentry.completed() == 2);
}
