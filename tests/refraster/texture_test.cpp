// The sampler's rules (refraster/src/models/llvmpipe/texture.cpp) against the measured facts they
// come from (docs/precision.md, "Textures"), each computed here a second, independent way.
#include "models/llvmpipe/texture.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace refraster::detail {
namespace {

TextureImage random_image(std::uint32_t w, std::uint32_t h, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    TextureImage img;
    img.width = w;
    img.height = h;
    img.rgba.resize(std::size_t{w} * h * 4);
    for (auto& b : img.rgba) b = static_cast<std::uint8_t>(rng() & 0xff);
    return img;
}

std::uint8_t texel(const TextureImage& img, std::uint32_t x, std::uint32_t y, std::size_t c) {
    return img.rgba[4 * (std::size_t{y} * img.width + x) + c];
}

// Samples one pixel: a quad whose four pixels share the coordinates (no derivatives).
std::array<float, 4> sample_one(const TextureUnit& u, float s, float t) {
    std::array<std::array<float, 4>, 4> out{};
    sample_quad(u, {s, s, s, s}, {t, t, t, t}, true, out);
    return out[0];
}

std::uint8_t to_byte(float f) {
    return static_cast<std::uint8_t>(std::lrint(f * 255.0f));
}

TEST(Texture, AByteComesBackFromItsFloat) {
    // cvt8(un8(v)) = v for all 256 bytes (the shader sees un8; the target stores cvt8).
    for (int v = 0; v < 256; ++v) {
        const float f = unorm8_to_float(static_cast<std::uint8_t>(v));
        EXPECT_EQ(static_cast<int>(std::nearbyint(f * 255.0f)), v) << v;
    }
}

TEST(Texture, EvenMipmapsAreCascadedAveragesOfTwoByTwoBlocks) {
    const TextureImage base = random_image(16, 8, 7);
    const auto levels = generate_mipmaps(base, true);
    ASSERT_EQ(levels.size(), 4u);  // 8x4, 4x2, 2x1, 1x1
    const TextureImage* src = &base;
    for (const auto& l : levels) {
        if (src->width % 2 == 0 && src->height % 2 == 0) {
            for (std::uint32_t y = 0; y < l.height; ++y)
                for (std::uint32_t x = 0; x < l.width; ++x)
                    for (std::size_t c = 0; c < 4; ++c) {
                        const auto avg = [](int a, int b) { return (a + b + 1) >> 1; };
                        const int want =
                            avg(avg(texel(*src, 2 * x, 2 * y, c), texel(*src, 2 * x + 1, 2 * y, c)),
                                avg(texel(*src, 2 * x, 2 * y + 1, c),
                                    texel(*src, 2 * x + 1, 2 * y + 1, c)));
                        ASSERT_EQ(texel(l, x, y, c), want) << l.width << "x" << l.height;
                    }
        }
        src = &l;
    }
    EXPECT_EQ(levels.back().width, 1u);
    EXPECT_EQ(levels.back().height, 1u);
}

TEST(Texture, AnOddLevelIsNotABoxFilter) {
    // 7 -> 3 samples the old level at 0.67, 3.0 and 5.33 texels: the middle texel of the new
    // level is the old texel 3 alone (weight 0 on the 8.8 grid), not an average.
    TextureImage base;
    base.width = 7;
    base.height = 1;
    for (int x = 0; x < 7; ++x) {
        for (int c = 0; c < 4; ++c) base.rgba.push_back(static_cast<std::uint8_t>(x * 30 + c));
    }
    const auto levels = generate_mipmaps(base, true);
    ASSERT_EQ(levels.front().width, 3u);
    EXPECT_EQ(texel(levels.front(), 1, 0, 0), texel(base, 3, 0, 0));
}

// glGenerateMipmap's blit interpolates its texture coordinates from the planes of the
// triangle a pixel lies in (the rectangle's fan split along its diagonal, each triangle's
// planes anchored at its first vertex after setup's swap), not at the exact texel centre
// (i + 0.5) / w'. The texels below were measured against llvmpipe (gl_mipmap_probe_test.cpp);
// the centre rule reads row 1492 with weight 255/256 and column 0 with weight 129/256.
TEST(Texture, GeneratedLevelsSampleWhereTheBlitInterpolates) {
    // 1x2999 -> 1x1499, row 746 (the lower triangle, anchored at t = 0): the blit's t is
    // on texel 1493 exactly (weight 0); the centre rule's is 1/256 texel below it.
    TextureImage tall;
    tall.width = 1;
    tall.height = 2999;
    tall.rgba.assign(std::size_t{2999} * 4, 0);
    for (std::size_t c = 0; c < 4; ++c) tall.rgba[4 * 1493 + c] = 255;
    for (const bool fma : {true, false}) {
        const TextureImage l1 = blit_level(tall, fma);
        ASSERT_EQ(l1.height, 1499u);
        EXPECT_EQ(texel(l1, 0, 746, 0), 255) << "fma " << fma;
    }
    // 511x1 -> 255x1, column 0 (the upper triangle, anchored at s = 1): weight 128 between
    // texels 0 and 1, so 255 and 0 give 255 + ((128 * -255 + 128) >> 8) = 128; the centre
    // rule's weight 129 gives 127.
    TextureImage wide;
    wide.width = 511;
    wide.height = 1;
    wide.rgba.assign(std::size_t{511} * 4, 0);
    for (std::size_t c = 0; c < 4; ++c) wide.rgba[c] = 255;
    const TextureImage w1 = blit_level(wide, true);
    ASSERT_EQ(w1.width, 255u);
    EXPECT_EQ(texel(w1, 0, 0, 0), 128);
}

TEST(Texture, BilinearWeightsRoundToNearestEvenOnTheGrid) {
    // A 1:1 mapping shifted by half of 1/256 texel puts u*W*256 exactly on k + 0.5: the
    // weight rounds to even, 0 here, so each pixel reads one texel unfiltered.
    const TextureImage img = random_image(16, 16, 3);
    const std::vector<TextureImage> levels{img};
    TextureState st;
    st.min_filter = st.mag_filter = TextureFilter::Linear;
    const TextureUnit u = make_texture_unit(st, levels);
    ASSERT_TRUE(u.aos);
    for (std::uint32_t x = 0; x < 16; ++x) {
        // u*4096 = 256*x + 128 + 0.5: S = 256*x + 128 (even), minus 128.
        const float s = (static_cast<float>(x) * 256.0f + 128.5f) / 4096.0f;
        const float t = (5.0f * 256.0f + 128.5f) / 4096.0f;
        const auto c = sample_one(u, s, t);
        for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(to_byte(c[k]), texel(img, x, 5, k)) << x;
    }
}

TEST(Texture, BilinearByteLerpRoundsWithPmulhrsw) {
    // Half way between two texels along s: L(128, a, b) = a + floor((128 (b - a) + 128) / 256).
    TextureImage img;
    img.width = 2;
    img.height = 1;
    img.rgba = {10, 0, 255, 7, 13, 255, 0, 8};
    const std::vector<TextureImage> levels{img};
    TextureState st;
    st.wrap_s = st.wrap_t = TextureWrap::ClampToEdge;
    const TextureUnit u = make_texture_unit(st, levels);
    // u*512 - 128 = 128 -> i0 = 0, weight 128 (the midpoint of the two texel centres).
    const auto c = sample_one(u, 0.5f, 0.5f);
    for (std::size_t k = 0; k < 4; ++k) {
        const int a = img.rgba[k];
        const int b = img.rgba[4 + k];
        const int want = a + static_cast<int>(std::floor((128.0 * (b - a) + 128.0) / 256.0));
        EXPECT_EQ(to_byte(c[k]), want) << k;
    }
}

TEST(Texture, NearestRepeatWrapsPowerOfTwoAndOtherSizes) {
    for (std::uint32_t w : {8u, 6u}) {
        const TextureImage img = random_image(w, 1, w);
        const std::vector<TextureImage> levels{img};
        TextureState st;
        st.min_filter = st.mag_filter = TextureFilter::Nearest;
        const TextureUnit u = make_texture_unit(st, levels);
        for (int i = -20; i < 20; ++i) {
            const float s = (static_cast<float>(i) + 0.5f) / static_cast<float>(w);
            const int n = static_cast<int>(w);
            const auto expect = static_cast<std::uint32_t>(((i % n) + n) % n);
            EXPECT_EQ(to_byte(sample_one(u, s, 0.5f)[0]), texel(img, expect, 0, 0))
                << w << " " << i;
        }
    }
}

TEST(Texture, MirroredRepeatReflectsEveryOtherCopy) {
    const TextureImage img = random_image(4, 1, 11);
    const std::vector<TextureImage> levels{img};
    TextureState st;
    st.min_filter = st.mag_filter = TextureFilter::Nearest;
    st.wrap_s = TextureWrap::MirroredRepeat;
    const TextureUnit u = make_texture_unit(st, levels);
    EXPECT_FALSE(u.aos);  // mirrored repeat sends both axes to the float path
    // Texel centres of the copy [1, 2) read the image backwards.
    for (std::uint32_t x = 0; x < 4; ++x) {
        const float s = 1.0f + (static_cast<float>(x) + 0.5f) / 4.0f;
        EXPECT_EQ(to_byte(sample_one(u, s, 0.5f)[0]), texel(img, 3 - x, 0, 0)) << x;
    }
}

TEST(Texture, ClampToBorderReadsTheBorderColourOutside) {
    const TextureImage img = random_image(4, 4, 5);
    const std::vector<TextureImage> levels{img};
    TextureState st;
    st.min_filter = st.mag_filter = TextureFilter::Nearest;
    st.wrap_s = st.wrap_t = TextureWrap::ClampToBorder;
    st.border_color = {0.25f, 0.5f, 1.0f, 0.0f};
    const TextureUnit u = make_texture_unit(st, levels);
    const auto out = sample_one(u, -0.1f, 0.5f);
    EXPECT_EQ(out[0], 0.25f);
    EXPECT_EQ(out[1], 0.5f);
    const auto in = sample_one(u, 0.6f, 0.6f);
    EXPECT_EQ(to_byte(in[0]), texel(img, 2, 2, 0));
}

// The border colour is clamped under DAZ (lp_build_clamp_border_color in the rasterizer's
// float mode): a denormal channel reads as +0, a normal one keeps its bits; without the
// profile's flush the denormal passes through the clamp unchanged.
TEST(Texture, ADenormalBorderColourReadsAsZero) {
    const std::vector<TextureImage> levels{random_image(2, 2, 6)};
    TextureState st;
    st.min_filter = st.mag_filter = TextureFilter::Nearest;
    st.wrap_s = st.wrap_t = TextureWrap::ClampToBorder;
    const float tiny = std::numeric_limits<float>::denorm_min();
    const float smallest_normal = std::numeric_limits<float>::min();
    st.border_color = {tiny, smallest_normal, -tiny, 1.0f};
    TextureUnit u = make_texture_unit(st, levels);
    ASSERT_TRUE(u.flush_border);
    const auto out = sample_one(u, 2.5f, 2.5f);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(out[0]), 0u);
    EXPECT_EQ(out[1], smallest_normal);
    EXPECT_EQ(std::bit_cast<std::uint32_t>(out[2]), 0u);
    u.flush_border = false;
    const auto kept = sample_one(u, 2.5f, 2.5f);
    EXPECT_EQ(kept[0], tiny);
}

// A NaN coordinate on a repeat axis whose base size is not a power of two: the nearest
// texel comes from lp_build_fract_safe, whose min with 1 - 2^-24 returns that bound for a NaN
// fraction (minps' second operand), so the last texel is read; a power-of-two axis masks
// floor's INT32_MIN to texel 0.
TEST(Texture, ANanCoordinateReadsTheLastTexelOfANpotRepeatAxis) {
    const TextureImage img = random_image(2, 7, 8);
    const std::vector<TextureImage> levels{img};
    TextureState st;
    st.min_filter = st.mag_filter = TextureFilter::Nearest;
    st.wrap_s = st.wrap_t = TextureWrap::Repeat;
    const TextureUnit u = make_texture_unit(st, levels);
    ASSERT_TRUE(u.aos);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const auto c = sample_one(u, nan, nan);
    for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(to_byte(c[k]), texel(img, 0, 6, k)) << k;
}

// A quad whose pixel steps along x and y are `d` in s and t: rho = d * W.
std::array<std::array<float, 4>, 4> sample_with_step(const TextureUnit& u, float d,
                                                     TexelSample* tr) {
    std::array<std::array<float, 4>, 4> out{};
    const float s0 = 0.25f, t0 = 0.25f;
    sample_quad(u, {s0, s0 + d, s0, s0 + d}, {t0, t0, t0 + d, t0 + d}, true, out, false, tr, 0);
    return out;
}

TEST(Texture, NearestMipLevelIsRoundedLog2OfRho) {
    TextureImage base = random_image(64, 64, 9);
    std::vector<TextureImage> levels{base};
    for (auto& l : generate_mipmaps(base, true)) levels.push_back(std::move(l));
    TextureState st;
    st.min_filter = TextureFilter::NearestMipmapNearest;
    st.mag_filter = TextureFilter::Nearest;
    const TextureUnit u = make_texture_unit(st, levels);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> logrho(0.01f, 8.0f);
    for (int i = 0; i < 2000; ++i) {
        const float rho = std::exp2(logrho(rng));
        TexelSample tr;
        sample_with_step(u, rho / 64.0f, &tr);
        ASSERT_TRUE(tr.minified);
        // The nearest integer to log2(rho), ties up (rho2 = 2 (d W)^2 here), clamped to the
        // chain; coordinates too close to a tie for double rounding to decide are skipped.
        const double exact = 0.5 * std::log2(static_cast<double>(tr.rho2));
        const double up = exact + 0.5;
        if (std::fabs(up - std::round(up)) < 1e-6) continue;
        const int want = std::clamp(static_cast<int>(std::floor(up)), 0, 6);
        EXPECT_EQ(static_cast<int>(tr.level0), want) << rho;
    }
}

TEST(Texture, TrilinearLodIsNeverAboveTheTrueOneAndAtMost0043Below) {
    TextureImage base = random_image(64, 64, 10);
    std::vector<TextureImage> levels{base};
    for (auto& l : generate_mipmaps(base, true)) levels.push_back(std::move(l));
    TextureState st;
    st.min_filter = TextureFilter::LinearMipmapLinear;
    const TextureUnit u = make_texture_unit(st, levels);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> logrho(0.05f, 5.0f);
    for (int i = 0; i < 2000; ++i) {
        TexelSample tr;
        sample_with_step(u, std::exp2(logrho(rng)) / 64.0f, &tr);
        const double exact = 0.5 * std::log2(static_cast<double>(tr.rho2));
        EXPECT_LE(tr.lod, exact + 1e-6);
        EXPECT_GE(tr.lod, exact - 0.0431);
        EXPECT_EQ(tr.level_weight8, static_cast<std::uint32_t>(tr.level_weight * 256.0f));
    }
}

TEST(Texture, EqualMinAndMagFiltersComputeNoLod) {
    const TextureImage img = random_image(8, 8, 4);
    const std::vector<TextureImage> levels{img};
    TextureState st;
    st.min_filter = st.mag_filter = TextureFilter::Nearest;
    EXPECT_FALSE(make_texture_unit(st, levels).needs_lod);
    st.mag_filter = TextureFilter::Linear;
    const TextureUnit u = make_texture_unit(st, levels);
    EXPECT_TRUE(u.needs_lod);
    TexelSample tr;
    sample_with_step(u, 0.5f, &tr);  // 4 texels a pixel: minified, the min filter (nearest)
    EXPECT_TRUE(tr.minified);
    EXPECT_FALSE(tr.linear);
    sample_with_step(u, 0.01f, &tr);
    EXPECT_FALSE(tr.minified);
    EXPECT_TRUE(tr.linear);
}

}  // namespace
}  // namespace refraster::detail
