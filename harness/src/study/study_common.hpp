// study_common.hpp: what the three studies share: timing and progress lines.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "harness/study.hpp"

namespace harness::study {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// How many elements are in one of two lists sorted by their keys and not in the other (the
// centres a variant and the oracle disagree on).
template <typename A, typename B, typename KA, typename KB>
std::uint64_t count_difference(const std::vector<A>& a, const std::vector<B>& b, KA ka, KB kb) {
    std::uint64_t n = 0;
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
        if (j == b.size() || (i < a.size() && ka(a[i]) < kb(b[j]))) {
            ++n;
            ++i;
        } else if (i == a.size() || kb(b[j]) < ka(a[i])) {
            ++n;
            ++j;
        } else {
            ++i;
            ++j;
        }
    }
    return n;
}

inline void report(const StudyOptions& o, const std::string& line) {
    if (o.progress) o.progress(line);
}

}  // namespace harness::study
