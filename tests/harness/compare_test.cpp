// Comparison: classes, tolerance, the largest difference and its location, depth, float ULPs.
#include "harness/compare.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>

namespace {

using refraster::ColorFormat;
using refraster::DepthFormat;
using refraster::Framebuffer;

Framebuffer black(std::uint32_t w, std::uint32_t h, DepthFormat d = DepthFormat::None) {
    Framebuffer fb(w, h, ColorFormat::Rgba8, d);
    for (std::size_t i = 0; i < fb.pixel_count(); ++i) fb.color8[4 * i + 3] = 255;
    return fb;
}

void set(Framebuffer& fb, std::uint32_t x, std::uint32_t y, std::array<std::uint8_t, 4> c) {
    std::copy(c.begin(), c.end(),
              fb.color8.begin() + static_cast<std::ptrdiff_t>(4 * fb.index(x, y)));
}

const refraster::ClearValues kClearBlack{{0, 0, 0, 1}, 1.0f};

TEST(Compare, EqualImages) {
    const auto a = black(4, 4);
    const auto c = harness::compare_images(a, a, kClearBlack, {});
    EXPECT_EQ(c.mismatched_pixels, 0u);
    EXPECT_TRUE(c.within_expect);
    EXPECT_FALSE(c.max_color.has_value());
    EXPECT_EQ(c.mask.color8[0], 48);
}

TEST(Compare, ClassesMissingExtraColourOnly) {
    auto ref = black(4, 4);
    auto act = black(4, 4);
    set(ref, 0, 0, {255, 0, 0, 255});  // missing in act
    set(act, 1, 0, {0, 255, 0, 255});  // extra in act
    set(ref, 2, 3, {10, 10, 10, 255});
    set(act, 2, 3, {13, 10, 10, 255});  // colour only, by 3
    const auto c = harness::compare_images(ref, act, kClearBlack, {});
    EXPECT_EQ(c.missing, 1u);
    EXPECT_EQ(c.extra, 1u);
    EXPECT_EQ(c.color_only, 1u);
    EXPECT_EQ(c.mismatched_pixels, 3u);
    EXPECT_FALSE(c.within_expect);
    ASSERT_TRUE(c.max_color.has_value());
    EXPECT_EQ(c.max_color->amount, 255u);
    EXPECT_EQ(c.max_color->x, 0u);  // the first largest, in row order
    EXPECT_EQ(c.max_color->y, 0u);
    EXPECT_EQ(c.max_color->channel, 0u);
    EXPECT_EQ(c.max_color->reference[0], 255.0);
    EXPECT_EQ(c.max_color->actual[0], 0.0);
    const auto px = [&](std::uint32_t x, std::uint32_t y) {
        const auto i = 4 * c.mask.index(x, y);
        return std::array<std::uint8_t, 4>{c.mask.color8[i], c.mask.color8[i + 1],
                                           c.mask.color8[i + 2], c.mask.color8[i + 3]};
    };
    EXPECT_EQ(px(0, 0), harness::mask_color(harness::PixelClass::Missing));
    EXPECT_EQ(px(1, 0), harness::mask_color(harness::PixelClass::Extra));
    EXPECT_EQ(px(2, 3), harness::mask_color(harness::PixelClass::ColorOnly));
    EXPECT_EQ(px(3, 3), harness::mask_color(harness::PixelClass::Equal));
}

TEST(Compare, ToleranceAndBudget) {
    auto ref = black(4, 1);
    auto act = black(4, 1);
    set(ref, 0, 0, {100, 0, 0, 255});
    set(act, 0, 0, {101, 0, 0, 255});
    set(ref, 1, 0, {100, 0, 0, 255});
    set(act, 1, 0, {103, 0, 0, 255});
    auto c = harness::compare_images(ref, act, kClearBlack, {1, 0});
    EXPECT_EQ(c.mismatched_pixels, 1u);  // 1 is within tolerance, 3 is not
    EXPECT_FALSE(c.within_expect);
    c = harness::compare_images(ref, act, kClearBlack, {1, 1});
    EXPECT_TRUE(c.within_expect);
    EXPECT_EQ(c.max_color->amount, 3u);
    EXPECT_EQ(c.max_color->x, 1u);
}

TEST(Compare, DepthOnlyDifference) {
    auto ref = black(2, 2, DepthFormat::Z24);
    auto act = black(2, 2, DepthFormat::Z24);
    ref.depth[3] = 1000;
    act.depth[3] = 1003;
    const auto c = harness::compare_images(ref, act, kClearBlack, {});
    EXPECT_EQ(c.depth_only, 1u);
    EXPECT_EQ(c.mismatched_pixels, 1u);
    ASSERT_TRUE(c.max_depth.has_value());
    EXPECT_EQ(c.max_depth->amount, 3u);
    EXPECT_EQ(c.max_depth->x, 1u);
    EXPECT_EQ(c.max_depth->y, 1u);
}

TEST(Compare, FloatUlps) {
    Framebuffer ref(1, 1, ColorFormat::Rgba32f, DepthFormat::None);
    Framebuffer act = ref;
    ref.color32f[0] = 1.0f;
    act.color32f[0] = std::nextafter(std::nextafter(1.0f, 2.0f), 2.0f);
    ref.color32f[1] = 0.0f;
    act.color32f[1] = -0.0f;  // +0 and -0 are the same value
    auto c = harness::compare_images(ref, act, {{0, 0, 0, 0}, 1.0f}, {});
    EXPECT_EQ(c.max_color->amount, 2u);
    EXPECT_EQ(c.max_color->channel, 0u);
    c = harness::compare_images(ref, act, {{0, 0, 0, 0}, 1.0f}, {2, 0});
    EXPECT_TRUE(c.within_expect);
}

TEST(Compare, SizeMismatch) {
    const auto c = harness::compare_images(black(2, 2), black(3, 2), kClearBlack, {100, 100});
    EXPECT_TRUE(c.size_mismatch);
    EXPECT_FALSE(c.within_expect);
}

}  // namespace
