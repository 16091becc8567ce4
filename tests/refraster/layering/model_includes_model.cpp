// Compiled as a file of the softpipe layer, this must fail: a model sees no other model's
// folder (refraster/CMakeLists.txt, docs/architecture.md).
#include "models/llvmpipe/setup.hpp"
#include "models/softpipe/scanline_setup.hpp"

int model_includes_model() {
    return 0;
}
