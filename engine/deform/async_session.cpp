#include "deform/async_session.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <system_error>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

#include "core/memory_bytes.hpp"
#include "core/stopwatch.hpp"

namespace dfm::deform {

namespace {

// Names the worker for debuggers and profilers, and takes it out of wake-up
// preemption: with SCHED_BATCH a submit that wakes it does not hand the
// host's core to it (the host's frame would pay for the switch); it still
// gets its fair share of time.
void configure_worker_thread() {
#if defined(__linux__)
    pthread_setname_np(pthread_self(), "dfm-session");
    sched_param param{};
    param.sched_priority = 0;
    pthread_setschedparam(pthread_self(), SCHED_BATCH, &param);
#endif
}

}  // namespace

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
                            Start start, std::unique_ptr<AsyncSession>& out) {
    out.reset();
    if (!setup) return Status(Errc::invalid_argument, "no set-up given");
    try {
        std::unique_ptr<AsyncSession> s(new AsyncSession(model));
        s->setup_ = std::move(setup);
        s->handle_vertices_.assign(handle_vertices.begin(), handle_vertices.end());
        s->moving_.assign(roi.begin(), roi.end());
        s->queued_targets_.resize(s->handle_vertices_.size());
        s->worker_targets_.resize(s->handle_vertices_.size());
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
        s->worker_ = std::thread([raw = s.get()] { raw->run_worker(); });
        out = std::move(s);
        return Status::ok();
    } catch (const std::bad_alloc&) {
        return Status(Errc::out_of_memory, "out of memory while starting the session's worker");
    } catch (const std::system_error& e) {
        return Status(Errc::out_of_memory,
                      std::string("could not start the session's worker thread: ") + e.what());
    }
}

AsyncSession::~AsyncSession() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
        has_queued_ = false;
        cancelled_through_ = next_generation_ - 1;
        interrupt_.store(true, std::memory_order_release);
        stop_setup_.store(true, std::memory_order_relaxed);
    }
    work_ready_.notify_all();
    if (worker_.joinable()) worker_.join();
}

Status AsyncSession::check_targets(std::span<const glm::dvec3> targets) const {
    if (targets.size() != handle_vertices_.size()) {
        return Status(Errc::invalid_argument,
                      "expected " + std::to_string(handle_vertices_.size()) + " targets, got " +
                          std::to_string(targets.size()));
    }
    for (std::size_t h = 0; h < targets.size(); ++h) {
        if (!std::isfinite(targets[h].x) || !std::isfinite(targets[h].y) ||
            !std::isfinite(targets[h].z)) {
            return Status(Errc::numerical, "target " + std::to_string(h) + " (vertex " +
                                               std::to_string(handle_vertices_[h]) +
                                               ") is not finite; nothing was changed");
        }
    }
    return Status::ok();
}

Status AsyncSession::submit(std::span<const glm::dvec3> targets, std::uint64_t& generation) {
    generation = 0;
    if (Status s = check_targets(targets); !s) return s;
    bool wake = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!setup_status_) return setup_status_;
        std::copy(targets.begin(), targets.end(), queued_targets_.begin());
        has_queued_ = true;
        queued_generation_ = next_generation_++;
        generation = queued_generation_;
        wake = !worker_polling_;
    }
    if (wake) work_ready_.notify_one();
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
    // The worker holds solve_mutex_ for the whole of a solve, not during the set-up.
    std::lock_guard<std::mutex> idle(solve_mutex_);
}

bool AsyncSession::wait_until_set_up() {
    std::unique_lock<std::mutex> lock(mutex_);
    frame_ready_.wait(lock, [&] { return !preparing_; });
    return setup_status_.is_ok();
}

Status AsyncSession::solve_now(std::span<const glm::dvec3> targets, std::uint64_t& generation) {
    generation = 0;
    if (Status s = check_targets(targets); !s) return s;
    if (!wait_until_set_up()) return setup_status();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        has_queued_ = false;
        generation = next_generation_++;
        interrupt_.store(true, std::memory_order_release);
    }
    return solve_and_publish(targets, generation, nullptr);
}

AsyncSession::WaitResult AsyncSession::wait(std::uint64_t generation,
                                            std::chrono::nanoseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    // Generations up to the start frame's are the set-up's: ready once it ends.
    const auto cancelled = [&] {
        return generation > first_generation_ && generation <= cancelled_through_;
    };
    const auto finished = [&] { return !preparing_ && newest_finished_ >= generation; };
    const auto done = [&] { return finished() || cancelled(); };
    // wait_for adds the timeout to now(), which overflows for "forever".
    if (timeout == std::chrono::nanoseconds::max()) {
        frame_ready_.wait(lock, done);
    } else {
        frame_ready_.wait_for(lock, timeout, done);
    }
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
    m.staging = capacity_bytes(moving_, handle_vertices_, queued_targets_, worker_targets_);
    memory_ = m;
}

bool AsyncSession::set_up() {
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
    if (built) session_ = std::move(session);
    std::uint64_t generation = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        preparing_ = false;
        setup_status_ = built;
        if (built) {
            setup_report_ = session_->setup_report();
            setup_report_.setup_ms += frames_ms;
        }
        generation = first_generation_;
        // Targets queued meanwhile hear of the failure through their frame.
        if (!built && has_queued_) {
            generation = queued_generation_;
            has_queued_ = false;
        }
    }
    publish(generation, SolveReport{.converged = built.is_ok()}, built.code(), false);
    return built.is_ok();
}

void AsyncSession::run_worker() {
    configure_worker_thread();
    bool ready = false;
    try {
        ready = set_up();
    } catch (...) {
        // Only recording the outcome can throw here (out of memory); the
        // session then refuses work as if the set-up had failed.
        std::lock_guard<std::mutex> lock(mutex_);
        preparing_ = false;
    }
    if (!ready) {
        std::unique_lock<std::mutex> lock(mutex_);
        // A short message: std::string keeps it without allocating.
        if (setup_status_) setup_status_ = Status(Errc::out_of_memory, "out of memory");
        frame_ready_.notify_all();
        work_ready_.wait(lock, [&] { return stopping_; });
        return;
    }
    for (;;) {
        std::uint64_t generation = 0;
        {
            std::unique_lock<std::mutex> lock(mutex_);
            wait_for_work(lock);
            if (stopping_) return;
            std::swap(queued_targets_, worker_targets_);
            generation = queued_generation_;
            has_queued_ = false;
            interrupt_.store(false, std::memory_order_release);
        }
        // The targets were checked when they were queued; a breakdown is
        // published as the frame's status. Nothing may escape the thread:
        // an exception here would terminate the host.
        try {
            static_cast<void>(solve_and_publish(worker_targets_, generation, &interrupt_));
        } catch (const std::bad_alloc&) {
            publish_failure(generation, Errc::out_of_memory);
        } catch (...) {
            publish_failure(generation, Errc::internal);
        }
    }
}

void AsyncSession::wait_for_work(std::unique_lock<std::mutex>& lock) {
    const auto idle_since = std::chrono::steady_clock::now();
    while (!stopping_ && !has_queued_) {
        if (std::chrono::steady_clock::now() - idle_since < idle_poll_window) {
            worker_polling_ = true;
            work_ready_.wait_for(lock, idle_poll_interval);
        } else {
            worker_polling_ = false;
            work_ready_.wait(lock, [&] { return stopping_ || has_queued_; });
        }
    }
    worker_polling_ = false;
}

Status AsyncSession::solve_and_publish(std::span<const glm::dvec3> targets,
                                       std::uint64_t generation,
                                       const std::atomic<bool>* interrupt) {
    std::lock_guard<std::mutex> solving(solve_mutex_);
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (generation <= last_solved_ || generation <= cancelled_through_) return Status::ok();
    }
    last_solved_ = generation;
    if (Status s = session_->set_targets(targets); !s) return s;
    DeformSession::Control control;
    control.interrupt = interrupt;
    if (interrupt != nullptr) {
        control.on_iteration = [&](const SolveReport& progress) {
            const auto now = std::chrono::steady_clock::now();
            if (now - last_publish_ < preview_interval) return;
            publish(generation, progress, Errc::ok, true);
        };
    }
    SolveReport report;
    const Status solved = session_->solve(report, &control);
    // Stopped by cancel, destroy or a synchronous solve: nothing to show.
    if (report.interrupted) return Status::ok();
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
                           bool partial) {
    int slot = 0;
    bool preparing = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        while (slot == front_ || slot == finished_ || slot == reading_ || slot == held_) ++slot;
        preparing = preparing_;
    }
    Frame& frame = frames_[slot];
    // Already sized by the set-up (no allocation) unless it ran out of memory.
    size_frame(frame);
    write_frame(frame, generation, report, status, partial, preparing);
    record_memory();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        front_ = slot;
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
