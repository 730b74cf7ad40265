#include "sdk/host_job_queue.hpp"

namespace dfm::test {

HostJobQueue::HostJobQueue(std::size_t threads) {
    for (std::size_t i = 0; i < threads; ++i) threads_.emplace_back([this] { drain(); });
}

HostJobQueue::~HostJobQueue() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    ready_.notify_all();
    for (std::thread& t : threads_) t.join();
}

void HostJobQueue::enqueue(void* user, dfm_job* job) {
    auto* self = static_cast<HostJobQueue*>(user);
    {
        std::lock_guard<std::mutex> lock(self->mutex_);
        self->jobs_.push_back(job);
    }
    self->ready_.notify_one();
}

void HostJobQueue::run_front(std::unique_lock<std::mutex>& lock) {
    dfm_job* job = jobs_.front();
    jobs_.pop_front();
    ++running_;
    lock.unlock();
    dfm_job_run(job);
    lock.lock();
    --running_;
    ++run_;
}

void HostJobQueue::run_held() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!jobs_.empty()) run_front(lock);
}

std::size_t HostJobQueue::waiting() {
    std::lock_guard<std::mutex> lock(mutex_);
    return jobs_.size();
}

std::size_t HostJobQueue::outstanding() {
    std::lock_guard<std::mutex> lock(mutex_);
    return jobs_.size() + running_;
}

std::size_t HostJobQueue::jobs_run() {
    std::lock_guard<std::mutex> lock(mutex_);
    return run_;
}

void HostJobQueue::drain() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        ready_.wait(lock, [&] { return stopping_ || !jobs_.empty(); });
        if (jobs_.empty()) return;
        run_front(lock);
    }
}

}  // namespace dfm::test
