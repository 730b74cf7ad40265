#pragma once

#include <chrono>

namespace dfm::jobs {

using Clock = std::chrono::steady_clock;

class Scheduler;

// One owner's work on a scheduler: a session's set-up and solves. The
// owner posts it when it has work (Scheduler::post); the scheduler runs it
// on one thread at a time, and each run does one piece (a set-up, a solve)
// and returns. Runs of different tasks take turns in the order they were
// posted, so no task starves.
class Task {
public:
    // What a run is given.
    struct Slice {
        // Host stepping's budget: a solve stops after the iteration in
        // progress once this time has passed, and resumes at the next run.
        // Clock::time_point::max(): no limit.
        Clock::time_point deadline = Clock::time_point::max();
        // The scheduler is closing (Scheduler::close): the task ends its
        // work without doing it (cancels what is queued, reports a set-up
        // that never ran) and is not run again.
        bool closing = false;
    };

    enum class Outcome {
        done,    // the piece finished; run again only when posted again
        more,    // the piece finished and more work waits: queue behind the others
        paused,  // stopped at the deadline: run next, before any other task
    };

    virtual Outcome run(const Slice& slice) = 0;

protected:
    Task() = default;
    ~Task() = default;
    Task(const Task&) = delete;
    Task& operator=(const Task&) = delete;

private:
    friend class Scheduler;
    enum class State { idle, queued, running };
    // All under the scheduler's mutex.
    State state_ = State::idle;
    bool again_ = false;  // posted while running: queued again once the run ends
    Task* previous_ = nullptr;
    Task* next_ = nullptr;
};

}  // namespace dfm::jobs
