// float_ops.hpp: float32 operations as the reproduced driver code performs them.
//
// Implements: flushing denormals to zero (FTZ on results, DAZ on inputs), which llvmpipe
// enables around its vertex pipeline and rasterizer (draw_pt.c, lp_rast.c:
// util_fpstate_set_denorms_to_zero; docs/precision.md "Denormals"), and the four operations plus a
// fused multiply-add under that mode. Each operation rounds once, as IEEE float32 does; the
// project compiles with -ffp-contract=off so that nothing else fuses.
//
// Deliberately does not: change the CPU's floating-point environment.
#pragma once

#include <cmath>
#include <limits>

namespace refraster::detail {

// These are the innermost operations of every stage; they are forced inline because a unit
// with many fragment kernels otherwise exceeds the compiler's inlining budget and calls them.
#define REFRASTER_FLOAT_OP [[gnu::always_inline]] inline

// One fused multiply-add and one round-to-nearest-even in the current rounding mode, as the
// compiler's builtins, so that a caller compiled for FMA or SSE4.1 (the run-time kernel
// variants of fragment.cpp) gets the instruction inline and any other caller the library
// function: the results are the same.
REFRASTER_FLOAT_OP float fused_multiply_add(float a, float b, float c) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_fmaf(a, b, c);
#else
    return std::fma(a, b, c);
#endif
}
REFRASTER_FLOAT_OP float round_to_nearest_even(float v) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_nearbyintf(v);
#else
    return std::nearbyint(v);
#endif
}

// A denormal becomes a zero of the same sign.
REFRASTER_FLOAT_OP float flush_denormal(float v) {
    return std::fabs(v) < std::numeric_limits<float>::min() ? std::copysign(0.0f, v) : v;
}

// x86's flush-to-zero replaces a result that underflows, and SSE judges underflow on the
// result rounded to 24 bits with an unbounded exponent (Intel SDM vol. 1, 4.9.1.5, "tiny after
// rounding"). A product or quotient whose exact value lies just below FLT_MIN can round up to
// FLT_MIN on float's subnormal grid and still be tiny: it is flushed. Below FLT_MIN the grid
// of the unbounded rounding is 2^-150, so the exact value is tiny iff it is less than
// FLT_MIN - 2^-151 (the midpoint rounds to FLT_MIN, the even neighbour). Sums are exact there
// (any float sum below FLT_MIN is a multiple of 2^-149), so only *, / and fma need the test.
inline constexpr double kTinyBelow = 0x1p-126 - 0x1p-151;
static_assert(kTinyBelow < static_cast<double>(std::numeric_limits<float>::min()),
              "the tininess threshold");

REFRASTER_FLOAT_OP float flush_if_tiny(float rounded, bool tiny) {
    return tiny ? std::copysign(0.0f, rounded) : rounded;
}

struct Fp {
    bool flush;
    REFRASTER_FLOAT_OP float f(float v) const { return flush ? flush_denormal(v) : v; }
    REFRASTER_FLOAT_OP float add(float a, float b) const { return f(f(a) + f(b)); }
    REFRASTER_FLOAT_OP float sub(float a, float b) const { return f(f(a) - f(b)); }
    REFRASTER_FLOAT_OP float mul(float a, float b) const {
        const float x = f(a);
        const float y = f(b);
        const float r = x * y;
        if (!flush) return r;
        if (std::fabs(r) != std::numeric_limits<float>::min()) return flush_denormal(r);
        // The double product of two floats is exact.
        return flush_if_tiny(
            r, std::fabs(static_cast<double>(x) * static_cast<double>(y)) < kTinyBelow);
    }
    REFRASTER_FLOAT_OP float div(float a, float b) const {
        const float x = f(a);
        const float y = f(b);
        const float r = x / y;
        if (!flush) return r;
        if (std::fabs(r) != std::numeric_limits<float>::min()) return flush_denormal(r);
        const double q = static_cast<double>(x) / static_cast<double>(y);
        bool tiny = std::fabs(q) < kTinyBelow;
        if (std::fabs(q) == kTinyBelow) {
            // The remainder of a correctly rounded quotient is exact: it says on which side of
            // q the exact quotient lies.
            const double rem = std::fma(-q, static_cast<double>(y), static_cast<double>(x));
            tiny = rem != 0.0 && (std::signbit(rem) != std::signbit(y)) != std::signbit(q);
        }
        return flush_if_tiny(r, tiny);
    }
    REFRASTER_FLOAT_OP float fma(float a, float b, float c) const {
        const float x = f(a);
        const float y = f(b);
        const float z = f(c);
        const float r = fused_multiply_add(x, y, z);
        if (!flush) return r;
        if (std::fabs(r) != std::numeric_limits<float>::min()) return flush_denormal(r);
        // One rounding to 53 bits; it can only mislead within 2^-53 of the threshold itself.
        const double d =
            std::fma(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z));
        return flush_if_tiny(r, std::fabs(d) < kTinyBelow);
    }
};

#undef REFRASTER_FLOAT_OP

}  // namespace refraster::detail
