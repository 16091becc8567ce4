// Compiled as a file of the softpipe layer: its own folder and the stages compile. The control
// of model_includes_model.cpp.
#include "models/softpipe/scanline_setup.hpp"
#include "stages/edge_rules.hpp"

int model_uses_stages() {
    return 0;
}
