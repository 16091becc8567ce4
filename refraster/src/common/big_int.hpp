// big_int.hpp: fixed-width signed integers wide enough for the exact coverage predicates.
//
// Implements: BigInt, a two's-complement integer of kLimbs 32-bit limbs with +, -, * and sign.
// Width budget: a float32 scaled by 2^149 is an integer below 2^277; the predicates multiply
// at most three of them and two small integers below 2^30 each, and add a handful of such
// terms: below 2^(3*277 + 60 + 4) = 2^895. 1024 bits hold that with room to spare.
//
// Deliberately does not: divide, detect overflow at run time (the budget above rules it out),
// or allocate.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "refraster/assert.hpp"

namespace refraster::detail {

class BigInt {
  public:
    static constexpr int kLimbs = 32;
    static constexpr int kBits = 32 * kLimbs;
    static constexpr int kFloatScaleBits = 149;  // 2^-149 is float32's smallest step
    static_assert(3 * (128 + kFloatScaleBits) + 60 + 4 < kBits - 1, "exact predicate budget");

    BigInt() = default;
    static BigInt from_int(std::int64_t v) {
        BigInt r;
        auto u = static_cast<std::uint64_t>(v);
        r.limb_[0] = static_cast<std::uint32_t>(u);
        r.limb_[1] = static_cast<std::uint32_t>(u >> 32);
        const std::uint32_t fill = v < 0 ? 0xffffffffu : 0u;
        for (int i = 2; i < kLimbs; ++i) r.limb_[i] = fill;
        return r;
    }
    // f * 2^149, exactly (f finite).
    static BigInt from_scaled_float(float f) {
        REFRASTER_ASSERT(std::isfinite(f), "a finite float");
        if (f == 0.0f) return {};
        int e = 0;
        const double m = std::frexp(static_cast<double>(f), &e);   // f = m * 2^e, |m| in [0.5, 1)
        auto mant = static_cast<std::int64_t>(std::ldexp(m, 24));  // exact: 24 bits
        int shift = e - 24 + kFloatScaleBits;
        if (shift < 0) {  // denormals: the dropped low bits of the mantissa are zero
            mant /= std::int64_t{1} << -shift;
            shift = 0;
        }
        return from_int(mant).shifted_left(shift);
    }

    int sign() const {
        if (limb_[kLimbs - 1] & 0x80000000u) return -1;
        for (auto l : limb_) {
            if (l != 0) return 1;
        }
        return 0;
    }

    friend BigInt operator+(const BigInt& a, const BigInt& b) {
        BigInt r;
        std::uint64_t carry = 0;
        for (int i = 0; i < kLimbs; ++i) {
            const std::uint64_t s = std::uint64_t{a.limb_[i]} + b.limb_[i] + carry;
            r.limb_[i] = static_cast<std::uint32_t>(s);
            carry = s >> 32;
        }
        return r;
    }
    BigInt operator-() const {
        BigInt r;
        for (int i = 0; i < kLimbs; ++i) r.limb_[i] = ~limb_[i];
        return r + from_int(1);
    }
    friend BigInt operator-(const BigInt& a, const BigInt& b) { return a + (-b); }
    friend BigInt operator*(const BigInt& a, const BigInt& b) {
        // Multiply magnitudes, then restore the sign.
        const bool neg = (a.sign() < 0) != (b.sign() < 0);
        const BigInt x = a.sign() < 0 ? -a : a;
        const BigInt y = b.sign() < 0 ? -b : b;
        const int nx = x.used();
        const int ny = y.used();
        BigInt r;
        for (int i = 0; i < nx; ++i) {
            std::uint64_t carry = 0;
            for (int j = 0; j < ny && i + j < kLimbs; ++j) {
                const std::uint64_t t =
                    std::uint64_t{x.limb_[i]} * y.limb_[j] + r.limb_[i + j] + carry;
                r.limb_[i + j] = static_cast<std::uint32_t>(t);
                carry = t >> 32;
            }
            if (i + ny < kLimbs) r.limb_[i + ny] = static_cast<std::uint32_t>(carry);
        }
        return neg ? -r : r;
    }
    friend bool operator==(const BigInt&, const BigInt&) = default;

    // The nearest double, give or take a few ulps (for the oracle's attribute weights, where
    // the decisions are already made exactly). Values stay below 2^1023 by the budget above.
    double to_double() const {
        const bool neg = sign() < 0;
        const BigInt m = neg ? -*this : *this;
        double r = 0.0;
        for (int i = kLimbs - 1; i >= 0; --i)
            r = r * 4294967296.0 + static_cast<double>(m.limb_[i]);
        return neg ? -r : r;
    }

  private:
    int used() const {
        int n = kLimbs;
        while (n > 0 && limb_[n - 1] == 0) --n;
        return n;
    }
    BigInt shifted_left(int s) const {
        BigInt r;
        const int limbs = s / 32;
        const int bits = s % 32;
        for (int i = kLimbs - 1; i >= 0; --i) {
            const int src = i - limbs;
            std::uint32_t v = 0;
            if (src >= 0) {
                v = limb_[src] << bits;
                if (bits != 0 && src > 0) v |= limb_[src - 1] >> (32 - bits);
            }
            r.limb_[i] = v;
        }
        // In two's complement a left shift is a multiplication by 2^s for negative values too,
        // as long as the result fits, which the budget guarantees.
        return r;
    }

    std::uint32_t limb_[kLimbs] = {};
};

}  // namespace refraster::detail
