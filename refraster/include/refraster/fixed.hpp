// fixed.hpp: fixed-point numbers as a type, and the named roundings that produce them.
//
// Implements: Fixed<FracBits, Rep>, a signed fixed-point value with FracBits fraction bits held
// in the integer type Rep; the float-to-fixed conversions each rasterizer rule names
// (round to nearest even as SSE's cvtps2dq does, half away from zero as Mesa's util_iround
// does, truncation); widening products into int64. A checked mode (the template argument
// kChecked of the conversions, used by tests) reports any value that does not fit instead of
// wrapping.
//
// Deliberately does not: overload arithmetic operators that could silently overflow. Sums and
// products of raw values are written out by the code that owns their bit budget, next to the
// comment that proves it.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>

#if defined(__x86_64__) || defined(_M_X64)
#include <xmmintrin.h>
#endif

namespace refraster {

enum class SnapRounding : std::uint8_t {
    NearestEven,       // cvtps2dq under the default MXCSR (llvmpipe triangles)
    HalfAwayFromZero,  // util_iround: (int)(v + copysign(0.5, v)) (llvmpipe lines, points)
    Truncate,          // (int)v
};

template <int FracBits, class Rep = std::int32_t>
class Fixed {
    static_assert(std::is_integral_v<Rep> && std::is_signed_v<Rep>);
    static_assert(FracBits >= 0 && FracBits < static_cast<int>(sizeof(Rep) * 8) - 1);

  public:
    static constexpr int kFracBits = FracBits;
    static constexpr Rep kOne = Rep{1} << FracBits;

    constexpr Fixed() = default;
    static constexpr Fixed from_raw(Rep r) {
        Fixed f;
        f.raw_ = r;
        return f;
    }
    constexpr Rep raw() const { return raw_; }
    constexpr double to_double() const { return static_cast<double>(raw_) / kOne; }
    friend constexpr bool operator==(Fixed, Fixed) = default;

  private:
    Rep raw_ = 0;
};

// Rounds an already scaled float (v = x * 2^FracBits) to an integer. nullopt when the result
// does not fit in Rep or v is not finite.
template <class Rep>
std::optional<Rep> round_scaled(float v, SnapRounding mode) {
    if (!std::isfinite(v)) return std::nullopt;
    double r = 0.0;
    switch (mode) {
        case SnapRounding::NearestEven: {
            // std::nearbyint in the default rounding mode, without a library call: adding and
            // removing 2^52 leaves a double of magnitude below 2^52 rounded to an integer,
            // ties to even (a float's magnitude at or above 2^52 is an integer already).
            const double d = static_cast<double>(v);
            constexpr double kShift = 0x1p52;
            if (d >= 0.0 && d < kShift) {
                r = (d + kShift) - kShift;
            } else if (d < 0.0 && d > -kShift) {
                r = (d - kShift) + kShift;
            } else {
                r = d;
            }
            break;
        }
        case SnapRounding::HalfAwayFromZero:
            // util_iround on x86-64: (int)(v + 0.5f) or (int)(v - 0.5f), in float. The float
            // add can itself round (v + 0.5f for v just below a half-integer), which is the
            // behaviour being reproduced; the truncation is exact.
            r = std::trunc(static_cast<double>(v >= 0.0f ? v + 0.5f : v - 0.5f));
            break;
        case SnapRounding::Truncate:
            r = std::trunc(static_cast<double>(v));
            break;
    }
    if (r < static_cast<double>(std::numeric_limits<Rep>::min()) ||
        r > static_cast<double>(std::numeric_limits<Rep>::max())) {
        return std::nullopt;
    }
    return static_cast<Rep>(r);
}

// Round to nearest even as cvtps2dq does it: an int32, or INT32_MIN (x86's "integer
// indefinite") for NaN, infinities and values whose rounded value leaves int32 (so also for
// -2^31 itself). On x86-64 it is that instruction's scalar form, cvtss2si, which rounds by
// MXCSR (round to nearest even: the reference never changes the rounding mode, and llvmpipe's
// calc_fixed_position relies on the same default); elsewhere round_scaled.
inline std::int32_t round_nearest_even_or_indefinite(float v) {
#if defined(__x86_64__) || defined(_M_X64)
    return _mm_cvtss_si32(_mm_set_ss(v));
#else
    const auto r = round_scaled<std::int32_t>(v, SnapRounding::NearestEven);
    return r ? *r : std::numeric_limits<std::int32_t>::min();
#endif
}

// The product of two raw values, widened so that it cannot overflow for 32-bit inputs.
constexpr std::int64_t wide_mul(std::int32_t a, std::int32_t b) {
    return static_cast<std::int64_t>(a) * static_cast<std::int64_t>(b);
}

// Checked arithmetic. The bit budgets stated beside each constant rule overflow out; a build
// with REFRASTER_CHECKED_ARITHMETIC=1 (the tests' checked build) verifies that at run time and
// aborts with a message on the first overflow instead of wrapping.
#ifndef REFRASTER_CHECKED_ARITHMETIC
#define REFRASTER_CHECKED_ARITHMETIC 0
#endif
inline constexpr bool kCheckedArithmetic = REFRASTER_CHECKED_ARITHMETIC != 0;

[[noreturn]] void overflow_trap(const char* what);

template <class T>
constexpr T checked_add(T a, T b) {
    if constexpr (kCheckedArithmetic) {
        T r{};
        if (__builtin_add_overflow(a, b, &r)) overflow_trap("integer overflow in an addition");
        return r;
    } else {
        return static_cast<T>(a + b);
    }
}

template <class T>
constexpr T checked_sub(T a, T b) {
    if constexpr (kCheckedArithmetic) {
        T r{};
        if (__builtin_sub_overflow(a, b, &r)) overflow_trap("integer overflow in a subtraction");
        return r;
    } else {
        return static_cast<T>(a - b);
    }
}

// Narrows to a smaller integer type; in the checked build a value that does not fit traps.
template <class To, class From>
constexpr To checked_narrow(From v) {
    if constexpr (kCheckedArithmetic) {
        if (v < static_cast<From>(std::numeric_limits<To>::min()) ||
            v > static_cast<From>(std::numeric_limits<To>::max())) {
            overflow_trap("integer overflow in a narrowing conversion");
        }
    }
    return static_cast<To>(v);
}

template <class T>
constexpr T checked_mul(T a, T b) {
    if constexpr (kCheckedArithmetic) {
        T r{};
        if (__builtin_mul_overflow(a, b, &r)) overflow_trap("integer overflow in a multiplication");
        return r;
    } else {
        return static_cast<T>(a * b);
    }
}

}  // namespace refraster
