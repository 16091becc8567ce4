// Flush-to-zero as x86 SSE does it (float_ops.hpp): a result is flushed when it is tiny after
// rounding to 24 bits with an unbounded exponent, which includes products just below FLT_MIN
// that float's subnormal grid rounds up to FLT_MIN. Checked against this CPU's own MXCSR
// FTZ/DAZ mode where the compiler targets SSE.
#include "common/float_ops.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cfloat>
#include <cstdint>
#include <random>

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace {

using refraster::detail::Fp;

TEST(FlushToZero, ProductJustBelowFltMinIsFlushedThoughItRoundsToFltMin) {
    const Fp ftz{true};
    const Fp plain{false};
    const float below_one = 0x1.fffffep-1f;  // 1 - 2^-24
    // Exact product FLT_MIN - 2^-150: the subnormal grid rounds it (a tie) up to FLT_MIN; with
    // an unbounded exponent it is representable and below FLT_MIN, so tiny.
    EXPECT_EQ(plain.mul(below_one, FLT_MIN), FLT_MIN);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(ftz.mul(below_one, FLT_MIN)), 0u);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(ftz.mul(-below_one, FLT_MIN)), 0x80000000u);
    // FLT_MIN itself and anything above it stay.
    EXPECT_EQ(ftz.mul(1.0f, FLT_MIN), FLT_MIN);
    EXPECT_EQ(ftz.mul(0x1.000002p+0f, FLT_MIN), 0x1.000002p-126f);
}

#if defined(__SSE2__)
// The CPU with FTZ and DAZ set, on products and quotients scattered around FLT_MIN.
TEST(FlushToZero, AgreesWithThisCpuAroundFltMin) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::uint32_t> mant(0, (1u << 23) - 1);
    std::uniform_int_distribution<int> expo(-20, 20);
    std::uniform_int_distribution<int> ulps(-4, 4);
    const unsigned saved = _mm_getcsr();
    int in_window = 0;  // exact results in [FLT_MIN - 2^-150, FLT_MIN - 2^-151)
    for (int n = 0; n < 200000; ++n) {
        const float x =
            std::bit_cast<float>((static_cast<std::uint32_t>(127 + expo(rng)) << 23) | mant(rng));
        // y and q chosen so that x * y and q / x fall within a few units of FLT_MIN.
        const auto step = [&](float v) {
            return std::bit_cast<float>(static_cast<std::uint32_t>(
                static_cast<std::int64_t>(std::bit_cast<std::uint32_t>(v)) + ulps(rng)));
        };
        const float sign = n % 2 ? -1.0f : 1.0f;
        const float y =
            sign * step(static_cast<float>(static_cast<double>(FLT_MIN) / static_cast<double>(x)));
        const float q =
            sign * step(static_cast<float>(static_cast<double>(FLT_MIN) * static_cast<double>(x)));
        volatile float vx = x, vy = y, vq = q;
        _mm_setcsr(saved | 0x8040);  // FTZ | DAZ
        const float hw_mul = vx * vy;
        const float hw_div = vq / vx;
        _mm_setcsr(saved);
        const double exact = std::fabs(static_cast<double>(x) * static_cast<double>(y));
        in_window += exact >= 0x1p-126 - 0x1p-150 && exact < 0x1p-126 - 0x1p-151;
        const Fp ftz{true};
        ASSERT_EQ(std::bit_cast<std::uint32_t>(ftz.mul(x, y)), std::bit_cast<std::uint32_t>(hw_mul))
            << std::hexfloat << x << " * " << y;
        ASSERT_EQ(std::bit_cast<std::uint32_t>(ftz.div(q, x)), std::bit_cast<std::uint32_t>(hw_div))
            << std::hexfloat << q << " / " << x;
    }
    EXPECT_GT(in_window, 1000);  // the products the subnormal grid and the CPU disagree on
}
#endif

}  // namespace
