#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>
#include <vector>

#include "jobs/task.hpp"
#include "jobs/worker_pool.hpp"

namespace dfm::jobs {

// Where a context's work runs (dfm_work_mode).
enum class Mode {
    pool,          // the scheduler's own threads
    host_jobs,     // jobs handed to the host's job system
    host_stepped,  // the host's own calls (step), no thread at all
};

// The host's job system: enqueue(user, job) hands over one job, which the
// host runs exactly once, on any thread, with Scheduler::run_job(job).
struct HostJobs {
    void (*enqueue)(void* user, void* job) = nullptr;
    void* user = nullptr;
};

struct SchedulerConfig {
    Mode mode = Mode::pool;
    // pool: the threads started; host_jobs: how many of the host's threads
    // may run its jobs at once; host_stepped: must be 1. Also the
    // thread_count() that parallel loops split their work by.
    std::size_t workers = 1;
    HostJobs host;  // host_jobs only

    static SchedulerConfig threads(std::size_t count) { return {Mode::pool, count, {}}; }
    static SchedulerConfig jobs(std::size_t workers, HostJobs host) {
        return {Mode::host_jobs, workers, host};
    }
    static SchedulerConfig stepped() { return {Mode::host_stepped, 1, {}}; }
};

// A context's workers: the tasks (task.hpp) of all its sessions take turns
// on them, and the solver's parallel loops (WorkerPool) spread over the
// ones that are idle. In the pool mode it owns `workers` threads, named
// "dfm-worker"; handed to the host's job system it starts no thread and
// hands over at most `workers` jobs at a time, each running one task's piece
// or helping one loop; stepped by the host it runs work only inside step()
// and the waits that drive it (step_one).
class Scheduler final : public WorkerPool {
public:
    // Starts the pool's threads; throws std::system_error when one cannot
    // start (none is left running then).
    explicit Scheduler(const SchedulerConfig& config);
    // Closes, then stops and joins the pool's threads.
    ~Scheduler() override;

    Mode mode() const { return config_.mode; }

    // Queues a run of `task` at the back of the line; a task already queued
    // keeps its place, and one running is queued again when its run ends.
    // False, and nothing queued, once the scheduler is closed.
    bool post(Task& task);

    // Takes `task` out of the scheduler: once this returns it is neither
    // queued nor running, and runs again only if posted again. Waits for a
    // run in progress to return.
    void withdraw(Task& task);

    // host_stepped: runs queued tasks on the calling thread, one after the
    // other, until none is left or `deadline` has passed (a solve stops at
    // the deadline after its iteration in progress). True when work is left.
    // Threads that step take turns.
    bool step(Clock::time_point deadline);

    // host_stepped: one run of the task first in line (with `deadline`), on
    // the calling thread; false when no task was queued. What a wait runs
    // while it waits.
    bool step_one(Clock::time_point deadline);

    // host_jobs: runs a job that was handed to the host (`job` as given to
    // HostJobs::enqueue): a piece of a task or help for a loop, or nothing
    // when the work is already done.
    static void run_job(void* job);

    // The host lets go (host_jobs, host_stepped): every queued task gets a
    // closing run (Task::Slice::closing) on this thread, the jobs already
    // handed over are waited for (the host must go on running them), and no
    // job is handed over, no task queued, after it returns. The pool mode
    // closes only when the scheduler is destroyed.
    void close();
    bool closed() const;

    // Tasks queued and not running (for tests and the host's step).
    std::size_t queued() const;

private:
    // The queued tasks in order: an intrusive list, so queueing never
    // allocates.
    struct Line {
        Task* first = nullptr;
        Task* last = nullptr;
        std::size_t size = 0;
        void push_back(Task& t);
        void push_front(Task& t);
        void remove(Task& t);
        Task* pop_front();
    };
    // One parallel loop's calls, claimed one at a time by the caller and
    // the helpers that join it.
    struct Batch {
        Call call = nullptr;
        void* context = nullptr;
        std::size_t count = 0;
        std::atomic<std::size_t> next_call{0};
        std::size_t help_wanted = 0;  // helpers that may still join; under mutex_
        std::size_t helpers = 0;      // joined and not yet gone; under mutex_
        Batch* next = nullptr;        // the open batches' list; under mutex_
    };

    void dispatch(std::size_t count, Call call, void* context) override;
    void thread_loop();
    // The open batch that wants a helper, joined under the lock; null if none.
    Batch* join_batch(std::unique_lock<std::mutex>& lock);
    void help(Batch& batch, std::unique_lock<std::mutex>& lock);
    // Runs the task first in line on this thread; false if none was queued.
    bool run_first(std::unique_lock<std::mutex>& lock, const Task::Slice& slice);
    // Where a task goes once its run returns.
    void finish(Task& task, Task::Outcome outcome, std::unique_lock<std::mutex>& lock);
    // host_jobs: how many more jobs to hand over now (counted as handed):
    // no more than the work queued, and no more than `workers` working.
    std::size_t jobs_to_hand();
    void hand_jobs(std::size_t count);
    void run_host_job();
    // pool: wakes a sleeping thread for work that the polling ones cannot take.
    void wake_for_tasks();

    const SchedulerConfig config_;
    mutable std::mutex mutex_;
    std::condition_variable work_;      // the pool's threads wait here for work
    std::condition_variable returned_;  // a run, a job or a helper ended
    Line line_;
    Batch* batches_ = nullptr;
    bool closed_ = false;
    bool stopping_ = false;         // the pool's threads end
    std::size_t polling_ = 0;       // pool threads looking for work by themselves
    std::size_t sleeping_ = 0;      // pool threads waiting to be woken
    std::size_t jobs_handed_ = 0;   // host_jobs: handed over, not yet started
    std::size_t jobs_running_ = 0;  // host_jobs: started, not yet returned
    std::mutex step_mutex_;         // host_stepped: one stepping thread at a time
    std::vector<std::thread> threads_;
};

}  // namespace dfm::jobs
