// assert.cpp: what a failed REFRASTER_ASSERT does (assert.hpp).
#include "refraster/assert.hpp"

#include <cstdio>
#include <cstdlib>

namespace refraster {

void assertion_failed(const char* condition, const char* message, const char* file,
                      int line) noexcept {
    std::fprintf(stderr, "%s:%d: precondition failed: %s (%s)\n", file, line, condition, message);
    std::fflush(stderr);
    std::abort();
}

}  // namespace refraster
