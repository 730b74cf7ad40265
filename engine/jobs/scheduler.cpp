#include "jobs/scheduler.hpp"

#include <algorithm>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace dfm::jobs {

namespace {

// After its last piece of work a pool thread looks for new work every
// idle_poll_interval for idle_poll_window before it sleeps until woken. A
// post while it looks makes no system call: waking a sleeping thread costs
// the posting thread several microseconds, which a host pays in its frame;
// the looking costs the thread a wake-up per interval, and a new drag's
// first submit pays the wake-up once.
constexpr std::chrono::microseconds idle_poll_interval{200};
constexpr std::chrono::milliseconds idle_poll_window{100};

// Takes the thread out of wake-up preemption: with SCHED_BATCH a post that
// wakes it does not hand the host's core to it (the host's frame would pay
// for the switch); it still gets its fair share of time.
void lower_wakeup_preemption() {
#if defined(__linux__)
    sched_param param{};
    param.sched_priority = 0;
    pthread_setschedparam(pthread_self(), SCHED_BATCH, &param);
#endif
}

// A host's debugger and profiler show whose threads these are. Named as
// they start, so that one that has not run yet has its name too.
void name_worker(std::thread& thread) {
#if defined(__linux__)
    pthread_setname_np(thread.native_handle(), "dfm-worker");
#else
    (void)thread;
#endif
}

}  // namespace

void Scheduler::Line::push_back(Task& t) {
    t.previous_ = last;
    t.next_ = nullptr;
    (last != nullptr ? last->next_ : first) = &t;
    last = &t;
    ++size;
}

void Scheduler::Line::push_front(Task& t) {
    t.previous_ = nullptr;
    t.next_ = first;
    (first != nullptr ? first->previous_ : last) = &t;
    first = &t;
    ++size;
}

void Scheduler::Line::remove(Task& t) {
    (t.previous_ != nullptr ? t.previous_->next_ : first) = t.next_;
    (t.next_ != nullptr ? t.next_->previous_ : last) = t.previous_;
    t.previous_ = t.next_ = nullptr;
    --size;
}

Task* Scheduler::Line::pop_front() {
    Task* t = first;
    if (t != nullptr) remove(*t);
    return t;
}

Scheduler::Scheduler(const SchedulerConfig& config)
    : WorkerPool(config.mode == Mode::host_stepped ? 1 : config.workers), config_(config) {
    if (config_.mode != Mode::pool) return;
    threads_.reserve(config_.workers);
    try {
        for (std::size_t i = 0; i < config_.workers; ++i) {
            threads_.emplace_back([this] { thread_loop(); });
            name_worker(threads_.back());
        }
    } catch (...) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        work_.notify_all();
        for (std::thread& t : threads_) t.join();
        throw;
    }
}

Scheduler::~Scheduler() {
    close();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    work_.notify_all();
    for (std::thread& t : threads_) t.join();
}

bool Scheduler::post(Task& task) {
    std::size_t hand = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (closed_) return false;
        switch (task.state_) {
            case Task::State::idle:
                task.state_ = Task::State::queued;
                line_.push_back(task);
                break;
            case Task::State::queued: break;
            case Task::State::running: task.again_ = true; break;
        }
        wake_for_tasks();
        hand = jobs_to_hand();
    }
    hand_jobs(hand);
    return true;
}

void Scheduler::withdraw(Task& task) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        task.again_ = false;
        if (task.state_ == Task::State::queued) {
            line_.remove(task);
            task.state_ = Task::State::idle;
        }
        if (task.state_ == Task::State::idle) return;
        returned_.wait(lock);
    }
}

bool Scheduler::step(Clock::time_point deadline) {
    std::lock_guard<std::mutex> stepping(step_mutex_);
    std::unique_lock<std::mutex> lock(mutex_);
    while (run_first(lock, Task::Slice{.deadline = deadline})) {
        if (Clock::now() >= deadline) break;
    }
    return line_.size > 0;
}

bool Scheduler::step_one(Clock::time_point deadline) {
    std::lock_guard<std::mutex> stepping(step_mutex_);
    std::unique_lock<std::mutex> lock(mutex_);
    return run_first(lock, Task::Slice{.deadline = deadline});
}

void Scheduler::run_job(void* job) {
    static_cast<Scheduler*>(job)->run_host_job();
}

void Scheduler::close() {
    std::unique_lock<std::mutex> lock(mutex_);
    if (closed_) return;
    closed_ = true;
    while (Task* task = line_.pop_front()) {
        task->again_ = false;
        task->state_ = Task::State::running;
        lock.unlock();
        task->run(Task::Slice{.closing = true});
        lock.lock();
        task->state_ = Task::State::idle;
        returned_.notify_all();
    }
    returned_.wait(lock, [&] { return jobs_handed_ == 0 && jobs_running_ == 0; });
}

bool Scheduler::closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
}

std::size_t Scheduler::queued() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return line_.size;
}

void Scheduler::dispatch(std::size_t count, Call call, void* context) {
    Batch batch;
    batch.call = call;
    batch.context = context;
    batch.count = count;
    bool open = false;
    std::size_t hand = 0;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!closed_) {
            open = true;
            batch.help_wanted = std::min(count, thread_count()) - 1;
            batch.next = batches_;
            batches_ = &batch;
            if (polling_ + sleeping_ > 0) work_.notify_all();
            hand = jobs_to_hand();
        }
    }
    hand_jobs(hand);
    for (std::size_t i; (i = batch.next_call.fetch_add(1, std::memory_order_relaxed)) < count;)
        call(context, i);
    if (!open) return;
    std::unique_lock<std::mutex> lock(mutex_);
    Batch** link = &batches_;
    while (*link != &batch) link = &(*link)->next;
    *link = batch.next;
    // The helpers' calls wrote what the caller reads next: their leaving,
    // under the lock, orders those writes before this return.
    returned_.wait(lock, [&] { return batch.helpers == 0; });
}

Scheduler::Batch* Scheduler::join_batch(std::unique_lock<std::mutex>&) {
    for (Batch* b = batches_; b != nullptr; b = b->next) {
        if (b->help_wanted > 0 && b->next_call.load(std::memory_order_relaxed) < b->count) {
            --b->help_wanted;
            ++b->helpers;
            return b;
        }
    }
    return nullptr;
}

void Scheduler::help(Batch& batch, std::unique_lock<std::mutex>& lock) {
    lock.unlock();
    for (std::size_t i;
         (i = batch.next_call.fetch_add(1, std::memory_order_relaxed)) < batch.count;)
        batch.call(batch.context, i);
    lock.lock();
    if (--batch.helpers == 0) returned_.notify_all();
}

bool Scheduler::run_first(std::unique_lock<std::mutex>& lock, const Task::Slice& slice) {
    Task* task = line_.pop_front();
    if (task == nullptr) return false;
    task->state_ = Task::State::running;
    lock.unlock();
    const Task::Outcome outcome = task->run(slice);
    lock.lock();
    finish(*task, outcome, lock);
    return true;
}

void Scheduler::finish(Task& task, Task::Outcome outcome, std::unique_lock<std::mutex>& lock) {
    const bool more = outcome != Task::Outcome::done || task.again_;
    task.again_ = false;
    if (more && closed_) {
        // Posted while the scheduler closed: what it was posted for ends
        // here, as the queued tasks' work ended in close().
        lock.unlock();
        task.run(Task::Slice{.closing = true});
        lock.lock();
        task.state_ = Task::State::idle;
    } else if (outcome == Task::Outcome::paused) {
        task.state_ = Task::State::queued;
        line_.push_front(task);
    } else if (more) {
        task.state_ = Task::State::queued;
        line_.push_back(task);
        wake_for_tasks();
    } else {
        task.state_ = Task::State::idle;
    }
    returned_.notify_all();
}

void Scheduler::wake_for_tasks() {
    if (config_.mode == Mode::pool && sleeping_ > 0 && line_.size > polling_) work_.notify_one();
}

std::size_t Scheduler::jobs_to_hand() {
    if (config_.mode != Mode::host_jobs || closed_) return 0;
    std::size_t demand = line_.size;
    for (const Batch* b = batches_; b != nullptr; b = b->next) demand += b->help_wanted;
    std::size_t count = 0;
    while (jobs_handed_ < demand && jobs_handed_ + jobs_running_ < config_.workers) {
        ++jobs_handed_;
        ++count;
    }
    return count;
}

void Scheduler::hand_jobs(std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) config_.host.enqueue(config_.host.user, this);
}

void Scheduler::run_host_job() {
    std::unique_lock<std::mutex> lock(mutex_);
    --jobs_handed_;
    ++jobs_running_;
    if (Batch* batch = join_batch(lock)) {
        help(*batch, lock);
    } else if (!closed_) {
        run_first(lock, Task::Slice{});
    }
    // The job's work is done: it leaves the count in the same hold of the
    // lock in which it finds nothing left to hand over, so that a post
    // that found the limit reached by it is not lost. While it hands jobs
    // over (without the lock) it still counts for close(), which waits for
    // it, but no longer against the limit.
    for (;;) {
        --jobs_running_;
        const std::size_t hand = jobs_to_hand();
        if (hand == 0) break;
        ++jobs_running_;
        lock.unlock();
        hand_jobs(hand);
        lock.lock();
    }
    returned_.notify_all();
}

void Scheduler::thread_loop() {
    lower_wakeup_preemption();
    std::unique_lock<std::mutex> lock(mutex_);
    auto idle_since = Clock::now();
    while (!stopping_) {
        if (Batch* batch = join_batch(lock)) {
            help(*batch, lock);
            idle_since = Clock::now();
        } else if (run_first(lock, Task::Slice{})) {
            idle_since = Clock::now();
        } else if (Clock::now() - idle_since < idle_poll_window) {
            ++polling_;
            work_.wait_for(lock, idle_poll_interval);
            --polling_;
        } else {
            ++sleeping_;
            work_.wait(lock);
            --sleeping_;
        }
    }
}

}  // namespace dfm::jobs
