// softpipe's colour tile cache (refraster/src/models/softpipe/softpipe_tiles.hpp) and depth
// conversion (softpipe_fragment.hpp), each against values derived by hand from the rules of
// docs/precision.md "softpipe": raw clear floats until written back, write-back on eviction of
// a direct-mapped slot and at the flush, reload as byte * (1/255); the generic path's unclamped
// truncation with cvttss2si's wrap.
#include "models/softpipe/softpipe_fragment.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

#include "models/softpipe/softpipe_tiles.hpp"
#include "refraster/framebuffer.hpp"

namespace {

using refraster::ColorFormat;
using refraster::DepthFormat;
using refraster::Framebuffer;
using refraster::detail::softpipe_depth_value;
using refraster::detail::SoftpipeTileCache;

TEST(SoftpipeTiles, ClearColourStaysRawUntilWrittenBack) {
    Framebuffer fb(64, 64, ColorFormat::Rgba8, DepthFormat::None);
    SoftpipeTileCache tiles(fb, std::array<float, 4>{0.3f, 1.5f, -0.25f, 0.5f});
    tiles.fetch(10, 10);
    const float* p = tiles.pixel(10, 10);
    EXPECT_EQ(p[0], 0.3f);  // not 77 / 255
    EXPECT_EQ(p[1], 1.5f);  // not clamped
    EXPECT_EQ(p[2], -0.25f);
    tiles.flush();
    // float_to_ubyte: the clamp, then RNE(fl(c * 255)): 0.3f * 255 = 76.4999... -> 76.
    const std::size_t i = 4 * fb.index(10, 10);
    EXPECT_EQ(fb.color8[i + 0], 76);
    EXPECT_EQ(fb.color8[i + 1], 255);
    EXPECT_EQ(fb.color8[i + 2], 0);
    EXPECT_EQ(fb.color8[i + 3], 128);  // 127.5 -> even 128
}

TEST(SoftpipeTiles, EvictionWritesBackAndReloadsBytes) {
    // 11 tiles tall: tile (0, 10) lands in slot (0 + 5 * 10) % 50 = 0, tile (0, 0)'s.
    Framebuffer fb(64, 704, ColorFormat::Rgba8, DepthFormat::None);
    SoftpipeTileCache tiles(fb, std::array<float, 4>{0.0f, 0.0f, 0.0f, 0.0f});
    tiles.fetch(5, 5);
    tiles.pixel(5, 5)[0] = 0.3f;
    tiles.fetch(5, 645);  // evicts tile (0, 0)
    EXPECT_EQ(fb.color8[4 * fb.index(5, 5)], 76);
    tiles.fetch(5, 5);  // reloads it from the bytes
    EXPECT_EQ(tiles.pixel(5, 5)[0], 76.0f * (1.0f / 255.0f));
    EXPECT_NE(tiles.pixel(5, 5)[0], 0.3f);
    // A tile of another slot is not disturbed.
    tiles.fetch(5, 69);
    tiles.pixel(5, 69)[1] = 0.7f;
    tiles.fetch(5, 5);
    EXPECT_EQ(tiles.pixel(5, 69)[1], 0.7f);
}

TEST(SoftpipeTiles, FloatTargetsKeepTheirBits) {
    Framebuffer fb(64, 64, ColorFormat::Rgba32f, DepthFormat::None);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    SoftpipeTileCache tiles(fb, std::array<float, 4>{-2.5f, 1e30f, nan, 1e-40f});
    tiles.flush();
    const std::size_t i = 4 * fb.index(3, 60);
    EXPECT_EQ(fb.color32f[i + 0], -2.5f);
    EXPECT_EQ(fb.color32f[i + 1], 1e30f);
    EXPECT_TRUE(std::isnan(fb.color32f[i + 2]));
    EXPECT_EQ(std::bit_cast<std::uint32_t>(fb.color32f[i + 3]),
              std::bit_cast<std::uint32_t>(1e-40f));
}

TEST(SoftpipeDepth, GenericPathTruncatesWithoutClampAndWraps) {
    // (unsigned)(z * 16777215.0f): truncation, no rounding.
    EXPECT_EQ(softpipe_depth_value(0.5f, DepthFormat::Z24), 8388607u);
    EXPECT_EQ(softpipe_depth_value(0.5f, DepthFormat::Z24, true), 8388608u);
    // Just above 1: beyond 2^24 - 1 (the caller keeps the low 24 bits when it stores).
    EXPECT_EQ(softpipe_depth_value(1.0000012f, DepthFormat::Z24),
              static_cast<std::uint32_t>(1.0000012f * 16777215.0f));
    // Negative: cvttss2si to 64 bits, the low 32 kept.
    EXPECT_EQ(softpipe_depth_value(-4.5f / 16777215.0f, DepthFormat::Z24), 0xfffffffcu);
    // NaN: the integer indefinite, whose low 32 bits are 0.
    EXPECT_EQ(softpipe_depth_value(std::numeric_limits<float>::quiet_NaN(), DepthFormat::Z16), 0u);
    // z32f: the float itself, unclamped.
    EXPECT_EQ(softpipe_depth_value(-0.125f, DepthFormat::Z32f),
              std::bit_cast<std::uint32_t>(-0.125f));
}

}  // namespace
