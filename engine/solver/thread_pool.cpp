#include "solver/thread_pool.hpp"

#if defined(__linux__)
#include <pthread.h>
#endif

namespace dfm::solver {

namespace {

// A host's debugger and profiler show whose threads these are. Named by
// the pool as it starts them, not by each thread once it runs: a thread
// that had not run yet (a small edit never wakes them) had no name.
void name_solver_thread(std::thread& thread) {
#if defined(__linux__)
    pthread_setname_np(thread.native_handle(), "dfm-solver");
#else
    (void)thread;
#endif
}

}  // namespace

ThreadPool::ThreadPool(std::size_t thread_count) {
    const std::size_t workers = thread_count > 1 ? thread_count - 1 : 0;
    workers_.reserve(workers);
    for (std::size_t i = 0; i < workers; ++i) {
        workers_.emplace_back([this] { worker_loop(); });
        name_solver_thread(workers_.back());
    }
}

ThreadPool::~ThreadPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
}

void ThreadPool::dispatch(std::size_t count, Call call, void* context) {
    {
        std::lock_guard lock(mutex_);
        call_ = call;
        context_ = context;
        task_count_ = count;
        next_task_.store(0, std::memory_order_relaxed);
        busy_workers_ = workers_.size();
        ++generation_;
    }
    wake_.notify_all();
    work_on_current_job();
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return busy_workers_ == 0; });
}

void ThreadPool::work_on_current_job() {
    for (;;) {
        const std::size_t i = next_task_.fetch_add(1, std::memory_order_relaxed);
        if (i >= task_count_) return;
        call_(context_, i);
    }
}

void ThreadPool::worker_loop() {
    std::size_t seen = 0;
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stopping_ || generation_ != seen; });
            if (stopping_) return;
            seen = generation_;
        }
        work_on_current_job();
        bool last = false;
        {
            std::lock_guard lock(mutex_);
            last = --busy_workers_ == 0;
        }
        if (last) done_.notify_one();
    }
}

}  // namespace dfm::solver
