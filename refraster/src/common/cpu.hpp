// cpu.hpp: what the host CPU can run, and its floating-point modes.
//
// Implements: the run-time checks behind every choice of a compiled variant (FMA and SSE4.1
// for the scalar kernels and the vertex transform, AVX2 and AVX-512 for the vector kernels),
// and a scope that sets or clears the CPU's flush-to-zero and denormals-are-zero modes: the
// modes llvmpipe's rasterizer threads run under (lp_rast.c util_fpstate_set_denorms_to_zero)
// and draw_vbo sets for its own duration (draw_pt.c), which the fast paths let the CPU apply
// where the model otherwise emulates them operation by operation (float_ops.hpp).
//
// Deliberately does not: choose a kernel (each model does, from these answers), or change
// any value: a variant runs only where it computes the model's own bytes.
#pragma once

#include <cstdint>

// The vector kernels exist for x86-64 with GCC or clang (function-level targets); elsewhere
// only the scalar paths do.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define REFRASTER_VECTOR_KERNELS 1
#else
#define REFRASTER_VECTOR_KERNELS 0
#endif

namespace refraster::detail {

// Whether this CPU runs code compiled for FMA, SSE4.1 and POPCNT: the scalar kernels' and the
// vertex transform's run-time variants (fragment.cpp, vertex_stage.cpp).
bool host_runs_fma_sse41();
bool host_runs_avx2();
bool host_runs_avx512();

// Whether this CPU has flush-to-zero and denormals-are-zero modes the code can set (x86).
bool cpu_flush_modes_available();

// The CPU's flush-to-zero and denormals-are-zero modes set (`flush`) or cleared (!`flush`)
// for the scope's duration when `active`, restored after: the float mode the vector kernels
// and the fast setup assume where the profile flushes, and the plain mode that code the model
// runs without flushing needs inside such a scope.
class ScopedDenormalMode {
  public:
    ScopedDenormalMode(bool active, bool flush);
    ~ScopedDenormalMode();
    ScopedDenormalMode(const ScopedDenormalMode&) = delete;
    ScopedDenormalMode& operator=(const ScopedDenormalMode&) = delete;

  private:
    bool active_;
    std::uint32_t saved_ = 0;
};

// Flushing on for the scope when `on`.
class ScopedDenormalsAreZero : public ScopedDenormalMode {
  public:
    explicit ScopedDenormalsAreZero(bool on) : ScopedDenormalMode(on, true) {}
};

}  // namespace refraster::detail
