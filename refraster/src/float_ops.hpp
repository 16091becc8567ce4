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

// A denormal becomes a zero of the same sign.
REFRASTER_FLOAT_OP float flush_denormal(float v) {
    return std::fabs(v) < std::numeric_limits<float>::min() ? std::copysign(0.0f, v) : v;
}

struct Fp {
    bool flush;
    REFRASTER_FLOAT_OP float f(float v) const { return flush ? flush_denormal(v) : v; }
    REFRASTER_FLOAT_OP float add(float a, float b) const { return f(f(a) + f(b)); }
    REFRASTER_FLOAT_OP float sub(float a, float b) const { return f(f(a) - f(b)); }
    REFRASTER_FLOAT_OP float mul(float a, float b) const { return f(f(a) * f(b)); }
    REFRASTER_FLOAT_OP float div(float a, float b) const { return f(f(a) / f(b)); }
    REFRASTER_FLOAT_OP float fma(float a, float b, float c) const {
        return f(std::fma(f(a), f(b), f(c)));
    }
};

#undef REFRASTER_FLOAT_OP

}  // namespace refraster::detail
