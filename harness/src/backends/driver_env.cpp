// driver_env.cpp: see driver_env.hpp.
#include "driver_env.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>

namespace harness::driver_env {

bool selects_or_changes_driver(std::string_view kv) {
    // MESA_LOADER_DRIVER_OVERRIDE and LIBGL_ALWAYS_SOFTWARE choose the DRI driver,
    // GALLIUM_DRIVER the Gallium software driver, __EGL_VENDOR_LIBRARY_* and
    // __GLX_VENDOR_LIBRARY_* glvnd's vendor library, VK_* (VK_ICD_FILENAMES, ...) zink's
    // Vulkan driver; GALLIVM_PERF, LP_*, ZINK_* and MESA_* debug and tuning flags change what
    // the driver renders (GALLIVM_PERF=no_filter_hacks changes texture results).
    constexpr std::array<std::string_view, 11> prefixes{"MESA_",
                                                        "LIBGL_",
                                                        "GALLIUM_",
                                                        "GALLIVM_",
                                                        "LP_",
                                                        "VK_",
                                                        "ZINK_",
                                                        "__EGL_VENDOR_LIBRARY_",
                                                        "__GLX_VENDOR_LIBRARY_",
                                                        "EGL_PLATFORM=",
                                                        "SOFTPIPE_"};
    return std::any_of(prefixes.begin(), prefixes.end(),
                       [&](std::string_view p) { return kv.starts_with(p); });
}

std::vector<std::string> driver_variables(const std::vector<std::string>& environment) {
    std::vector<std::string> out;
    for (const auto& kv : environment)
        if (selects_or_changes_driver(kv)) out.push_back(kv);
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<std::string> process_environment() {
    std::vector<std::string> out;
    for (char** e = environ; e && *e; ++e) out.emplace_back(*e);
    return out;
}

namespace {

// The file names of `libraries` (';'-separated paths).
std::vector<std::string_view> file_names(std::string_view libraries) {
    std::vector<std::string_view> names;
    while (!libraries.empty()) {
        const auto end = libraries.find(';');
        std::string_view path = libraries.substr(0, end);
        names.push_back(path.substr(path.rfind('/') + 1));
        if (end == std::string_view::npos) break;
        libraries.remove_prefix(end + 1);
    }
    return names;
}

}  // namespace

std::string loaded_driver(std::string_view renderer, std::string_view libraries) {
    for (const auto name : file_names(libraries)) {
        const auto at = name.find("_dri.so");
        if (at == std::string_view::npos) continue;
        const std::string_view dri = name.substr(0, at);
        if (dri != "swrast" && dri != "kms_swrast") return std::string(dri);
    }
    std::string first;
    for (const char c : renderer) {
        if (c == ' ' || c == '(') break;
        first += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return first;
}

std::string vulkan_driver(std::string_view renderer) {
    constexpr std::string_view zink = "zink (";
    if (!renderer.starts_with(zink) || !renderer.ends_with(")")) return {};
    const std::string_view device = renderer.substr(zink.size(), renderer.size() - zink.size() - 1);
    // Mesa's Vulkan drivers name their devices: lavapipe "llvmpipe (...)", radv "AMD ... (RADV
    // ...)", anv "Intel(R) ...".
    if (device.starts_with("llvmpipe")) return "lavapipe: " + std::string(device);
    if (device.find("RADV") != std::string_view::npos) return "radv: " + std::string(device);
    return std::string(device);
}

}  // namespace harness::driver_env
