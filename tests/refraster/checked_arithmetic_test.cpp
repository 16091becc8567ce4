// The checked build traps overflow; the fixed-point helpers round as their rules say.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "refraster/fixed.hpp"

namespace {

TEST(CheckedArithmetic, ThisBuildChecks) {
    EXPECT_TRUE(refraster::kCheckedArithmetic);
}

TEST(CheckedArithmeticDeathTest, OverflowTraps) {
    const auto big = std::numeric_limits<std::int64_t>::max();
    EXPECT_DEATH((void)refraster::checked_add(big, std::int64_t{1}), "overflow in an addition");
    EXPECT_DEATH((void)refraster::checked_mul(big / 2, std::int64_t{3}),
                 "overflow in a multiplication");
    EXPECT_DEATH((void)refraster::checked_narrow<std::int32_t>(std::int64_t{1} << 40), "narrowing");
    EXPECT_EQ(refraster::checked_add(std::int64_t{2}, std::int64_t{3}), 5);
}

TEST(Snapping, RoundingModes) {
    using refraster::round_scaled;
    using refraster::SnapRounding;
    EXPECT_EQ(round_scaled<std::int32_t>(2560.5f, SnapRounding::NearestEven), 2560);
    EXPECT_EQ(round_scaled<std::int32_t>(2561.5f, SnapRounding::NearestEven), 2562);
    EXPECT_EQ(round_scaled<std::int32_t>(2560.5f, SnapRounding::HalfAwayFromZero), 2561);
    EXPECT_EQ(round_scaled<std::int32_t>(-2560.5f, SnapRounding::HalfAwayFromZero), -2561);
    EXPECT_EQ(round_scaled<std::int32_t>(-2560.7f, SnapRounding::Truncate), -2560);
    // util_iround's float add rounds: 0.49999997f + 0.5f is 1.0f in float, so it gives 1.
    EXPECT_EQ(round_scaled<std::int32_t>(0.49999997f, SnapRounding::HalfAwayFromZero), 1);
    EXPECT_FALSE(round_scaled<std::int32_t>(3e9f, SnapRounding::NearestEven).has_value());
}

// Nearest-even snapping is std::nearbyint in the default rounding mode, computed without a
// library call: the same integer for every float, ties, negatives, the largest and smallest
// magnitudes and the values just beyond int32 included.
TEST(Snapping, NearestEvenIsNearbyint) {
    using refraster::round_scaled;
    using refraster::SnapRounding;
    std::mt19937 rng(7);
    std::vector<float> values{
        0.0f,   -0.0f,       0.5f,       -0.5f,       1.5f,          -1.5f,          2.5f,
        -2.5f,  0.49999997f, 8388607.5f, -8388607.5f, 2147483520.0f, -2147483648.0f, 2147483648.0f,
        1e-45f, -1e-45f,     3e38f,      -3e38f,      2147483647.0f, -2147483904.0f};
    for (int i = 0; i < 200000; ++i) {
        const auto bits = static_cast<std::uint32_t>(rng());
        const float v = std::bit_cast<float>(bits);
        if (std::isfinite(v)) values.push_back(v);
        values.push_back(static_cast<float>(static_cast<std::int32_t>(rng())) / 256.0f);
        values.push_back(static_cast<float>(static_cast<int>(rng() % 4096) - 2048) + 0.5f);
    }
    for (const float v : values) {
        const double r = std::nearbyint(static_cast<double>(v));
        const bool fits = r >= -2147483648.0 && r <= 2147483647.0;
        const auto got = round_scaled<std::int32_t>(v, SnapRounding::NearestEven);
        ASSERT_EQ(got.has_value(), fits) << v;
        if (fits) {
            ASSERT_EQ(*got, static_cast<std::int32_t>(r)) << v;
        }
        // The instruction's form gives the same value, or INT32_MIN where nothing fits.
        ASSERT_EQ(refraster::round_nearest_even_or_indefinite(v),
                  fits ? static_cast<std::int32_t>(r) : std::numeric_limits<std::int32_t>::min())
            << v;
    }
    for (const float v :
         {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
          std::numeric_limits<float>::quiet_NaN()}) {
        EXPECT_FALSE(round_scaled<std::int32_t>(v, SnapRounding::NearestEven).has_value());
        EXPECT_EQ(refraster::round_nearest_even_or_indefinite(v),
                  std::numeric_limits<std::int32_t>::min());
    }
}

}  // namespace
