// study_common.hpp: what the three studies share: timing (a run time as the median of rounds
// with their range, and a ratio of two such times with its range), counting and progress lines.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "harness/study.hpp"

namespace harness::study {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// A run time measured in several rounds: the median of the rounds, and a range that bounds what
// the machine's load did to it: with 5 rounds or more, from the second fastest to the second
// slowest (one spike of load, or one cold start, in either direction does not stretch it),
// with fewer, from the fastest to the slowest. The rounds of the variants
// being compared are interleaved (round 1 of every variant, then round 2, ...), so that a spell
// of load slows every variant alike instead of one.
struct Timing {
    double median = 0.0;
    double low = 0.0;
    double high = 0.0;
    int rounds = 0;
};

inline Timing timing_of(std::vector<double> seconds) {
    Timing t;
    if (seconds.empty()) return t;
    std::sort(seconds.begin(), seconds.end());
    const std::size_t n = seconds.size();
    t.median = n % 2 == 1 ? seconds[n / 2] : (seconds[n / 2 - 1] + seconds[n / 2]) / 2.0;
    const std::size_t trim = n >= 5 ? 1 : 0;
    t.low = seconds[trim];
    t.high = seconds[n - 1 - trim];
    t.rounds = static_cast<int>(n);
    return t;
}

inline Timing scaled(Timing t, double factor) {
    t.median *= factor;
    t.low *= factor;
    t.high *= factor;
    return t;
}

// a / b: the ratio of the medians, and the range the two ranges allow (a's low over b's high to
// a's high over b's low).
struct Ratio {
    double median = 0.0;
    double low = 0.0;
    double high = 0.0;
};

inline Ratio ratio_of(const Timing& a, const Timing& b) {
    return {a.median / b.median, a.low / b.high, a.high / b.low};
}

// "3.1 (2.8-3.4)": two significant digits, the range in brackets.
inline std::string ratio_text(const Ratio& r) {
    const auto two = [](double v) {
        std::ostringstream o;
        o << std::setprecision(2) << v;
        return o.str();
    };
    return two(r.median) + " (" + two(r.low) + "-" + two(r.high) + ")";
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
