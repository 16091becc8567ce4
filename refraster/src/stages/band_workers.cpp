#include "stages/band_workers.hpp"

namespace refraster::detail {

BandWorkers::BandWorkers(unsigned threads) : count_(threads < 1 ? 1 : threads) {
    threads_.reserve(count_ - 1);
    for (unsigned t = 1; t < count_; ++t) {
        try {
            threads_.emplace_back([this, t] { work(t); });
        } catch (const std::exception&) {
            // A thread that cannot be started (no memory for its stack, no thread left): the
            // render runs on the threads there are, which gives the same bytes.
            count_ = t;
            break;
        }
    }
}

BandWorkers::~BandWorkers() {
    stop_and_join();
}

void BandWorkers::stop_and_join() noexcept {
    {
        const std::lock_guard lock(mutex_);
        stop_ = true;
    }
    start_.notify_all();
    for (auto& t : threads_) t.join();
    threads_.clear();
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
        failure_ = nullptr;
        ++generation_;
    }
    start_.notify_all();
    // The calling thread's share: an exception from it waits for the other threads, which still
    // read the job, before it leaves.
    std::exception_ptr own;
    try {
        job(0);
    } catch (...) {
        own = std::current_exception();
    }
    std::unique_lock lock(mutex_);
    done_.wait(lock, [&] { return running_ == 0; });
    job_ = nullptr;
    if (!own) own = failure_;
    failure_ = nullptr;
    if (own) std::rethrow_exception(own);
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
        // An exception leaving a thread's body would end the process; it is kept instead and
        // rethrown by run() in the calling thread (the first one, if several threads fail).
        std::exception_ptr failure;
        try {
            (*job)(index);
        } catch (...) {
            failure = std::current_exception();
        }
        {
            const std::lock_guard lock(mutex_);
            if (failure && !failure_) failure_ = failure;
            --running_;
        }
        done_.notify_one();
    }
}

}  // namespace refraster::detail
