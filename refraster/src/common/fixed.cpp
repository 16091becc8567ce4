#include "refraster/fixed.hpp"

#include <cstdio>
#include <cstdlib>

namespace refraster {

void overflow_trap(const char* what) {
    std::fprintf(stderr, "refraster: %s (checked arithmetic build)\n", what);
    std::abort();
}

}  // namespace refraster
