#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "core/pooled_allocator.hpp"
#include "core/status.hpp"
#include "deform/deform_session.hpp"
#include "deform/region_normals.hpp"
#include "jobs/scheduler.hpp"

namespace dfm::deform {

// One published result of an asynchronous session.
struct Frame {
    // The targets' generation it was solved for; the start state carries
    // AsyncSession::Start::first_generation.
    std::uint64_t generation = 0;
    // A preview: an iterate published while the solve for `generation` runs.
    bool partial = false;
    // The set-up (assembly, ordering, factorization) has not ended: the
    // positions are the rest pose.
    bool preparing = false;
    SolveReport report;
    // numerical: the solve broke down and `positions` are the last good ones;
    // any other failure: the set-up or the solve's run failed.
    Errc status = Errc::ok;
    // frame_checksum(positions), computed as the frame was written: a
    // reader that recomputes it knows the frame is whole.
    std::uint64_t checksum = 0;
    // The arrays come from the buffer pool: a session's frames reuse the
    // pages an earlier session's freed (fresh pages are dear in a large
    // edit's set-up). They are not zeroed when
    // sized: a slot is written whole before it is published, and the
    // set-up sizes five of them.
    UnzeroedPooledVector<glm::dvec3> positions;  // one per AsyncSession::moving() vertex
    // The vertices whose normals the edit changes, ascending, and their
    // normals; both empty before the set-up has ended (every normal is
    // then the rest pose's).
    std::span<const std::uint32_t> normal_vertices;
    UnzeroedPooledVector<glm::dvec3> normals;
    // The same in single precision, x y z per vertex, ready for a GPU upload.
    UnzeroedPooledVector<float> positions_f32;
    UnzeroedPooledVector<float> normals_f32;
};

// FNV-1a over the positions' 64-bit words (each double's bits; x, y, z of
// each vertex in order), the frame's checksum.
std::uint64_t frame_checksum(std::span<const glm::dvec3> positions);

// A DeformSession whose work runs on its context's scheduler
// (docs/design.md, "The asynchronous session"): a task (jobs/task.hpp)
// that takes turns with the other sessions' on the context's workers.
// Its first run builds the session (the set-up), so creating one never
// costs the host's frame; meanwhile frames show the rest pose, marked
// preparing, and submitted targets wait for it. The host submits targets
// without blocking; latest wins: queued targets that a newer submit replaces
// are never solved. A running solve finishes (only cancel, destroy and
// solve_now stop it early), so every finished frame is a converged result;
// while it runs, an iterate is published as a partial frame at most every
// preview_interval. Frames live in five slots: the newest, the newest
// finished (kept for a bake while previews follow it), the one a solve
// writes, one a reader copies and one a host holds as a view (and a sixth
// holds the start frame until the first is published); no side waits for
// another beyond swapping indices, no frame is ever torn, and after the
// set-up no publish allocates.
class AsyncSession final : private jobs::Task {
public:
    // Builds the session in the task's first run; what it throws is
    // reported as the set-up's failure. `stop` turns true when the
    // AsyncSession is destroyed or its scheduler closes: handed on to DeformSession::create, it
    // ends the set-up part way (Errc::cancelled, published as the set-up's frame).
    using Setup =
        std::function<Status(std::unique_ptr<DeformSession>&, const std::atomic<bool>* stop)>;
    // Called on the publishing thread (the scheduler's, or solve_now's
    // caller) after each frame is published, with no lock held.
    using FrameHook = std::function<void(const Frame&)>;

    struct Start {
        // The start frame's generation; submits count on from
        // submitted_through + 1, so generations grow across restarts.
        std::uint64_t first_generation = 0;
        std::uint64_t submitted_through = 0;
        FrameHook on_frame;
    };

    // `roi` is the region the session edits (ascending, no repeats);
    // frames carry the positions of all its vertices. `handle_vertices` are the set-up's,
    // in order. `model` and `scheduler` must outlive the AsyncSession.
    // Errc::cancelled when the scheduler is closed. The set-up waits for
    // begin().
    static Status create(const MeshModel& model, std::span<const std::uint32_t> roi,
                         std::span<const std::uint32_t> handle_vertices, Setup setup, Start start,
                         jobs::Scheduler& scheduler, std::unique_ptr<AsyncSession>& out);
    // Queues the set-up on the scheduler, which may call the host's job
    // system: so apart from create, for a caller that holds a lock while it
    // creates. A scheduler closed since create ends the set-up as cancelled
    // (published, so on_frame hears of it).
    void begin();
    // Stops the solve after the iteration in progress, or the set-up
    // through Setup's stop flag, and waits for the run to return; a set-up
    // that never ran is published as cancelled.
    ~AsyncSession();
    AsyncSession(const AsyncSession&) = delete;
    AsyncSession& operator=(const AsyncSession&) = delete;

    // Queues `targets` for the scheduler and returns their generation:
    // finite, one per handle vertex (the caller's staging checked them,
    // deform/edit.hpp). `staging` holds the caller's lock over `targets`:
    // they are copied under it, and it is let go before the scheduler hears
    // of them (which may call the host's job system). Never waits for a
    // solve or the set-up. A failed set-up or a closed scheduler is refused
    // and nothing is queued.
    Status submit(std::span<const glm::dvec3> targets, std::unique_lock<std::mutex>& staging,
                  std::uint64_t& generation);

    // Drops queued targets and stops the running solve after its current
    // iteration; returns once no solve runs (a running set-up goes on).
    // Frames already published stay; the session keeps the stopped iterate
    // as its next starting point.
    void cancel();

    // Solves `targets` (as submit's) on the calling thread, after
    // waiting for the set-up and stopping the scheduled solve, and publishes
    // the frame as a scheduled solve would: the same arithmetic, so the
    // result is bit for bit what the scheduler computes from the same state.
    Status solve_now(std::span<const glm::dvec3> targets, std::uint64_t& generation);

    enum class WaitResult { ready, cancelled, timed_out };
    // Waits until the set-up has ended and a finished (not interrupted) frame
    // of generation >= `generation` is published (ready), that generation is
    // cancelled, or `timeout` passes; nanoseconds::max() waits without
    // limit. The start frame's generation waits for the set-up alone.
    // With host stepping the wait runs the scheduler's work meanwhile.
    WaitResult wait(std::uint64_t generation, std::chrono::nanoseconds timeout);

    // Changes when later solves stop; waits for the set-up and a running
    // solve to end.
    Status set_stopping_rule(double tolerance, int max_iterations);

    // Whether the set-up still runs (false once the frame that ends it is
    // published), and how it ended once it has.
    bool preparing() const;
    Status setup_status() const;

    std::uint64_t newest_generation() const;
    std::uint64_t submitted_generation() const;

    // Calls `reader(const Frame&)` with the newest frame. Concurrent readers
    // take turns; a solve never waits for them.
    template <class Reader>
    void read(Reader&& reader) {
        std::lock_guard<std::mutex> read_lock(read_mutex_);
        int slot = 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            slot = front_;
            reading_ = slot;
        }
        reader(static_cast<const Frame&>(frames_[slot]));
        std::lock_guard<std::mutex> lock(mutex_);
        reading_ = -1;
    }

    // Calls `reader(const Frame&)` with the newest finished frame if
    // `generation` is 0 or that frame's; false (and no call) otherwise.
    template <class Reader>
    bool read_finished(std::uint64_t generation, Reader&& reader) {
        std::lock_guard<std::mutex> read_lock(read_mutex_);
        int slot = 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            slot = finished_;
            if (generation != 0 && frames_[slot].generation != generation) return false;
            reading_ = slot;
        }
        reader(static_cast<const Frame&>(frames_[slot]));
        std::lock_guard<std::mutex> lock(mutex_);
        reading_ = -1;
        return true;
    }

    // Holds the newest frame for the caller until release(): zero-copy
    // reading. Null when a frame is already held (one at a time).
    const Frame* acquire();
    // Gives the held frame back; false when none is held.
    bool release();
    bool holding() const;

    static constexpr std::chrono::milliseconds preview_interval{8};

    // The ROI, ascending (every vertex that may move is in it);
    // Frame::positions follows it.
    std::span<const std::uint32_t> moving() const { return moving_; }
    std::span<const std::uint32_t> handle_vertices() const { return handle_vertices_; }
    const MeshModel& model() const { return model_; }
    // The set-up of the session's system, once the set-up has built it
    // (zeros while it prepares or when it failed).
    SetupReport setup_report() const;

    // The bytes the session holds, as the publishing thread measured them
    // with the last frame (and as the set-up began): reading them never
    // waits for a solve. While the set-up runs, factor, system and
    // iteration are 0: the DeformSession does not exist yet.
    SessionMemory memory() const;

private:
    AsyncSession(const MeshModel& model, jobs::Scheduler& scheduler)
        : model_(model), scheduler_(scheduler) {}
    // The scheduler's run: the set-up first, then one solve of the newest
    // targets; a closing run ends the work instead.
    Outcome run(const Slice& slice) override;
    // Runs the set-up and publishes its outcome.
    void set_up();
    // Ends the set-up with `status` and publishes its frame.
    void finish_set_up(const Status& status, const SetupReport* report);
    // Goes on with a solve the last run's deadline stopped, or solves the
    // newest queued targets, and publishes the frame; paused when it
    // stopped at `deadline`.
    Outcome solve_queued(jobs::Clock::time_point deadline);
    // A closing run: what is queued is cancelled, a set-up that never ran
    // is reported as cancelled.
    void close_out();
    // Runs the scheduler's work while `done()` is false, or waits for the
    // threads that run it, until `deadline`; true once done() holds.
    template <class Done>
    bool wait_until(Done&& done, jobs::Clock::time_point deadline);
    // Solves for `targets` under solve_mutex_ and publishes the frame.
    Status solve_and_publish(std::span<const glm::dvec3> targets, std::uint64_t generation,
                             const std::atomic<bool>* interrupt, jobs::Clock::time_point deadline);
    // Resumes the paused solve, if there is one (false otherwise), under
    // solve_mutex_, and publishes its frame; `paused` when it stopped again.
    bool resume_and_publish(jobs::Clock::time_point deadline, std::uint64_t& generation,
                            bool& paused);
    // The solve (or its resumption) and the frame, under solve_mutex_.
    Status run_and_publish(std::uint64_t generation, const std::atomic<bool>* interrupt,
                           jobs::Clock::time_point deadline, bool resume);
    // The session's positions, or the rest pose before a set-up.
    std::span<const glm::dvec3> current_positions() const;
    // Publishes the session's current positions as the newest frame; with
    // `ends_set_up`, the frame that ends the set-up, which preparing()
    // turns false with.
    void publish(std::uint64_t generation, const SolveReport& report, Errc status, bool partial,
                 bool ends_set_up = false);
    // Sizes a slot's arrays for the ROI and (once built) the normals.
    void size_frame(Frame& frame) const;
    // Fills a sized slot from the session's current positions.
    void write_frame(Frame& frame, std::uint64_t generation, const SolveReport& report, Errc status,
                     bool partial, bool preparing);
    // Publishes the last good positions with a failure status, so a host
    // waiting for `generation` hears of it.
    void publish_failure(std::uint64_t generation, Errc status);
    // Waits until the set-up has ended; false when it failed.
    bool wait_until_set_up();
    // Measures the session's and the frames' bytes into memory_ (the
    // publishing thread's, which alone resizes them).
    void record_memory();

    const MeshModel& model_;
    jobs::Scheduler& scheduler_;
    Setup setup_;  // the first run's
    FrameHook on_frame_;
    std::unique_ptr<DeformSession> session_;  // set once by the set-up, before preparing_ ends
    std::vector<std::uint32_t> moving_;
    std::vector<std::uint32_t> handle_vertices_;
    RegionNormals normals_;  // built by the set-up; then only the publisher reads it
    bool normals_built_ = false;

    // Guards the queue, the generations, the set-up's outcome and the slot
    // indices; held briefly.
    mutable std::mutex mutex_;
    std::condition_variable frame_ready_;
    std::vector<glm::dvec3> queued_targets_;
    bool has_queued_ = false;
    bool preparing_ = true;
    Status setup_status_;
    std::uint64_t first_generation_ = 0;
    std::uint64_t next_generation_ = 1;
    std::uint64_t queued_generation_ = 0;
    std::uint64_t cancelled_through_ = 0;
    std::uint64_t newest_generation_ = 0;
    std::uint64_t newest_finished_ = 0;
    // Slots 0-4 take turns; the start frame has the last one to itself.
    static constexpr int start_slot = 5;
    int front_ = start_slot;
    int finished_ = start_slot;
    int reading_ = -1;
    int held_ = -1;
    std::array<Frame, 6> frames_;
    SetupReport setup_report_;             // under mutex_; filled when the set-up succeeds
    SessionMemory memory_;                 // under mutex_
    std::atomic<bool> stop_setup_{false};  // set by the destructor

    // Held by whoever runs the DeformSession: a scheduled run or solve_now.
    std::mutex solve_mutex_;
    std::uint64_t last_solved_ = 0;  // under solve_mutex_
    // The targets a scheduled solve takes from the queue; the runs' own
    // (the scheduler runs a task on one thread at a time).
    std::vector<glm::dvec3> run_targets_;
    bool set_up_ran_ = false;  // the runs' own, and the destructor's once withdrawn
    std::atomic<bool> interrupt_{false};
    std::chrono::steady_clock::time_point last_publish_;  // under solve_mutex_
    std::mutex read_mutex_;
};

}  // namespace dfm::deform
