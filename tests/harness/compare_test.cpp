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

// The one-line summary names each side and its units: bytes for rgba8, ULPs and the float
// values for rgba32f, the stored integer for z24 and the float for z32f (before, "values are
// A vs B", and a z32f error as the distance and values of its bit patterns).
TEST(Compare, SummaryNamesTheSidesAndTheUnits) {
    auto ref = black(2, 2, DepthFormat::Z24);
    auto act = black(2, 2, DepthFormat::Z24);
    set(ref, 1, 0, {10, 20, 30, 255});
    set(act, 1, 0, {10, 23, 30, 255});
    ref.depth[3] = 1000;
    act.depth[3] = 1003;
    auto s = harness::compare_images(ref, act, kClearBlack, {}).summary();
    EXPECT_NE(s.find("max colour error 3 @ (1, 0, G): reference 10,20,30,255, backend "
                     "10,23,30,255"),
              std::string::npos)
        << s;
    EXPECT_NE(s.find("max depth error 3 @ (1, 1): reference 1000, backend 1003"), std::string::npos)
        << s;
    Framebuffer fref(1, 1, ColorFormat::Rgba32f, DepthFormat::Z32f);
    Framebuffer fact = fref;
    fref.color32f[0] = 0.5f;
    fact.color32f[0] = 0.1f;
    fref.depth[0] = std::bit_cast<std::uint32_t>(0.25f);
    fact.depth[0] = std::bit_cast<std::uint32_t>(0.75f);
    s = harness::compare_images(fref, fact, {{0, 0, 0, 0}, 1.0f}, {}).summary();
    const auto ulps = std::bit_cast<std::uint32_t>(0.5f) - std::bit_cast<std::uint32_t>(0.1f);
    EXPECT_NE(s.find("max colour error " + std::to_string(ulps) +
                     " ULPs @ (0, 0, R): reference 0.5,0,0,0, backend 0.1,0,0,0"),
              std::string::npos)
        << s;
    EXPECT_NE(s.find(" ULPs @ (0, 0): reference 0.25, backend 0.75"), std::string::npos) << s;
}

TEST(Compare, SizeMismatch) {
    const auto c = harness::compare_images(black(2, 2), black(3, 2), kClearBlack, {100, 100});
    EXPECT_TRUE(c.size_mismatch);
    EXPECT_FALSE(c.within_expect);
}

}  // namespace

// ---- 4x targets: every sample compared, the resolve by colour ------------------------------

namespace {

using harness::PixelClass;

// A 4x framebuffer whose every sample is opaque black.
Framebuffer black4(std::uint32_t w, std::uint32_t h, DepthFormat d = DepthFormat::None) {
    Framebuffer fb(w, h, ColorFormat::Rgba8, d, 4);
    for (std::size_t i = 0; i < fb.pixel_count() * 4; ++i) fb.color8[4 * i + 3] = 255;
    return fb;
}

void set_sample(Framebuffer& fb, std::uint32_t x, std::uint32_t y, std::uint32_t s,
                std::array<std::uint8_t, 4> c) {
    std::copy(c.begin(), c.end(),
              fb.color8.begin() + static_cast<std::ptrdiff_t>(4 * fb.sample_index(x, y, s)));
}

std::array<std::uint8_t, 4> mask_at(const Framebuffer& mask, std::uint32_t x, std::uint32_t y) {
    const auto i = 4 * mask.index(x, y);
    return {mask.color8[i], mask.color8[i + 1], mask.color8[i + 2], mask.color8[i + 3]};
}

TEST(CompareSamples, MaskPositionsFollowTheSamplePattern) {
    // Sample 0 (0.375, 0.125) bottom-left, 1 (0.875, 0.375) bottom-right, 2 (0.125, 0.625)
    // top-left, 3 (0.625, 0.875) top-right; row 0 of a framebuffer is the bottom.
    using A = std::array<std::uint32_t, 2>;
    EXPECT_EQ(harness::sample_mask_pixel(3, 5, 0), (A{6, 10}));
    EXPECT_EQ(harness::sample_mask_pixel(3, 5, 1), (A{7, 10}));
    EXPECT_EQ(harness::sample_mask_pixel(3, 5, 2), (A{6, 11}));
    EXPECT_EQ(harness::sample_mask_pixel(3, 5, 3), (A{7, 11}));
}

TEST(CompareSamples, EqualSamples) {
    const auto a = black4(3, 2);
    const auto c = harness::compare_samples(a, a, kClearBlack, {});
    EXPECT_FALSE(c.size_mismatch);
    EXPECT_EQ(c.samples, 4u);
    EXPECT_EQ(c.mismatched_samples, 0u);
    EXPECT_TRUE(c.within_expect);
    EXPECT_FALSE(c.max_color.has_value());
    ASSERT_EQ(c.per_sample.size(), 4u);
    EXPECT_EQ(c.mask.width, 6u);
    EXPECT_EQ(c.mask.height, 4u);
    for (std::uint32_t y = 0; y < 4; ++y) {
        for (std::uint32_t x = 0; x < 6; ++x) {
            EXPECT_EQ(mask_at(c.mask, x, y), harness::mask_color(PixelClass::Equal));
        }
    }
}

// One sample of one pixel differs: found at that sample, counted once, masked at its place.
TEST(CompareSamples, OneSampleOfOnePixelIsFoundAtItsSample) {
    for (std::uint32_t s = 0; s < 4; ++s) {
        SCOPED_TRACE(s);
        const auto ref = black4(3, 4);
        auto act = ref;
        set_sample(act, 1, 2, s, {0, 200, 0, 255});  // extra in act: the clear is black
        const auto c = harness::compare_samples(ref, act, kClearBlack, {});
        EXPECT_EQ(c.mismatched_samples, 1u);
        EXPECT_EQ(c.pixels_with_mismatched_samples, 1u);
        EXPECT_EQ(c.extra, 1u);
        EXPECT_EQ(c.missing + c.color_only + c.depth_only + c.coverage, 0u);
        for (std::uint32_t k = 0; k < 4; ++k) {
            EXPECT_EQ(c.per_sample[k].mismatched_pixels, k == s ? 1u : 0u) << k;
        }
        ASSERT_TRUE(c.max_color.has_value());
        EXPECT_EQ(c.max_color->amount, 200u);
        EXPECT_EQ(c.max_color->x, 1u);
        EXPECT_EQ(c.max_color->y, 2u);
        EXPECT_EQ(c.max_color->sample, s);
        EXPECT_EQ(c.max_color->channel, 1u);
        EXPECT_EQ(c.max_color->actual[1], 200.0);
        EXPECT_FALSE(c.within_expect);
        EXPECT_EQ(c.class_at(1, 2, s), PixelClass::Extra);
        const auto at = harness::sample_mask_pixel(1, 2, s);
        for (std::uint32_t y = 0; y < c.mask.height; ++y) {
            for (std::uint32_t x = 0; x < c.mask.width; ++x) {
                const bool here = x == at[0] && y == at[1];
                EXPECT_EQ(mask_at(c.mask, x, y),
                          harness::mask_color(here ? PixelClass::Extra : PixelClass::Equal))
                    << x << "," << y;
                const std::uint32_t ks = (y % 2) * 2 + (x % 2);
                EXPECT_EQ(c.class_at(x / 2, y / 2, ks),
                          here ? PixelClass::Extra : PixelClass::Equal);
            }
        }
        EXPECT_NE(c.summary().find("1 of 48 samples mismatched"), std::string::npos) << c.summary();
        EXPECT_NE(c.summary().find("@ (1, 2, sample " + std::to_string(s)), std::string::npos)
            << c.summary();
    }
}

// Two samples of a pixel swapped: the resolve is the same, the samples are not.
TEST(CompareSamples, ResolvedEqualButSamplesDiffer) {
    auto ref = black4(2, 2);
    auto act = ref;
    set_sample(ref, 0, 1, 0, {240, 0, 0, 255});
    set_sample(act, 0, 1, 1, {240, 0, 0, 255});
    const auto rr = refraster::resolve_samples(ref);
    const auto ar = refraster::resolve_samples(act);
    EXPECT_EQ(rr.color8, ar.color8);
    EXPECT_EQ(harness::compare_resolved(rr, ar, kClearBlack, {}).mismatched_pixels, 0u);
    const auto c = harness::compare_samples(ref, act, kClearBlack, {});
    EXPECT_EQ(c.mismatched_samples, 2u);
    EXPECT_EQ(c.pixels_with_mismatched_samples, 1u);
    EXPECT_EQ(c.missing, 1u);  // sample 0: the reference drew it
    EXPECT_EQ(c.extra, 1u);    // sample 1
    EXPECT_EQ(c.class_at(0, 1, 0), PixelClass::Missing);
    EXPECT_EQ(c.class_at(0, 1, 1), PixelClass::Extra);
    EXPECT_FALSE(c.within_expect);
    // Among equal amounts the lowest sample is the largest difference.
    EXPECT_EQ(c.max_color->sample, 0u);
    // max_mismatched_pixels bounds mismatched samples too.
    EXPECT_FALSE(harness::compare_samples(ref, act, kClearBlack, {0, 1}).within_expect);
    EXPECT_TRUE(harness::compare_samples(ref, act, kClearBlack, {0, 2}).within_expect);
    // The tolerance applies per sample.
    EXPECT_TRUE(harness::compare_samples(ref, act, kClearBlack, {240, 0}).within_expect);
}

// The depth of a 4x target is compared per sample only: the resolved image's depth (sample
// 0's) is not counted again.
TEST(CompareSamples, DepthIsComparedPerSampleOnly) {
    auto ref = black4(2, 2, DepthFormat::Z24);
    for (auto& d : ref.depth) d = 1000;  // drawn: not the clear depth
    auto act = ref;
    act.depth[ref.sample_index(1, 0, 0)] = 985;
    const auto resolved = harness::compare_resolved(
        refraster::resolve_samples(ref), refraster::resolve_samples(act), kClearBlack, {});
    EXPECT_EQ(resolved.mismatched_pixels, 0u);
    EXPECT_EQ(resolved.depth_only, 0u);
    EXPECT_FALSE(resolved.max_depth.has_value());
    // compare_images would have seen sample 0's depth in the resolve.
    EXPECT_EQ(harness::compare_images(refraster::resolve_samples(ref),
                                      refraster::resolve_samples(act), kClearBlack, {})
                  .depth_only,
              1u);
    const auto c = harness::compare_samples(ref, act, kClearBlack, {});
    EXPECT_EQ(c.mismatched_samples, 1u);
    EXPECT_EQ(c.depth_only, 1u);
    ASSERT_TRUE(c.max_depth.has_value());
    EXPECT_EQ(c.max_depth->amount, 15u);
    EXPECT_EQ(c.max_depth->x, 1u);
    EXPECT_EQ(c.max_depth->y, 0u);
    EXPECT_EQ(c.max_depth->sample, 0u);
    EXPECT_EQ(c.class_at(1, 0, 0), PixelClass::DepthOnly);
}

TEST(CompareSamples, OwnersClassSamplesByPrimitive) {
    auto ref = black4(2, 1);
    auto act = ref;
    ref.owner.assign(8, 0);
    act.owner.assign(8, 0);
    set_sample(ref, 1, 0, 2, {9, 9, 9, 255});
    set_sample(act, 1, 0, 2, {7, 9, 9, 255});
    ref.owner[ref.sample_index(1, 0, 2)] = refraster::owner_id(0, 0);
    act.owner[act.sample_index(1, 0, 2)] = refraster::owner_id(0, 1);
    const auto c = harness::compare_samples(ref, act, kClearBlack, {});
    EXPECT_TRUE(c.classified_by_owners);
    EXPECT_EQ(c.coverage, 1u);
    EXPECT_EQ(c.class_at(1, 0, 2), PixelClass::Coverage);
    // The same owners: the same primitive, other bytes.
    act.owner = ref.owner;
    EXPECT_EQ(harness::compare_samples(ref, act, kClearBlack, {}).class_at(1, 0, 2),
              PixelClass::ColorOnly);
    // Owners of one side only classify by the clear colour.
    act.owner.clear();
    const auto k = harness::compare_samples(ref, act, kClearBlack, {});
    EXPECT_FALSE(k.classified_by_owners);
    EXPECT_EQ(k.color_only, 1u);
}

TEST(CompareSamples, OwnersPlausibleChecksEverySample) {
    auto fb = black4(2, 1);
    std::vector<std::uint32_t> owner(8, 0);
    EXPECT_TRUE(harness::owners_plausible(owner, fb, kClearBlack));
    set_sample(fb, 0, 0, 3, {1, 2, 3, 255});
    EXPECT_FALSE(harness::owners_plausible(owner, fb, kClearBlack));  // drawn, but no owner
    owner[fb.sample_index(0, 0, 3)] = refraster::owner_id(0, 0);
    EXPECT_TRUE(harness::owners_plausible(owner, fb, kClearBlack));
    owner.resize(2);  // one owner a pixel is not enough
    EXPECT_FALSE(harness::owners_plausible(owner, fb, kClearBlack));
}

TEST(CompareSamples, NotFourSamplesIsASizeMismatch) {
    const auto four = black4(2, 2);
    for (const auto& other : {black(2, 2), black4(2, 3), Framebuffer{}}) {
        const auto c = harness::compare_samples(four, other, kClearBlack, {100, 1000});
        EXPECT_TRUE(c.size_mismatch);
        EXPECT_FALSE(c.within_expect);
    }
    Framebuffer f32(2, 2, ColorFormat::Rgba32f, DepthFormat::None, 4);
    EXPECT_TRUE(harness::compare_samples(four, f32, kClearBlack, {}).size_mismatch);
}

TEST(CompareSamples, FloatSamplesInUlps) {
    Framebuffer ref(1, 1, ColorFormat::Rgba32f, DepthFormat::None, 4);
    auto act = ref;
    act.color32f[4 * 3 + 2] = std::nextafter(0.0f, 1.0f);  // sample 3, blue, one ULP
    const auto c = harness::compare_samples(ref, act, {{0, 0, 0, 0}, 1.0f}, {});
    EXPECT_EQ(c.mismatched_samples, 1u);
    EXPECT_EQ(c.max_color->amount, 1u);
    EXPECT_EQ(c.max_color->sample, 3u);
    EXPECT_EQ(c.max_color->channel, 2u);
    EXPECT_TRUE(harness::compare_samples(ref, act, {{0, 0, 0, 0}, 1.0f}, {1, 0}).within_expect);
}

}  // namespace
