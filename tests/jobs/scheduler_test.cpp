#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "jobs/scheduler.hpp"

using namespace dfm::jobs;

namespace {

// A host's job system as a game engine has one: its own threads drain a
// queue of jobs.
class HostQueue {
public:
    explicit HostQueue(std::size_t threads) {
        for (std::size_t i = 0; i < threads; ++i) threads_.emplace_back([this] { drain(); });
    }
    ~HostQueue() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stopping_ = true;
        }
        ready_.notify_all();
        for (std::thread& t : threads_) t.join();
    }
    HostJobs hooks() { return {&enqueue, this}; }
    std::size_t jobs_run() {
        std::lock_guard<std::mutex> lock(mutex_);
        return run_;
    }
    // Runs the jobs held so far on the calling thread.
    void run_held() {
        std::unique_lock<std::mutex> lock(mutex_);
        while (!jobs_.empty()) {
            void* job = jobs_.front();
            jobs_.pop_front();
            lock.unlock();
            Scheduler::run_job(job);
            lock.lock();
            ++run_;
        }
    }

private:
    static void enqueue(void* user, void* job) {
        auto* self = static_cast<HostQueue*>(user);
        {
            std::lock_guard<std::mutex> lock(self->mutex_);
            self->jobs_.push_back(job);
        }
        self->ready_.notify_one();
    }
    void drain() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            ready_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
            if (jobs_.empty()) return;
            void* job = jobs_.front();
            jobs_.pop_front();
            lock.unlock();
            Scheduler::run_job(job);
            lock.lock();
            ++run_;
        }
    }

    std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<void*> jobs_;
    std::size_t run_ = 0;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

// A task that records its runs in a shared journal.
struct NamedTask : Task {
    NamedTask(char name, std::string& journal, std::mutex& mutex)
        : name(name), journal(journal), mutex(mutex) {}
    Outcome run(const Slice& slice) override {
        const int at_once = ++running_now;
        most_at_once.store(std::max(most_at_once.load(), at_once));
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        --running_now;
        std::lock_guard<std::mutex> lock(mutex);
        journal += slice.closing ? static_cast<char>(name - 'A' + 'a') : name;
        if (pauses > 0) {
            --pauses;
            return Outcome::paused;
        }
        return Outcome::done;
    }
    char name;
    std::string& journal;
    std::mutex& mutex;
    int pauses = 0;
    // Runs of any NamedTask going on now, and the most there were at once.
    static inline std::atomic<int> running_now{0};
    static inline std::atomic<int> most_at_once{0};
};

int process_threads() {
    int count = 0;
    for ([[maybe_unused]] const auto& task :
         std::filesystem::directory_iterator("/proc/self/task")) {
        ++count;
    }
    return count;
}

// Every call of loops of several sizes, three times over, exactly once each.
void check_every_call_once(WorkerPool& pool) {
    for (const std::size_t count : {0u, 1u, 3u, 100u}) {
        CAPTURE(count);
        std::vector<std::atomic<int>> calls(count);
        for (int round = 0; round < 3; ++round)
            pool.run(count, [&](std::size_t i) { calls[i].fetch_add(1); });
        for (std::size_t i = 0; i < count; ++i) CHECK(calls[i].load() == 3);
    }
}

}  // namespace

TEST_CASE("jobs: every call of a parallel loop runs exactly once, in each mode") {
    for (const std::size_t workers : {1u, 2u, 4u}) {
        CAPTURE(workers);
        Scheduler pool(SchedulerConfig::threads(workers));
        CHECK(pool.thread_count() == workers);
        check_every_call_once(pool);
    }
    HostQueue host(3);
    Scheduler jobs(SchedulerConfig::jobs(3, host.hooks()));
    CHECK(jobs.thread_count() == 3);
    check_every_call_once(jobs);
    Scheduler stepped(SchedulerConfig::stepped());
    CHECK(stepped.thread_count() == 1);
    check_every_call_once(stepped);
}

TEST_CASE("jobs: a loop's call may run a loop of its own") {
    Scheduler pool(SchedulerConfig::threads(3));
    std::vector<std::atomic<int>> calls(40);
    pool.run(4, [&](std::size_t outer) {
        pool.run(10, [&](std::size_t inner) { calls[outer * 10 + inner].fetch_add(1); });
    });
    for (const std::atomic<int>& c : calls) CHECK(c.load() == 1);
}

TEST_CASE("jobs: run_tasks without a pool runs inline, in order") {
    std::vector<std::size_t> order;
    run_tasks(nullptr, 5, [&](std::size_t i) { order.push_back(i); });
    CHECK(order == std::vector<std::size_t>{0, 1, 2, 3, 4});
}

TEST_CASE("jobs: for_parts covers every index once, in one inline call below parallel_minimum") {
    for (const std::size_t workers : {1u, 2u, 3u}) {
        CAPTURE(workers);
        Scheduler pool(SchedulerConfig::threads(workers));
        for (const std::size_t n :
             {std::size_t{0}, parallel_minimum - 1, parallel_minimum, 3 * parallel_minimum + 7}) {
            CAPTURE(n);
            std::vector<std::atomic<int>> seen(n);
            std::atomic<int> calls{0};
            for_parts(&pool, n, [&](std::size_t begin, std::size_t end) {
                ++calls;
                for (std::size_t i = begin; i < end; ++i) seen[i].fetch_add(1);
            });
            for (const std::atomic<int>& s : seen) REQUIRE(s.load() == 1);
            const bool split = workers > 1 && n >= parallel_minimum;
            CHECK(calls.load() == (split ? static_cast<int>(4 * workers) : 1));
        }
    }
    std::size_t covered = 0;
    for_parts(nullptr, 3 * parallel_minimum, [&](std::size_t begin, std::size_t end) {
        CHECK(begin == 0);
        covered = end;
    });
    CHECK(covered == 3 * parallel_minimum);
}

TEST_CASE("jobs: tasks take turns in the order they were posted, a repost goes to the back") {
    Scheduler stepped(SchedulerConfig::stepped());
    std::string journal;
    std::mutex mutex;
    NamedTask a('A', journal, mutex), b('B', journal, mutex), c('C', journal, mutex);
    CHECK(stepped.post(a));
    CHECK(stepped.post(b));
    CHECK(stepped.post(a));  // already queued: keeps its place
    CHECK(stepped.post(c));
    CHECK(stepped.queued() == 3);
    CHECK(stepped.step_one(Clock::time_point::max()));
    CHECK(stepped.post(a));  // done: queued again, behind the others
    CHECK_FALSE(stepped.step(Clock::time_point::max()));
    CHECK(journal == "ABCA");
    CHECK_FALSE(stepped.step_one(Clock::time_point::max()));
}

TEST_CASE("jobs: a task stopped at the deadline runs first at the next step") {
    Scheduler stepped(SchedulerConfig::stepped());
    std::string journal;
    std::mutex mutex;
    NamedTask a('A', journal, mutex), b('B', journal, mutex);
    a.pauses = 2;
    stepped.post(a);
    stepped.post(b);
    // A deadline already past: one run, then the step returns.
    CHECK(stepped.step(Clock::now()));
    CHECK(journal == "A");
    CHECK(stepped.step(Clock::now()));
    CHECK(journal == "AA");
    CHECK_FALSE(stepped.step(Clock::time_point::max()));
    CHECK(journal == "AAAB");
}

TEST_CASE("jobs: withdraw takes a queued task out and waits for a running one") {
    Scheduler pool(SchedulerConfig::threads(1));
    std::mutex gate;
    std::unique_lock<std::mutex> closed_gate(gate);
    struct Blocking : Task {
        explicit Blocking(std::mutex& gate) : gate(gate) {}
        Outcome run(const Slice&) override {
            started = true;
            std::lock_guard<std::mutex> wait_for_gate(gate);
            ++runs;
            return Outcome::done;
        }
        std::mutex& gate;
        std::atomic<bool> started{false};
        std::atomic<int> runs{0};
    } running(gate), waiting(gate);
    pool.post(running);
    while (!running.started) std::this_thread::yield();
    pool.post(waiting);
    pool.post(running);  // while it runs: again after
    pool.withdraw(waiting);
    std::atomic<bool> withdrawn{false};
    std::thread other([&] {
        pool.withdraw(running);
        withdrawn = true;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK_FALSE(withdrawn.load());
    closed_gate.unlock();
    other.join();
    CHECK(running.runs == 1);  // withdrawn before its second run
    CHECK(waiting.runs == 0);
    CHECK(pool.queued() == 0);
}

TEST_CASE("jobs: on a host's job system no thread starts and at most `workers` jobs work") {
    HostQueue host(4);
    NamedTask::most_at_once = 0;
    const int threads_before = process_threads();
    std::string journal;
    std::mutex mutex;
    {
        Scheduler scheduler(SchedulerConfig::jobs(2, host.hooks()));
        std::vector<std::unique_ptr<NamedTask>> tasks;
        for (char name = 'A'; name <= 'L'; ++name) {
            tasks.push_back(std::make_unique<NamedTask>(name, journal, mutex));
            scheduler.post(*tasks.back());
        }
        std::vector<std::atomic<int>> calls(64);
        scheduler.run(64, [&](std::size_t i) { calls[i].fetch_add(1); });
        for (const std::atomic<int>& c : calls) CHECK(c.load() == 1);
        // Every task runs once, on the host's threads.
        for (;;) {
            std::lock_guard<std::mutex> lock(mutex);
            if (journal.size() == tasks.size()) break;
        }
        CHECK(process_threads() == threads_before);
        scheduler.close();
        std::string ran = journal;
        std::sort(ran.begin(), ran.end());
        CHECK(ran == "ABCDEFGHIJKL");
    }
    CHECK(NamedTask::most_at_once.load() <= 2);
    CHECK(host.jobs_run() >= 12);
}

TEST_CASE("jobs: close gives queued tasks a closing run, waits for jobs out, refuses posts") {
    std::string journal;
    std::mutex mutex;
    NamedTask a('A', journal, mutex), b('B', journal, mutex);
    {
        Scheduler stepped(SchedulerConfig::stepped());
        stepped.post(a);
        stepped.post(b);
        stepped.close();
        CHECK(journal == "ab");
        CHECK_FALSE(stepped.post(a));
        CHECK(stepped.closed());
        CHECK_FALSE(stepped.step(Clock::time_point::max()));
    }
    journal.clear();
    HostQueue host(0);  // holds its jobs until run_held()
    Scheduler scheduler(SchedulerConfig::jobs(1, host.hooks()));
    scheduler.post(a);
    scheduler.post(b);
    std::atomic<bool> closed{false};
    std::thread closer([&] {
        scheduler.close();
        closed = true;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK_FALSE(closed.load());  // a job is out
    host.run_held();
    closer.join();
    CHECK(journal == "ab");
    CHECK_FALSE(scheduler.post(a));
    host.run_held();
    CHECK(host.jobs_run() == 1);
}

namespace {

// A host's job system whose enqueue asks the scheduler how much is queued
// (which takes its lock) from another thread it waits for, then itself.
struct AskingHost {
    HostQueue queue{2};
    HostJobs inner = queue.hooks();
    Scheduler* scheduler = nullptr;
    std::atomic<int> asked{0};
    std::atomic<int> blocked{0};
    std::mutex mutex;
    std::vector<std::thread> late;  // blocked askers, joined at the end

    static void enqueue(void* user, void* job) {
        auto* self = static_cast<AskingHost*>(user);
        if (self->blocked == 0) {
            auto answered = std::make_shared<std::atomic<bool>>(false);
            std::thread other([self, answered] {
                static_cast<void>(self->scheduler->queued());
                *answered = true;
            });
            const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
            while (!*answered && std::chrono::steady_clock::now() < until)
                std::this_thread::sleep_for(std::chrono::microseconds(100));
            if (*answered) {
                other.join();
                static_cast<void>(self->scheduler->queued());
                ++self->asked;
            } else {
                ++self->blocked;
                std::lock_guard<std::mutex> lock(self->mutex);
                self->late.push_back(std::move(other));
            }
        }
        self->inner.enqueue(self->inner.user, job);
    }
};

}  // namespace

TEST_CASE("jobs: the host's enqueue runs with the scheduler's lock let go") {
    AskingHost host;
    std::string journal;
    std::mutex mutex;
    std::vector<std::unique_ptr<NamedTask>> tasks;
    {
        Scheduler scheduler(SchedulerConfig::jobs(2, {&AskingHost::enqueue, &host}));
        host.scheduler = &scheduler;
        // Posts, a loop's helpers and the jobs' own hand-overs.
        for (char name = 'A'; name <= 'F'; ++name) {
            tasks.push_back(std::make_unique<NamedTask>(name, journal, mutex));
            scheduler.post(*tasks.back());
        }
        std::vector<std::atomic<int>> calls(64);
        scheduler.run(64, [&](std::size_t i) { calls[i].fetch_add(1); });
        for (;;) {
            std::lock_guard<std::mutex> lock(mutex);
            if (journal.size() == tasks.size()) break;
        }
        scheduler.close();
    }
    for (std::thread& t : host.late) t.join();
    CHECK(host.blocked == 0);
    CHECK(host.asked > 0);
}
