// thread_pin.cpp: ThreadPin and allowed_cpus (thread_pin.hpp).
#include "thread_pin.hpp"

#include <cerrno>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <system_error>

namespace harness::detail {

namespace {

cpu_set_t current_set() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (::sched_getaffinity(0, sizeof set, &set) != 0)
        throw std::system_error(errno, std::generic_category(), "sched_getaffinity");
    return set;
}

bool has_cpu(const cpu_set_t& set, int cpu) {
    return cpu >= 0 && cpu < CPU_SETSIZE && CPU_ISSET(static_cast<std::size_t>(cpu), &set);
}

}  // namespace

std::vector<int> allowed_cpus() {
    const cpu_set_t set = current_set();
    std::vector<int> cpus;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (has_cpu(set, c)) cpus.push_back(c);
    return cpus;
}

ThreadPin::ThreadPin(std::optional<int> cpu) {
    if (!cpu) return;
    previous_ = current_set();
    if (!has_cpu(previous_, *cpu)) {
        std::string allowed;
        for (const int c : allowed_cpus())
            allowed += (allowed.empty() ? "" : ",") + std::to_string(c);
        throw std::invalid_argument("CPU " + std::to_string(*cpu) +
                                    " is not one this process may run on (" + allowed + ")");
    }
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(static_cast<std::size_t>(*cpu), &one);
    // sched_setaffinity with pid 0 sets the calling thread's affinity alone.
    if (::sched_setaffinity(0, sizeof one, &one) != 0)
        throw std::system_error(errno, std::generic_category(), "sched_setaffinity");
    pinned_ = true;
}

ThreadPin::~ThreadPin() {
    if (pinned_) (void)::sched_setaffinity(0, sizeof previous_, &previous_);
}

}  // namespace harness::detail
