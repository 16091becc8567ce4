// Compiled as a file of the stages layer: what it may include (common/ and stages/) compiles.
// The control of stage_includes_model.cpp, which differs by one include.
#include "common/float_ops.hpp"
#include "stages/quad.hpp"

int stage_uses_stages() {
    return 0;
}
