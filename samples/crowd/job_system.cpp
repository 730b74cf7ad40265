#include "job_system.hpp"

JobSystem::JobSystem(std::size_t threads) {
    for (std::size_t i = 0; i < threads; ++i) threads_.emplace_back([this] { drain(); });
}

JobSystem::~JobSystem() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    ready_.notify_all();
    for (std::thread& t : threads_) t.join();
}

void JobSystem::enqueue(void* user, dfm_job* job) {
    auto* self = static_cast<JobSystem*>(user);
    {
        std::lock_guard<std::mutex> lock(self->mutex_);
        self->jobs_.push_back(job);
    }
    self->ready_.notify_one();
}

void JobSystem::drain() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        ready_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
        if (jobs_.empty()) return;
        dfm_job* job = jobs_.front();
        jobs_.pop_front();
        lock.unlock();
        dfm_job_run(job);
        lock.lock();
    }
}
