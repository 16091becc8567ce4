#include "stages/band_workers.hpp"

namespace refraster::detail {

BandWorkers::BandWorkers(unsigned threads) : count_(threads < 1 ? 1 : threads) {
    threads_.reserve(count_ - 1);
    for (unsigned t = 1; t < count_; ++t) threads_.emplace_back([this, t] { work(t); });
}

BandWorkers::~BandWorkers() {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
    }
    start_.notify_all();
    for (auto& t : threads_) t.join();
}

void BandWorkers::run(const std::function<void(unsigned)>& job) {
    if (count_ == 1) {
        job(0);
        return;
    }
    {
        const std::lock_guard lock(mutex_);
        job_ = &job;
        running_ = count_ - 1;
        ++generation_;
    }
    start_.notify_all();
    job(0);
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return running_ == 0; });
    job_ = nullptr;
}

void BandWorkers::work(unsigned index) {
    std::uint64_t seen = 0;
    for (;;) {
        const std::function<void(unsigned)>* job = nullptr;
        {
            std::unique_lock lock(mutex_);
            start_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
            job = job_;
        }
        (*job)(index);
        {
            const std::lock_guard lock(mutex_);
            --running_;
        }
        done_.notify_one();
    }
}

}  // namespace refraster::detail
