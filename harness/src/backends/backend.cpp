#include "harness/backend.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "backend_ref.hpp"
#if defined(REFRASTER_HAVE_OSMESA) || defined(REFRASTER_HAVE_EGL)
#include "backend_gl.hpp"
#endif

#include "refraster_git_commit.hpp"  // generated at build time (cmake/GitCommit.cmake)

namespace harness {

std::string_view to_string(BackendKind k) {
    switch (k) {
        case BackendKind::Ref:
            return "ref";
        case BackendKind::OSMesa:
            return "osmesa";
        case BackendKind::Egl:
            return "egl";
    }
    return "?";
}

Driver::Driver(Known k) : name_(k == Llvmpipe ? "llvmpipe" : k == Softpipe ? "softpipe" : "zink") {}

const std::string& to_string(const Driver& d) {
    return d.name();
}

std::string_view to_string(RenderStatus s) {
    switch (s) {
        case RenderStatus::Ok:
            return "Ok";
        case RenderStatus::NotSupported:
            return "NotSupported";
        case RenderStatus::Crash:
            return "Crash";
        case RenderStatus::Timeout:
            return "Timeout";
        case RenderStatus::InternalError:
            return "InternalError";
    }
    return "?";
}

Provenance host_provenance() {
    Provenance p;
    p["commit"] = REFRASTER_GIT_COMMIT;
    std::string flags;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init();
    // Mesa's gallivm fuses llvm.fmuladd iff the CPU has FMA (gallivm passes +fma to LLVM exactly
    // then; docs/precision.md "Viewport transform").
    if (__builtin_cpu_supports("fma")) flags += "fma ";
    if (__builtin_cpu_supports("avx")) flags += "avx ";
    if (__builtin_cpu_supports("avx2")) flags += "avx2 ";
    if (__builtin_cpu_supports("avx512f")) flags += "avx512f ";
    if (__builtin_cpu_supports("sse4.1")) flags += "sse4.1 ";
#endif
    if (!flags.empty()) flags.pop_back();
    p["cpu_flags"] = flags;
    return p;
}

std::vector<std::string> mesa_prefix_environment(const std::filesystem::path& prefix,
                                                 const std::string& current_ld_library_path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(prefix, ec))
        throw MesaPrefixError("--mesa-prefix " + prefix.string() + ": not a directory");
    const auto holds_mesa = [&](const fs::path& dir) {
        if (!fs::is_directory(dir, ec)) return false;
        for (const auto& e : fs::directory_iterator(dir, ec)) {
            const std::string n = e.path().filename().string();
            if (n.starts_with("libOSMesa.so") || n.starts_with("libEGL_mesa.so")) return true;
        }
        return false;
    };
    fs::path lib;
    for (const char* sub : {"lib/x86_64-linux-gnu", "lib/aarch64-linux-gnu", "lib64", "lib"}) {
        if (holds_mesa(prefix / sub)) {
            lib = fs::absolute(prefix / sub, ec);
            break;
        }
    }
    if (lib.empty())
        throw MesaPrefixError("--mesa-prefix " + prefix.string() +
                              ": no libOSMesa.so* or libEGL_mesa.so* in its lib/<multiarch>, "
                              "lib64 or lib");
    std::vector<std::string> env;
    env.push_back("LD_LIBRARY_PATH=" + lib.string() +
                  (current_ld_library_path.empty() ? "" : ":" + current_ld_library_path));
    if (fs::is_directory(lib / "dri", ec))
        env.push_back("LIBGL_DRIVERS_PATH=" + (lib / "dri").string());
    const fs::path vendors = fs::absolute(prefix / "share/glvnd/egl_vendor.d", ec);
    if (fs::is_directory(vendors, ec)) {
        for (const auto& e : fs::directory_iterator(vendors, ec)) {
            const std::string n = e.path().filename().string();
            if (n.find("mesa") != std::string::npos && n.ends_with(".json")) {
                env.push_back("__EGL_VENDOR_LIBRARY_FILENAMES=" + e.path().string());
                break;
            }
        }
    }
    env.push_back("REFRASTER_MESA_PREFIX=" + fs::absolute(prefix, ec).string());
    return env;
}

std::unique_ptr<Backend> make_reference_backend(const refraster::Profile& profile,
                                                unsigned threads) {
    BackendOptions o;
    o.kind = BackendKind::Ref;
    o.profile = profile;
    o.threads = threads;
    return make_backend(o);
}

std::unique_ptr<Backend> make_backend(const BackendOptions& options) {
    if (options.egl_device) {
        if (options.kind != BackendKind::Egl)
            throw BackendOptionError("--egl-device applies to the egl backend only");
        if (*options.egl_device < 0)
            throw BackendOptionError("--egl-device " + std::to_string(*options.egl_device) +
                                     ": not a device index");
        BackendOptions o = options;
        o.environment.push_back("REFRASTER_EGL_DEVICE=" + std::to_string(*options.egl_device));
        o.egl_device.reset();
        return make_backend(o);
    }
    if (options.kind != BackendKind::Ref && !options.mesa_prefix.empty()) {
        BackendOptions o = options;
        const char* ld = std::getenv("LD_LIBRARY_PATH");
        for (auto& kv : mesa_prefix_environment(options.mesa_prefix, ld ? ld : ""))
            o.environment.push_back(std::move(kv));
        o.mesa_prefix.clear();
        return make_backend(o);
    }
    switch (options.kind) {
        case BackendKind::Ref:
            return make_ref_backend(options);
        case BackendKind::OSMesa:
#ifdef REFRASTER_HAVE_OSMESA
            return make_gl_backend(options);
#else
            throw std::runtime_error("the osmesa backend was not built (libosmesa6-dev missing)");
#endif
        case BackendKind::Egl:
#ifdef REFRASTER_HAVE_EGL
            return make_gl_backend(options);
#else
            throw std::runtime_error("the egl backend was not built (libegl-dev missing)");
#endif
    }
    throw std::runtime_error("unknown backend");
}

}  // namespace harness
