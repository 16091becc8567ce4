// band_workers.hpp: the threads that rasterize and shade a list of set-up primitives together.
//
// Implements: a fixed set of threads, started once per render, that each run the same job on
// their own index and are waited for as a group (BandWorkers::run). Thread t owns the 64-row
// bands of the target whose index modulo the thread count is t, and shades there every
// primitive of the list in API order (pipeline.hpp, shade_by_band), so each pixel is written
// by one thread in the order the API drew it: the bytes are the same for any count of
// threads.
//
// A thread the system cannot start leaves the work to the threads that did start (the bytes do
// not depend on the count). An exception thrown by the job in any thread (running out of memory,
// say) is kept and rethrown by run() in the calling thread once every thread has returned from the
// job; no exception leaves a worker thread's body.
//
// Deliberately does not: set up primitives in parallel (setup hands over whole lists), or
// share pixels between threads.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "stages/quad.hpp"
#include "stages/row_block.hpp"

namespace refraster::detail {

inline constexpr int kBandRows = 64;
static_assert(kBandRows == kTileSize, "a band holds whole 64x64 tiles of the walk");

class BandWorkers {
  public:
    // `threads` in all, the calling thread included (at least 1); fewer when the system cannot
    // start that many (count() says how many run).
    explicit BandWorkers(unsigned threads);
    ~BandWorkers();
    BandWorkers(const BandWorkers&) = delete;
    BandWorkers& operator=(const BandWorkers&) = delete;

    unsigned count() const { return count_; }
    // Runs job(t) for every t in [0, count()), job(0) in the calling thread, and returns when
    // every one has returned. If job threw in any thread, rethrows that exception (the calling
    // thread's own first, else the first a worker kept) after every thread has returned.
    void run(const std::function<void(unsigned)>& job);

  private:
    void work(unsigned index);
    void stop_and_join() noexcept;

    unsigned count_;
    std::vector<std::thread> threads_;
    std::mutex mutex_;
    std::condition_variable start_;
    std::condition_variable done_;
    const std::function<void(unsigned)>* job_ = nullptr;
    std::uint64_t generation_ = 0;
    unsigned running_ = 0;
    std::exception_ptr failure_;  // the first exception a worker thread kept in this run
    bool stop_ = false;
};

}  // namespace refraster::detail
