// The checked build traps overflow; the fixed-point helpers round as their rules say.
#include <gtest/gtest.h>

#include <limits>

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

}  // namespace
