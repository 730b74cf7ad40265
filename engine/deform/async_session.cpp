#include "deform/async_session.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "core/memory_bytes.hpp"
#include "core/stopwatch.hpp"

namespace dfm::deform {

// A word at a time, not a byte: the multiplications are one chain, which
// over bytes was a visible share of every large frame's publication.
std::uint64_t frame_checksum(std::span<const glm::dvec3> positions) {
    std::uint64_t hash = 14695981039346656037ull;
    for (const glm::dvec3& p : positions) {
        hash = (hash ^ std::bit_cast<std::uint64_t>(p.x)) * 1099511628211ull;
        hash = (hash ^ std::bit_cast<std::uint64_t>(p.y)) * 1099511628211ull;
        hash = (hash ^ std::bit_cast<std::uint64_t>(p.z)) * 1099511628211ull;
    }
    return hash;
}

Status AsyncSession::create(const MeshModel& model, std::span<const std::uint32_t> roi,
                            std::span<const std::uint32_t> handle_vertices, Setup setup,
                            Start start, jobs::Scheduler& scheduler,
                            std::unique_ptr<AsyncSession>& out) {
    out.reset();
    if (!setup) return Status(Errc::invalid_argument, "no set-up given");
    try {
        std::unique_ptr<AsyncSession> s(new AsyncSession(model, scheduler));
        s->setup_ = std::move(setup);
        s->handle_vertices_.assign(handle_vertices.begin(), handle_vertices.end());
        s->moving_.assign(roi.begin(), roi.end());
        s->queued_targets_.resize(s->handle_vertices_.size());
        s->run_targets_.resize(s->handle_vertices_.size());
        s->first_generation_ = start.first_generation;
        s->next_generation_ = std::max(start.first_generation, start.submitted_through) + 1;
        s->cancelled_through_ = s->next_generation_ - 1;
        // The start frame has a slot of its own, sized here; the set-up
        // sizes the others, so no later publish allocates.
        Frame& first = s->frames_[start_slot];
        s->size_frame(first);
        s->write_frame(first, start.first_generation, SolveReport{}, Errc::ok, false, true);
        s->newest_generation_ = start.first_generation;
        s->newest_finished_ = start.first_generation;
        s->on_frame_ = std::move(start.on_frame);
        s->record_memory();
        if (scheduler.closed()) {
            // Never started: nothing to report to on_frame.
            s->set_up_ran_ = true;
            return Status(Errc::cancelled,
                          "the context that would run the session's work was destroyed");
        }
        out = std::move(s);
        return Status::ok();
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, "out of memory while starting the session");
    }
}

void AsyncSession::begin() {
    // Closed since create: the set-up ends as one the closing scheduler
    // found in line.
    if (!scheduler_.post(*this)) run(Slice{.closing = true});
}

AsyncSession::~AsyncSession() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        has_queued_ = false;
        cancelled_through_ = next_generation_ - 1;
        interrupt_.store(true, std::memory_order_release);
        stop_setup_.store(true, std::memory_order_relaxed);
    }
    scheduler_.withdraw(*this);
    if (set_up_ran_) return;
    // Destroyed while its set-up waited in line: reported as a set-up that
    // was stopped, as one stopped part way is. Without memory for the frame
    // there is no report; the session goes all the same.
    try {
        std::lock_guard<std::mutex> solving(solve_mutex_);
        finish_set_up(Status(Errc::cancelled, "the session was destroyed before its set-up ran"),
                      nullptr);
    } catch (...) {
    }
}

Status AsyncSession::submit(std::span<const glm::dvec3> targets,
                            std::unique_lock<std::mutex>& staging, std::uint64_t& generation) {
    generation = 0;
    std::uint64_t queued = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!setup_status_) return setup_status_;
        std::copy(targets.begin(), targets.end(), queued_targets_.begin());
        has_queued_ = true;
        queued_generation_ = next_generation_++;
        queued = queued_generation_;
    }
    staging.unlock();
    if (!scheduler_.post(*this)) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (queued_generation_ == queued) has_queued_ = false;
        cancelled_through_ = std::max(cancelled_through_, queued);
        return Status(Errc::cancelled,
                      "the context that runs this session's work was destroyed; solve on the "
                      "calling thread instead");
    }
    generation = queued;
    return Status::ok();
}

void AsyncSession::cancel() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        has_queued_ = false;
        cancelled_through_ = next_generation_ - 1;
        interrupt_.store(true, std::memory_order_release);
    }
    frame_ready_.notify_all();
    // A scheduled run holds solve_mutex_ for the whole of a solve, not during the set-up.
    std::lock_guard<std::mutex> idle(solve_mutex_);
}

template <class Done>
bool AsyncSession::wait_until(Done&& done, jobs::Clock::time_point deadline) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (scheduler_.mode() != jobs::Mode::host_stepped) {
        // wait_until converts the deadline for the system, which overflows for "forever".
        if (deadline == jobs::Clock::time_point::max()) {
            frame_ready_.wait(lock, done);
            return true;
        }
        return frame_ready_.wait_until(lock, deadline, done);
    }
    // No thread runs the work: the waiting thread runs it, first in line
    // first, until what it waits for is done. Another thread may be solving
    // meanwhile (stepping, or a synchronous solve): its frames wake the wait.
    constexpr std::chrono::milliseconds recheck{1};
    while (!done()) {
        const auto now = jobs::Clock::now();
        if (now >= deadline) return false;
        lock.unlock();
        const bool ran = scheduler_.step_one(deadline);
        lock.lock();
        if (!ran) frame_ready_.wait_until(lock, std::min(deadline, now + recheck), done);
    }
    return true;
}

bool AsyncSession::wait_until_set_up() {
    wait_until([&] { return !preparing_; }, jobs::Clock::time_point::max());
    return setup_status().is_ok();
}

Status AsyncSession::solve_now(std::span<const glm::dvec3> targets, std::uint64_t& generation) {
    generation = 0;
    if (!wait_until_set_up()) return setup_status();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        has_queued_ = false;
        generation = next_generation_++;
        interrupt_.store(true, std::memory_order_release);
    }
    return solve_and_publish(targets, generation, nullptr, jobs::Clock::time_point::max());
}

AsyncSession::WaitResult AsyncSession::wait(std::uint64_t generation,
                                            std::chrono::nanoseconds timeout) {
    // Generations up to the start frame's are the set-up's: ready once it ends.
    const auto cancelled = [&] {
        return generation > first_generation_ && generation <= cancelled_through_;
    };
    const auto finished = [&] { return !preparing_ && newest_finished_ >= generation; };
    const auto deadline = timeout == std::chrono::nanoseconds::max()
                              ? jobs::Clock::time_point::max()
                              : jobs::Clock::now() + timeout;
    wait_until([&] { return finished() || cancelled(); }, deadline);
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished()) return WaitResult::ready;
    return cancelled() ? WaitResult::cancelled : WaitResult::timed_out;
}

Status AsyncSession::set_stopping_rule(double tolerance, int max_iterations) {
    if (!wait_until_set_up()) return setup_status();
    std::lock_guard<std::mutex> solving(solve_mutex_);
    return session_->set_stopping_rule(tolerance, max_iterations);
}

bool AsyncSession::preparing() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return preparing_;
}

Status AsyncSession::setup_status() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return setup_status_;
}

std::uint64_t AsyncSession::newest_generation() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return newest_generation_;
}

std::uint64_t AsyncSession::submitted_generation() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return next_generation_ - 1;
}

SetupReport AsyncSession::setup_report() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return setup_report_;
}

SessionMemory AsyncSession::memory() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return memory_;
}

void AsyncSession::record_memory() {
    SessionMemory m = session_ ? session_->memory() : SessionMemory{};
    m.frames = normals_.memory_bytes();
    for (const Frame& f : frames_)
        m.frames += capacity_bytes(f.positions, f.normals, f.positions_f32, f.normals_f32);
    std::lock_guard<std::mutex> lock(mutex_);
    m.staging = capacity_bytes(moving_, handle_vertices_, queued_targets_, run_targets_);
    memory_ = m;
}

void AsyncSession::set_up() {
    Status built;
    std::unique_ptr<DeformSession> session;
    // The frames' normals are part of what the host waits for, so their
    // set-up counts in the report's set-up time.
    const auto start = std::chrono::steady_clock::now();
    double frames_ms = 0.0;
    try {
        normals_.build(model_, moving_);
        normals_built_ = true;
        // Only the start frame can be read while the set-up runs.
        for (int slot = 0; slot < start_slot; ++slot) size_frame(frames_[slot]);
        frames_ms = ms_since(start);
        record_memory();
        built = setup_(session, &stop_setup_);
        if (built && !session) built = Status(Errc::internal, "the set-up made no session");
    } catch (const std::bad_alloc&) {
        built = Status(Errc::out_of_memory, "out of memory while setting up the edit");
    } catch (const std::exception& e) {
        built = Status(Errc::internal, std::string("the set-up failed: ") + e.what());
    } catch (...) {
        built = Status(Errc::internal, "the set-up failed with an unknown exception");
    }
    setup_ = nullptr;
    std::lock_guard<std::mutex> solving(solve_mutex_);
    SetupReport report;
    if (built) {
        session_ = std::move(session);
        report = session_->setup_report();
        report.setup_ms += frames_ms;
    }
    finish_set_up(built, built ? &report : nullptr);
}

void AsyncSession::finish_set_up(const Status& status, const SetupReport* report) {
    std::uint64_t generation = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        setup_status_ = status;
        if (report != nullptr) setup_report_ = *report;
        generation = first_generation_;
        // Targets queued meanwhile hear of the failure through their frame.
        if (!status && has_queued_) {
            generation = queued_generation_;
            has_queued_ = false;
        }
    }
    publish(generation, SolveReport{.converged = status.is_ok()}, status.code(), false, true);
}

jobs::Task::Outcome AsyncSession::run(const Slice& slice) {
    // Nothing may escape a run: it runs on a thread of the context's or of
    // the host's, and an exception there would end the host.
    try {
        if (slice.closing) {
            close_out();
        } else if (!set_up_ran_) {
            set_up_ran_ = true;
            set_up();
        } else {
            return solve_queued(slice.deadline);
        }
    } catch (...) {
        // Only publishing an outcome can throw here (out of memory); a
        // set-up that could not publish refuses work as if it had failed.
        std::lock_guard<std::mutex> lock(mutex_);
        if (preparing_) {
            preparing_ = false;
            // A short message: std::string keeps it without allocating.
            setup_status_ = Status(Errc::out_of_memory, "out of memory");
        }
    }
    frame_ready_.notify_all();
    // Targets queued during the set-up wait for the next run.
    std::lock_guard<std::mutex> lock(mutex_);
    return has_queued_ && !slice.closing ? Outcome::more : Outcome::done;
}

jobs::Task::Outcome AsyncSession::solve_queued(jobs::Clock::time_point deadline) {
    std::uint64_t generation = 0;
    bool paused = false;
    try {
        // A solve stopped at the last run's deadline goes on first; one
        // that cancel stopped meanwhile ends at once.
        if (resume_and_publish(deadline, generation, paused)) {
            if (paused) return Outcome::paused;
            std::lock_guard<std::mutex> lock(mutex_);
            return has_queued_ ? Outcome::more : Outcome::done;
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!has_queued_) return Outcome::done;
            std::swap(queued_targets_, run_targets_);
            generation = queued_generation_;
            has_queued_ = false;
            interrupt_.store(false, std::memory_order_release);
        }
        // The targets were checked when they were queued; a breakdown is
        // published as the frame's status.
        static_cast<void>(solve_and_publish(run_targets_, generation, &interrupt_, deadline));
        std::lock_guard<std::mutex> solving(solve_mutex_);
        if (session_ && session_->paused()) return Outcome::paused;
    } catch (const std::bad_alloc&) {
        publish_failure(generation, Errc::out_of_memory);
    } catch (...) {
        publish_failure(generation, Errc::internal);
    }
    return Outcome::done;
}

void AsyncSession::close_out() {
    if (!set_up_ran_) {
        set_up_ran_ = true;
        std::lock_guard<std::mutex> solving(solve_mutex_);
        finish_set_up(Status(Errc::cancelled,
                             "the context that would run the set-up was destroyed before it ran"),
                      nullptr);
        return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    has_queued_ = false;
    cancelled_through_ = next_generation_ - 1;
}

Status AsyncSession::solve_and_publish(std::span<const glm::dvec3> targets,
                                       std::uint64_t generation, const std::atomic<bool>* interrupt,
                                       jobs::Clock::time_point deadline) {
    std::lock_guard<std::mutex> solving(solve_mutex_);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (generation <= last_solved_ || generation <= cancelled_through_) return Status::ok();
    }
    last_solved_ = generation;
    if (Status s = session_->set_targets(targets); !s) return s;
    return run_and_publish(generation, interrupt, deadline, false);
}

bool AsyncSession::resume_and_publish(jobs::Clock::time_point deadline, std::uint64_t& generation,
                                      bool& paused) {
    std::lock_guard<std::mutex> solving(solve_mutex_);
    // No session: the set-up failed, and no solve ever ran.
    if (!session_ || !session_->paused()) return false;
    generation = last_solved_;
    static_cast<void>(run_and_publish(generation, &interrupt_, deadline, true));
    paused = session_->paused();
    return true;
}

Status AsyncSession::run_and_publish(std::uint64_t generation, const std::atomic<bool>* interrupt,
                                     jobs::Clock::time_point deadline, bool resume) {
    DeformSession::Control control;
    control.interrupt = interrupt;
    control.pause_after = deadline;
    if (interrupt != nullptr) {
        control.on_iteration = [&](const SolveReport& progress) {
            const auto now = std::chrono::steady_clock::now();
            if (now - last_publish_ < preview_interval) return;
            publish(generation, progress, Errc::ok, true);
        };
    }
    SolveReport report;
    const Status solved =
        resume ? session_->resume(report, &control) : session_->solve(report, &control);
    // Stopped by cancel, destroy or a synchronous solve: nothing to show;
    // stopped at the deadline: the next run goes on.
    if (report.interrupted || report.paused) return Status::ok();
    publish(generation, report, solved.code(), false);
    return solved;
}

void AsyncSession::publish_failure(std::uint64_t generation, Errc status) {
    std::lock_guard<std::mutex> solving(solve_mutex_);
    SolveReport report;
    read([&](const Frame& newest) { report = newest.report; });
    publish(generation, report, status, false);
}

const Frame* AsyncSession::acquire() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (held_ >= 0) return nullptr;
    held_ = front_;
    return &frames_[held_];
}

bool AsyncSession::holding() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return held_ >= 0;
}

bool AsyncSession::release() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (held_ < 0) return false;
    held_ = -1;
    return true;
}

std::span<const glm::dvec3> AsyncSession::current_positions() const {
    return session_ ? session_->positions() : std::span<const glm::dvec3>(model_.mesh.positions);
}

void AsyncSession::publish(std::uint64_t generation, const SolveReport& report, Errc status,
                           bool partial, bool ends_set_up) {
    int slot = 0;
    bool preparing = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        while (slot == front_ || slot == finished_ || slot == reading_ || slot == held_) ++slot;
        preparing = preparing_ && !ends_set_up;
    }
    Frame& frame = frames_[slot];
    // Already sized by the set-up (no allocation) unless it ran out of memory.
    size_frame(frame);
    write_frame(frame, generation, report, status, partial, preparing);
    record_memory();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        front_ = slot;
        // A waiter that sees the set-up ended finds its frame published.
        if (ends_set_up) preparing_ = false;
        newest_generation_ = generation;
        if (!partial) {
            finished_ = slot;
            newest_finished_ = generation;
        }
    }
    frame_ready_.notify_all();
    if (on_frame_) on_frame_(frame);
}

void AsyncSession::size_frame(Frame& frame) const {
    frame.positions.resize(moving_.size());
    frame.positions_f32.resize(3 * moving_.size());
    const std::size_t normal_count = normals_built_ ? normals_.vertices().size() : 0;
    frame.normals.resize(normal_count);
    frame.normals_f32.resize(3 * normal_count);
    frame.normal_vertices = normals_built_ ? normals_.vertices() : std::span<const std::uint32_t>();
}

void AsyncSession::write_frame(Frame& frame, std::uint64_t generation, const SolveReport& report,
                               Errc status, bool partial, bool preparing) {
    const std::span<const glm::dvec3> positions = current_positions();
    for (std::size_t i = 0; i < moving_.size(); ++i) frame.positions[i] = positions[moving_[i]];
    if (normals_built_) normals_.compute(positions, frame.normals);
    for (std::size_t i = 0; i < frame.positions.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            frame.positions_f32[3 * i + c] = static_cast<float>(frame.positions[i][c]);
        }
    }
    for (std::size_t i = 0; i < frame.normals.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            frame.normals_f32[3 * i + c] = static_cast<float>(frame.normals[i][c]);
        }
    }
    frame.generation = generation;
    frame.partial = partial;
    frame.preparing = preparing;
    frame.report = report;
    frame.status = status;
    frame.checksum = frame_checksum(frame.positions);
    last_publish_ = std::chrono::steady_clock::now();
}

}  // namespace dfm::deform
