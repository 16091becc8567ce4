// study_common.hpp: what the three studies share: timing and progress lines.
#pragma once

#include <chrono>
#include <string>

#include "harness/study.hpp"

namespace harness::study {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

inline void report(const StudyOptions& o, const std::string& line) {
    if (o.progress) o.progress(line);
}

}  // namespace harness::study
