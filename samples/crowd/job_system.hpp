#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "dualform/dualform.h"

// The game's own job system, as small as a host's can be: a queue and the
// threads that drain it. Dualform hands its jobs over through
// dfm_job_system (hooks()) and the threads run them with dfm_job_run, beside
// whatever else the game queues.
class JobSystem {
public:
    explicit JobSystem(std::size_t threads);
    // Runs what is left, then stops the threads: destroy Dualform's
    // context first, so that it hands nothing over any more.
    ~JobSystem();
    JobSystem(const JobSystem&) = delete;
    JobSystem& operator=(const JobSystem&) = delete;

    dfm_job_system hooks() { return {&enqueue, this}; }

private:
    static void enqueue(void* user, dfm_job* job);
    void drain();

    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<dfm_job*> jobs_;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};
