// cpu.cpp: what the host CPU runs and its floating-point modes (cpu.hpp).
#include "common/cpu.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <xmmintrin.h>
#define REFRASTER_X86 1
#endif

#include "refraster/renderer.hpp"

namespace refraster {

std::string_view to_string(KernelPath p) {
    switch (p) {
        case KernelPath::Model:
            return "model";
        case KernelPath::Scalar:
            return "scalar";
        case KernelPath::Avx2:
            return "avx2";
        case KernelPath::Avx512:
            return "avx512";
        case KernelPath::Fastest:
            return "fastest";
    }
    return "model";
}

bool kernel_path_available(KernelPath p) {
    switch (p) {
        case KernelPath::Avx2:
            return detail::host_runs_avx2();
        case KernelPath::Avx512:
            return detail::host_runs_avx512();
        default:
            return true;
    }
}

KernelPath resolve_kernel_path(KernelPath p) {
    if (p == KernelPath::Fastest) p = KernelPath::Avx512;
    if (p == KernelPath::Avx512 && !detail::host_runs_avx512()) p = KernelPath::Avx2;
    if (p == KernelPath::Avx2 && !detail::host_runs_avx2()) p = KernelPath::Scalar;
    return p;
}

}  // namespace refraster

namespace refraster::detail {

bool host_runs_fma_sse41() {
#if defined(REFRASTER_X86) && (defined(__GNUC__) || defined(__clang__))
    static const bool yes = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("fma") && __builtin_cpu_supports("sse4.1") &&
               __builtin_cpu_supports("popcnt");
    }();
    return yes;
#else
    return false;
#endif
}

bool host_runs_avx2() {
#if defined(REFRASTER_X86) && (defined(__GNUC__) || defined(__clang__))
    static const bool yes = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
               __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
               __builtin_cpu_supports("popcnt");
    }();
    return yes;
#else
    return false;
#endif
}

bool host_runs_avx512() {
#if defined(REFRASTER_X86) && (defined(__GNUC__) || defined(__clang__))
    static const bool yes = [] {
        __builtin_cpu_init();
        return host_runs_avx2() && __builtin_cpu_supports("avx512f") &&
               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512vl");
    }();
    return yes;
#else
    return false;
#endif
}

// MXCSR bits: flush-to-zero (15) and denormals-are-zero (6).
constexpr std::uint32_t kFtzDaz = (1u << 15) | (1u << 6);

bool cpu_flush_modes_available() {
#if defined(REFRASTER_X86)
    return true;
#else
    return false;
#endif
}

ScopedDenormalMode::ScopedDenormalMode(bool active, bool flush) : active_(active) {
#if defined(REFRASTER_X86)
    if (active_) {
        saved_ = _mm_getcsr();
        _mm_setcsr(flush ? (saved_ | kFtzDaz) : (saved_ & ~kFtzDaz));
    }
#else
    (void)flush;
    active_ = false;
#endif
}

ScopedDenormalMode::~ScopedDenormalMode() {
#if defined(REFRASTER_X86)
    if (active_) _mm_setcsr(saved_);
#endif
}

}  // namespace refraster::detail
