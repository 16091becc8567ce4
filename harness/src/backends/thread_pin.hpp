// thread_pin.hpp: the calling thread held to one CPU for a scope.
//
// Implements: ThreadPin, which sets the calling thread's affinity to one CPU and gives back the
// set it had when it goes out of scope, so that a process spawned or a thread started within
// the scope inherits the one CPU (sched_setaffinity(2): a child of fork, posix_spawn or
// pthread_create starts with its parent thread's set); allowed_cpus, the CPUs this thread may
// run on. `refraster bench` times a single-threaded renderer and the single-threaded reference
// on the same CPU: the CPUs of a shared machine can differ in speed by half, and a ratio of
// two renders that ran on different ones measures the CPUs.
//
// Deliberately does not: pin any other thread of the process, or move memory between nodes.
#pragma once

#include <sched.h>

#include <optional>
#include <vector>

namespace harness::detail {

// The CPUs the calling thread may run on, in increasing order.
std::vector<int> allowed_cpus();

class ThreadPin {
  public:
    // nullopt: changes nothing. A CPU outside the calling thread's set: throws
    // std::invalid_argument naming it and the set.
    explicit ThreadPin(std::optional<int> cpu);
    ~ThreadPin();
    ThreadPin(const ThreadPin&) = delete;
    ThreadPin& operator=(const ThreadPin&) = delete;

  private:
    bool pinned_ = false;
    cpu_set_t previous_{};
};

}  // namespace harness::detail
