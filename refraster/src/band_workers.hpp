// band_workers.hpp: the threads that rasterize and shade a list of set-up primitives together.
//
// Implements: a fixed set of threads, started once per render, that each run the same job on
// their own index and are waited for as a group (BandWorkers::run), and the split of a row
// block between them. Thread t owns the 64-row bands of the target whose index modulo the
// thread count is t, and shades there every primitive of the list in API order, so each pixel
// is written by one thread in the order the API drew it: the bytes are the same for any
// count of threads.
//
// Deliberately does not: set up primitives in parallel (setup hands over whole lists), or
// share pixels between threads.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "row_block.hpp"

namespace refraster::detail {

inline constexpr int kBandRows = 64;

class BandWorkers {
  public:
    // `threads` in all, the calling thread included (at least 1).
    explicit BandWorkers(unsigned threads);
    ~BandWorkers();
    BandWorkers(const BandWorkers&) = delete;
    BandWorkers& operator=(const BandWorkers&) = delete;

    unsigned count() const { return count_; }
    // Runs job(t) for every t in [0, count()), job(0) in the calling thread, and returns when
    // every one has returned.
    void run(const std::function<void(unsigned)>& job);

  private:
    void work(unsigned index);

    unsigned count_;
    std::vector<std::thread> threads_;
    std::mutex mutex_;
    std::condition_variable start_;
    std::condition_variable done_;
    const std::function<void(unsigned)>* job_ = nullptr;
    std::uint64_t generation_ = 0;
    unsigned running_ = 0;
    bool stop_ = false;
};

// The rows of `b` in thread `t`'s bands (of `n`): `b` itself when all of its rows are there,
// an empty block when none is, otherwise a copy in `scratch` with the other rows cleared.
inline RowBlock band_rows(const RowBlock& b, unsigned t, unsigned n, std::uint64_t* scratch) {
    const auto band = [&](int y) { return static_cast<unsigned>(y / kBandRows) % n; };
    const unsigned first = band(b.y0);
    const unsigned last = band(b.y0 + b.rows - 1);
    if (first == last && b.y0 / kBandRows == (b.y0 + b.rows - 1) / kBandRows) {
        return first == t ? b : RowBlock{b.x0, b.y0, 0, b.mask};
    }
    for (int r = 0; r < b.rows; ++r) scratch[r] = band(b.y0 + r) == t ? b.mask[r] : 0;
    return {b.x0, b.y0, b.rows, scratch};
}

}  // namespace refraster::detail
