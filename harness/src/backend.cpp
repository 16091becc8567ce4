#include "harness/backend.hpp"

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

std::string_view to_string(Driver d) {
    return d == Driver::Llvmpipe ? "llvmpipe" : "softpipe";
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

std::unique_ptr<Backend> make_backend(const BackendOptions& options) {
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
