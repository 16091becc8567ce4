// driver_env.hpp: which environment variables choose Mesa's driver or change what it renders,
// and which driver a GL context really runs. Shared by the harness (a worker's environment,
// a run's setup) and the GL workers (their provenance); no GL here.
//
// Implements: the variable families recorded and compared (docs/conformance.md, "Choosing the
// driver"), and naming the loaded driver from GL_RENDERER and the mapped libraries.
//
// Deliberately does not: read the process environment itself (callers pass it), or know any
// driver's rendering rules.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace harness::driver_env {

// True for NAME=value when NAME selects a driver or changes its results: MESA_*, LIBGL_*,
// GALLIUM_*, GALLIVM_*, LP_*, VK_*, ZINK_*, __EGL_VENDOR_LIBRARY_* and __GLX_VENDOR_LIBRARY_*
// (glvnd's choice of vendor library), and EGL_PLATFORM.
bool selects_or_changes_driver(std::string_view name_value);

// Those of `environment` (NAME=value strings), sorted, so that equal environments compare
// equal.
std::vector<std::string> driver_variables(const std::vector<std::string>& environment);

// The process's own environment as NAME=value strings.
std::vector<std::string> process_environment();

// The driver a context runs, as --driver names it: the DRI driver mapped into the process
// (`libraries`, ';'-separated paths: zink_dri.so -> "zink") unless it is the swrast loader
// (swrast_dri.so, kms_swrast_dri.so), which hosts the Gallium software drivers; then, and for
// OSMesa, the first word of GL_RENDERER ("llvmpipe (LLVM 15.0.6, 256 bits)" -> "llvmpipe").
std::string loaded_driver(std::string_view renderer, std::string_view libraries);

// The Vulkan device under zink, from GL_RENDERER ("zink (llvmpipe (LLVM 15.0.6, 256 bits))"):
// the device name zink shows in parentheses, headed by its driver where the name tells it
// ("lavapipe: llvmpipe (LLVM 15.0.6, 256 bits)": lavapipe's devices are named llvmpipe). The
// mapped libraries cannot tell: the Vulkan loader maps every installed driver. Empty for a
// renderer that is not zink.
std::string vulkan_driver(std::string_view renderer);

}  // namespace harness::driver_env
