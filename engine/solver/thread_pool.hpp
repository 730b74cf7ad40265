#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace dfm::solver {

// A fixed set of worker threads for the solver's data-parallel loops. The
// solver splits work into tasks whose results do not depend on which thread
// runs them and combines partial results in task order, so every output is
// bit-identical whatever the thread count.
//
// One caller at a time: `run` is not reentrant and a pool must not be shared
// by two threads calling `run` concurrently.
class ThreadPool {
public:
    // `thread_count` threads in all, the calling thread included; 1 (or 0)
    // starts no worker and runs everything inline.
    explicit ThreadPool(std::size_t thread_count = 1);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    std::size_t thread_count() const { return workers_.size() + 1; }

    // Calls task(i) once for every i in [0, count), spread over the threads,
    // and returns when all calls have returned. Tasks must not throw.
    template <class Task>
    void run(std::size_t count, Task&& task) {
        if (count == 0) return;
        if (workers_.empty() || count == 1) {
            for (std::size_t i = 0; i < count; ++i) task(i);
            return;
        }
        using Callable = std::remove_reference_t<Task>;
        dispatch(
            count, [](void* context, std::size_t i) { (*static_cast<Callable*>(context))(i); },
            const_cast<void*>(static_cast<const void*>(&task)));
    }

private:
    using Call = void (*)(void*, std::size_t);

    void dispatch(std::size_t count, Call call, void* context);
    void work_on_current_job();
    void worker_loop();

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_;
    std::condition_variable done_;
    std::size_t generation_ = 0;
    bool stopping_ = false;
    std::size_t busy_workers_ = 0;

    Call call_ = nullptr;
    void* context_ = nullptr;
    std::size_t task_count_ = 0;
    std::atomic<std::size_t> next_task_{0};
};

// Work on fewer unknowns (or rows) than this runs on one thread, whatever
// the pool: below it, waking the other threads costs more than their share
// of the work. The factorization, the solves, the set-up's analysis and the
// rotation fit all split from here.
inline constexpr std::size_t parallel_minimum = 8192;

// Runs `task(i)` for i in [0, count): on `pool` when there is one, inline
// otherwise.
template <class Task>
void run_tasks(ThreadPool* pool, std::size_t count, Task&& task) {
    if (pool != nullptr) {
        pool->run(count, task);
    } else {
        for (std::size_t i = 0; i < count; ++i) task(i);
    }
}

}  // namespace dfm::solver
