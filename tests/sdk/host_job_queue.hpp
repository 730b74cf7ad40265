#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "dualform/dualform.h"

namespace dfm::test {

// A host's job system as a game engine has one (dfm_job_system): its own
// threads drain a queue of jobs with dfm_job_run. With no threads it only
// holds the jobs until run_held().
class HostJobQueue {
public:
    explicit HostJobQueue(std::size_t threads);
    ~HostJobQueue();
    HostJobQueue(const HostJobQueue&) = delete;
    HostJobQueue& operator=(const HostJobQueue&) = delete;

    dfm_job_system hooks() { return {&enqueue, this}; }
    // Runs the jobs held so far on the calling thread.
    void run_held();
    // Jobs handed over and not yet started; and those not yet returned
    // from dfm_job_run as well.
    std::size_t waiting();
    std::size_t outstanding();
    std::size_t jobs_run();

private:
    static void enqueue(void* user, dfm_job* job);
    // Runs the first job with the lock released; `lock` holds mutex_.
    void run_front(std::unique_lock<std::mutex>& lock);
    void drain();

    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<dfm_job*> jobs_;
    std::size_t running_ = 0;
    std::size_t run_ = 0;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace dfm::test
