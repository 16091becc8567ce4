// Compiled as a file of the stages layer, this must fail: stages/ sees no model's folder
// (refraster/CMakeLists.txt, docs/architecture.md).
#include "common/float_ops.hpp"
#include "models/llvmpipe/setup.hpp"
#include "stages/quad.hpp"

int stage_includes_model() {
    return 0;
}
