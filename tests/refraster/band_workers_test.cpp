// The band workers: every thread runs the job, and an exception thrown by the job in any
// thread (a worker's or the calling one's) comes back from run() in the calling thread after
// every thread has returned, instead of ending the process.
#include "stages/band_workers.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <new>
#include <stdexcept>

namespace {

using refraster::detail::BandWorkers;

TEST(BandWorkers, RunsTheJobOnEveryIndex) {
    BandWorkers workers(3);
    std::atomic<unsigned> mask{0};
    workers.run([&](unsigned t) { mask |= 1u << t; });
    EXPECT_EQ(mask.load(), 7u);
}

TEST(BandWorkers, AWorkerThreadsBadAllocIsRethrownByRun) {
    BandWorkers workers(3);
    std::atomic<unsigned> returned{0};
    EXPECT_THROW(workers.run([&](unsigned t) {
        if (t == 2) throw std::bad_alloc();
        ++returned;
    }),
                 std::bad_alloc);
    EXPECT_EQ(returned.load(), 2u);  // the others ran to their end before run() threw
    // The workers are still usable after a failed run.
    std::atomic<unsigned> mask{0};
    workers.run([&](unsigned t) { mask |= 1u << t; });
    EXPECT_EQ(mask.load(), 7u);
}

TEST(BandWorkers, TheCallingThreadsExceptionWaitsForTheWorkers) {
    BandWorkers workers(2);
    std::atomic<bool> worker_done{false};
    EXPECT_THROW(workers.run([&](unsigned t) {
        if (t == 0) throw std::runtime_error("band 0");
        worker_done = true;
    }),
                 std::runtime_error);
    EXPECT_TRUE(worker_done.load());
}

}  // namespace
