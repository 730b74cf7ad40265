#pragma once

#include <cstddef>
#include <type_traits>

namespace dfm::jobs {

// The threads a data-parallel loop of the solver may use. The solver splits
// its work into tasks whose results do not depend on which thread runs
// them and combines partial results in task order, so every output is
// bit-identical whatever thread_count() is and whichever threads run the
// tasks. A context's scheduler (scheduler.hpp) is one: its workers help
// the loops of every session on it.
class WorkerPool {
public:
    virtual ~WorkerPool() = default;
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    // How many threads may run the tasks of one loop at once, the caller's
    // included: what the loops split their work by. At least 1.
    std::size_t thread_count() const { return thread_count_; }

    // Calls task(i) once for every i in [0, count) and returns when all calls
    // have returned. The calling thread takes part; idle workers help. Tasks
    // must not throw; a task may run a loop of its own.
    template <class Task>
    void run(std::size_t count, Task&& task) {
        if (count == 0) return;
        if (thread_count_ == 1 || count == 1) {
            for (std::size_t i = 0; i < count; ++i) task(i);
            return;
        }
        using Callable = std::remove_reference_t<Task>;
        dispatch(
            count, [](void* context, std::size_t i) { (*static_cast<Callable*>(context))(i); },
            const_cast<void*>(static_cast<const void*>(&task)));
    }

protected:
    using Call = void (*)(void*, std::size_t);

    explicit WorkerPool(std::size_t thread_count)
        : thread_count_(thread_count == 0 ? 1 : thread_count) {}

    // Runs call(context, i) for every i in [0, count), the caller taking part.
    virtual void dispatch(std::size_t count, Call call, void* context) = 0;

private:
    std::size_t thread_count_;
};

// Work on fewer unknowns (or rows) than this runs on one thread, whatever
// the pool: below it, waking the other threads costs more than their share
// of the work. The factorization, the solves, the set-up's analysis and the
// rotation fit all split from here.
inline constexpr std::size_t parallel_minimum = 8192;

// Runs `task(i)` for i in [0, count): on `pool` when there is one, inline
// otherwise.
template <class Task>
void run_tasks(WorkerPool* pool, std::size_t count, Task&& task) {
    if (pool != nullptr) {
        pool->run(count, task);
    } else {
        for (std::size_t i = 0; i < count; ++i) task(i);
    }
}

// Calls body(begin, end) over [0, n) split into contiguous parts, a few
// for each of `pool`'s threads, so that a thread that wakes late takes
// fewer; in one call, inline, without a pool, with one thread or below
// parallel_minimum. For loops whose every element is computed alone, the
// same bits however split.
template <class Body>
void for_parts(WorkerPool* pool, std::size_t n, Body&& body) {
    const std::size_t threads = pool != nullptr ? pool->thread_count() : 1;
    if (threads == 1 || n < parallel_minimum) {
        body(std::size_t{0}, n);
        return;
    }
    const std::size_t parts = 4 * threads;
    pool->run(parts, [&](std::size_t p) { body(p * n / parts, (p + 1) * n / parts); });
}

}  // namespace dfm::jobs
