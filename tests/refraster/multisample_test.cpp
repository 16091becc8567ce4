// 4x multisampling in the reference: where samples are tested, what each sample receives, the
// scissor's half-pixel leak, rectangle lines, quad points and the resolve (docs/precision.md,
// "Multisampling (4x)").
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "refraster/framebuffer.hpp"
#include "refraster/renderer.hpp"

namespace {

using refraster::ColorFormat;
using refraster::DepthFormat;
using refraster::PrimitiveType;

constexpr std::uint32_t kSize = 32;  // a power of two: window positions survive the round trip

refraster::DrawList target_4x(DepthFormat depth = DepthFormat::None) {
    refraster::DrawList l;
    l.target = {kSize, kSize, ColorFormat::Rgba8, depth, 4};
    l.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};
    return l;
}

// Window-space (x, y, z) positions and colours into a draw over the whole target (w = 1).
refraster::Draw window_draw(PrimitiveType p, const std::vector<std::array<float, 3>>& pos,
                            const std::vector<std::array<float, 4>>& colors = {}) {
    refraster::Draw d;
    d.primitive = p;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(kSize), static_cast<std::int32_t>(kSize)};
    d.vertices.attributes = {{"color", 4}};
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const auto& v = pos[i];
        const auto c = colors.empty() ? std::array<float, 4>{1, 1, 1, 1} : colors[i];
        d.vertices.data.insert(d.vertices.data.end(),
                               {v[0] / static_cast<float>(kSize) * 2.0f - 1.0f,
                                v[1] / static_cast<float>(kSize) * 2.0f - 1.0f, v[2] * 2.0f - 1.0f,
                                1.0f, c[0], c[1], c[2], c[3]});
    }
    return d;
}

refraster::Framebuffer render(const refraster::DrawList& l) {
    refraster::Framebuffer fb;
    const auto r = refraster::render(l, fb);
    EXPECT_EQ(r.status, refraster::RenderStatus::Ok) << r.message;
    return fb;
}

// Bit s set when sample s of pixel (x, y) holds a non-zero red channel.
unsigned lit_samples(const refraster::Framebuffer& fb, std::uint32_t x, std::uint32_t y) {
    unsigned m = 0;
    for (std::uint32_t s = 0; s < 4; ++s) {
        if (fb.color8[4 * fb.sample_index(x, y, s)] != 0) m |= 1u << s;
    }
    return m;
}

// A quad (two triangles) over [x0, x1] x [y0, y1].
refraster::Draw quad(float x0, float y0, float x1, float y1) {
    return window_draw(
        PrimitiveType::Triangles,
        {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y0, 0}, {x1, y1, 0}, {x0, y1, 0}});
}

TEST(Multisample, TheTieRuleIsDecidedAtTheSample) {
    // Sample 0 of pixel 10 lies at x = 10.375. A quad whose left edge passes exactly through
    // it owns it; one whose right edge does leaves it out. Samples 2 (x 10.125) and 1, 3
    // (x 10.875, 10.625) fall on either side.
    auto l = target_4x();
    l.draws.push_back(quad(10.375f, 4.0f, 20.0f, 8.0f));
    auto fb = render(l);
    EXPECT_EQ(lit_samples(fb, 10, 5), 0b1011u);  // 0 (on the left edge), 1, 3
    l.draws = {quad(2.0f, 4.0f, 10.375f, 8.0f)};
    fb = render(l);
    EXPECT_EQ(lit_samples(fb, 10, 5), 0b0100u);  // only sample 2: sample 0 is on the right edge
    // The same for a horizontal edge through sample 1 (y = 5.375): bottom owns, top does not.
    l.draws = {quad(2.0f, 5.375f, 20.0f, 9.0f)};
    fb = render(l);
    EXPECT_EQ(lit_samples(fb, 8, 5), 0b1110u);
    l.draws = {quad(2.0f, 2.0f, 20.0f, 5.375f)};
    fb = render(l);
    EXPECT_EQ(lit_samples(fb, 8, 5), 0b0001u);
}

TEST(Multisample, ColourOncePerPixelDepthPerSample) {
    // A smooth, sloped, depth-tested triangle: the covered samples of an inner pixel share
    // one colour (shaded at the centre) and have depths that differ (evaluated at each
    // sample), increasing with x + y as the plane does.
    auto l = target_4x(DepthFormat::Z32f);
    auto d = window_draw(PrimitiveType::Triangles, {{1, 1, 0.0f}, {31, 1, 0.5f}, {1, 31, 1.0f}},
                         {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}});
    d.state.depth_test = refraster::CompareFunc::Always;
    l.draws.push_back(d);
    const auto fb = render(l);
    const std::uint32_t x = 8, y = 8;
    for (std::uint32_t s = 1; s < 4; ++s) {
        for (std::uint32_t c = 0; c < 4; ++c) {
            EXPECT_EQ(fb.color8[4 * fb.sample_index(x, y, s) + c],
                      fb.color8[4 * fb.sample_index(x, y, 0) + c]);
        }
    }
    const auto z = [&](std::uint32_t s) {
        return std::bit_cast<float>(fb.depth[fb.sample_index(x, y, s)]);
    };
    // Depth grows with x (0.5 over 30 pixels) and with y (1 over 30): the sample order by
    // x/2 + y is 0 (0.3125), 1 (0.8125), 2 (0.6875), 3 (1.1875).
    EXPECT_LT(z(0), z(2));
    EXPECT_LT(z(2), z(1));
    EXPECT_LT(z(1), z(3));
}

TEST(Multisample, OffOnA4xTargetFillsEverySampleOfACoveredPixel) {
    auto l = target_4x();
    auto d = window_draw(PrimitiveType::Triangles,
                         {{1.3f, 1.7f, 0}, {29.1f, 5.2f, 0}, {7.9f, 27.4f, 0}});
    d.state.multisample = false;
    l.draws.push_back(d);
    const auto fb = render(l);
    int partial = 0, full = 0;
    for (std::uint32_t y = 0; y < kSize; ++y) {
        for (std::uint32_t x = 0; x < kSize; ++x) {
            const unsigned m = lit_samples(fb, x, y);
            partial += m != 0 && m != 0xf;
            full += m == 0xf;
        }
    }
    EXPECT_EQ(partial, 0);
    EXPECT_GT(full, 100);
    // With it on, the same triangle leaves partly covered pixels along its edges.
    l.draws[0].state.multisample = true;
    const auto ms = render(l);
    int ms_partial = 0;
    for (std::uint32_t y = 0; y < kSize; ++y) {
        for (std::uint32_t x = 0; x < kSize; ++x) {
            const unsigned m = lit_samples(ms, x, y);
            ms_partial += m != 0 && m != 0xf;
        }
    }
    EXPECT_GT(ms_partial, 20);
}

TEST(Multisample, ScissorLeaksHalfAPixelOnTheLeftAndBottomForTriangles) {
    // llvmpipe's scissor planes get +127 under multisampling: the column left of the scissor
    // keeps samples 1 and 3, the row below samples 2 and 3, the corner sample 3 only; right
    // and top stay exact.
    auto l = target_4x();
    auto d = quad(0, 0, 32, 32);
    d.state.scissor = refraster::Rect{5, 7, 13, 9};
    l.draws.push_back(d);
    const auto fb = render(l);
    EXPECT_EQ(lit_samples(fb, 4, 10), 0b1010u);
    EXPECT_EQ(lit_samples(fb, 10, 6), 0b1100u);
    EXPECT_EQ(lit_samples(fb, 4, 6), 0b1000u);
    EXPECT_EQ(lit_samples(fb, 5, 7), 0xfu);
    EXPECT_EQ(lit_samples(fb, 17, 15), 0xfu);
    EXPECT_EQ(lit_samples(fb, 18, 10), 0u);
    EXPECT_EQ(lit_samples(fb, 10, 16), 0u);
    EXPECT_EQ(lit_samples(fb, 3, 10), 0u);
    // Points are cut at the scissor's pixels.
    auto p = window_draw(PrimitiveType::Points, {{5.0f, 10.5f, 0}});
    p.state.point_size = 4.0f;
    p.state.scissor = refraster::Rect{5, 7, 13, 9};
    l.draws = {p};
    const auto pf = render(l);
    EXPECT_EQ(lit_samples(pf, 4, 10), 0u);
    EXPECT_EQ(lit_samples(pf, 5, 10), 0xfu);
    // Without multisampling the scissor is exact.
    d.state.multisample = false;
    l.draws = {d};
    const auto off = render(l);
    EXPECT_EQ(lit_samples(off, 4, 10), 0u);
    EXPECT_EQ(lit_samples(off, 10, 6), 0u);
}

TEST(Multisample, LinesAreRectanglesOfTheUnroundedWidth) {
    // A horizontal line from x 2 to 12 at y 8.5: width 1 covers y in (8, 9), every sample of
    // row 8 between the ends and nothing else; width 1.5 reaches y 7.75 and 9.25, taking the
    // samples of rows 7 and 9 inside that band (sample 3 of row 7 at y 7.875, sample 0 of
    // row 9 at y 9.125).
    auto l = target_4x();
    auto d = window_draw(PrimitiveType::Lines, {{2.0f, 8.5f, 0}, {12.0f, 8.5f, 0}});
    l.draws.push_back(d);
    auto fb = render(l);
    for (std::uint32_t x = 2; x < 12; ++x) EXPECT_EQ(lit_samples(fb, x, 8), 0xfu) << x;
    EXPECT_EQ(lit_samples(fb, 1, 8), 0u);
    EXPECT_EQ(lit_samples(fb, 12, 8), 0u);
    EXPECT_EQ(lit_samples(fb, 6, 7), 0u);
    EXPECT_EQ(lit_samples(fb, 6, 9), 0u);
    l.draws[0].state.line_width = 1.5f;
    fb = render(l);
    EXPECT_EQ(lit_samples(fb, 6, 7), 0b1000u);
    EXPECT_EQ(lit_samples(fb, 6, 9), 0b0001u);
    // No diamond rule at the ends: the last pixel's samples left of x 12 are covered.
    EXPECT_EQ(lit_samples(fb, 11, 8), 0xfu);
}

TEST(Multisample, PointsAreSquaresTestedAtTheSamples) {
    // Size 1 at (10.3, 6.5): snapped origin x 10.3 - 0.5 = 9.8 (2637 - 128 = 2509 in 1/256),
    // side 256: samples with 2509 <= 256 px + sx < 2765, i.e. pixel 9's samples at x 9.875
    // (1) and pixel 10's at 10.125, 10.375, 10.625 (2, 0, 3); y from 6 to 7: all four rows.
    auto l = target_4x();
    l.draws.push_back(window_draw(PrimitiveType::Points, {{10.3f, 6.5f, 0}}));
    const auto fb = render(l);
    EXPECT_EQ(lit_samples(fb, 9, 6), 0b0010u);
    EXPECT_EQ(lit_samples(fb, 10, 6), 0b1101u);
    EXPECT_EQ(lit_samples(fb, 11, 6), 0u);
}

TEST(Multisample, ResolveIsTheFloatMeanInSampleOrder) {
    // Resolves measured on llvmpipe 22.3 (docs/precision.md, "Resolve") (samples -> resolved byte).
    const std::vector<std::pair<std::array<std::uint8_t, 4>, std::uint8_t>> table{
        {{255, 0, 0, 0}, 64},   {{255, 255, 0, 0}, 128},    {{255, 255, 255, 0}, 191},
        {{1, 1, 0, 0}, 0},      {{3, 0, 0, 0}, 1},          {{10, 11, 0, 0}, 5},
        {{128, 129, 0, 0}, 64}, {{254, 255, 255, 255}, 255}};
    for (const auto& [samples, resolved] : table) {
        refraster::Framebuffer ms(1, 1, ColorFormat::Rgba8, DepthFormat::None, 4);
        for (std::size_t s = 0; s < 4; ++s) ms.color8[4 * s] = samples[s];
        EXPECT_EQ(refraster::resolve_samples(ms).color8[0], resolved)
            << int{samples[0]} << "," << int{samples[1]} << "," << int{samples[2]} << ","
            << int{samples[3]};
    }
    // rgba32f: the same sum and scale, without conversion; depth and owners are sample 0's.
    refraster::Framebuffer f(1, 1, ColorFormat::Rgba32f, DepthFormat::Z24, 4);
    f.owner = {7, 8, 9, 10};
    for (std::size_t s = 0; s < 4; ++s) {
        f.color32f[4 * s] = 0.1f * static_cast<float>(s + 1);
        f.depth[s] = static_cast<std::uint32_t>(100 + s);
    }
    const auto r = refraster::resolve_samples(f);
    EXPECT_EQ(r.color32f[0], (((0.1f + 0.2f) + 0.3f) + 0.4f) * 0.25f);
    EXPECT_EQ(r.depth[0], 100u);
    EXPECT_EQ(r.owner, std::vector<std::uint32_t>{7});
    const auto plane = refraster::sample_plane(f, 2);
    EXPECT_EQ(plane.color32f[0], 0.3f);
    EXPECT_EQ(plane.depth[0], 102u);
    EXPECT_EQ(plane.owner, std::vector<std::uint32_t>{9});
}

// A pixel whose samples are equal resolves to their bytes (the shortcut resolve.cpp takes for
// them), beside pixels whose samples differ, in one image.
TEST(Multisample, ResolveOfEqualSamplesKeepsTheirBytes) {
    refraster::Framebuffer ms(256, 2, ColorFormat::Rgba8, DepthFormat::None, 4);
    for (std::size_t x = 0; x < 256; ++x) {
        for (std::size_t s = 0; s < 4; ++s) {
            for (std::size_t c = 0; c < 4; ++c) {
                const auto v = static_cast<std::uint8_t>((x + 85 * c) % 256);
                ms.color8[(x * 4 + s) * 4 + c] = v;
                // Row 1: sample 3 one above (255 wraps to 0).
                ms.color8[((256 + x) * 4 + s) * 4 + c] =
                    s == 3 ? static_cast<std::uint8_t>(v + 1) : v;
            }
        }
    }
    const auto r = refraster::resolve_samples(ms);
    for (std::size_t x = 0; x < 256; ++x) {
        for (std::size_t c = 0; c < 4; ++c) {
            const auto v = static_cast<std::uint8_t>((x + 85 * c) % 256);
            ASSERT_EQ(r.color8[x * 4 + c], v) << "pixel " << x << " channel " << c;
            // The float mean in sample order: (((v + v) + v) + (v + 1)) / 4 in unorm8 units.
            const float k = 1.0f / 255.0f;
            const auto w = static_cast<std::uint8_t>(v + 1);
            float sum = 0.0f;
            for (const std::uint8_t b : {v, v, v, w}) sum += static_cast<float>(b) * k;
            const float mean = sum * 0.25f;
            const auto expected = static_cast<std::uint8_t>(
                mean >= 1.0f ? 255.0f : (mean > 0.0f ? std::nearbyint(mean * 255.0f) : 0.0f));
            ASSERT_EQ(r.color8[(256 + x) * 4 + c], expected) << "pixel " << x << " channel " << c;
        }
    }
}

TEST(Multisample, OwnersArePerSample) {
    auto l = target_4x();
    l.draws.push_back(quad(2.0f, 2.0f, 10.375f, 8.0f));
    l.draws.push_back(quad(10.375f, 2.0f, 20.0f, 8.0f));
    refraster::RenderOptions o;
    o.record_owners = true;
    refraster::Framebuffer fb;
    ASSERT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
    ASSERT_EQ(fb.owner.size(), std::size_t{kSize} * kSize * 4);
    // Pixel 10: sample 2 from the first draw, the others from the second.
    EXPECT_EQ(fb.owner[fb.sample_index(10, 5, 2)] >> 24, 0u);
    EXPECT_NE(fb.owner[fb.sample_index(10, 5, 2)], 0u);
    EXPECT_EQ(fb.owner[fb.sample_index(10, 5, 0)] >> 24, 1u);
}

}  // namespace

namespace {

TEST(Multisample, TheTraceFollowsTheSample) {
    // Sample 0 of pixel (10, 5) lies exactly on the quad's left edge (owned: covered); sample
    // 2 lies left of it (not covered). The trace evaluates the edges at the sample asked for.
    auto l = target_4x();
    l.draws.push_back(quad(10.375f, 4.0f, 20.0f, 8.0f));
    const auto traced = [&](int sample) {
        refraster::PixelTrace t;
        t.x = 10;
        t.y = 5;
        t.sample = sample;
        refraster::RenderOptions o;
        o.trace = &t;
        refraster::Framebuffer fb;
        EXPECT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
        return t;
    };
    const auto t0 = traced(0);
    bool tie_owned = false, covered = false;
    for (const auto& p : t0.primitives) {
        EXPECT_TRUE(p.multisample);
        covered = covered || p.covered;
        for (const auto& s : p.setups) {
            for (const auto& e : s.edges) tie_owned = tie_owned || (e.tie && e.owns_ties);
        }
    }
    EXPECT_TRUE(covered);
    EXPECT_TRUE(tie_owned);
    EXPECT_EQ(t0.final_color[0], 255.0f);
    const auto t2 = traced(2);
    bool covered2 = false;
    for (const auto& p : t2.primitives) covered2 = covered2 || p.covered;
    EXPECT_FALSE(covered2);
    EXPECT_EQ(t2.final_color[0], 0.0f);
}

}  // namespace
