// GL-free tests of rules the golden hashes alone covered: llvmpipe's unorm8 blending
// arithmetic, line coverage (one fragment a column or row, width in whole pixels), the
// clipper's edge flags in polygon mode line, the draw module's NaN polygon offset, and
// softpipe's colour tiles written back by a fill rule's stencil clear.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "models/llvmpipe/fragment.hpp"
#include "refraster/profile.hpp"
#include "refraster/renderer.hpp"

namespace {

using refraster::PrimitiveType;

TEST(UnormBlending, ProductApproximatesTheQuotientBy255) {
    // lp_build_mul_norm's (p + (p >> 8) + 128) >> 8 for p = x * y: exact at the ends (times 0 is
    // 0, times 255 is the other factor), symmetric, never more than half a step and 1/255 from
    // x * y / 255; and not always the rounded quotient: where the quotient's fraction is just
    // above one half it rounds down, which a reference must reproduce.
    int rounded_down = 0;
    for (std::uint32_t x = 0; x < 256; ++x) {
        ASSERT_EQ(refraster::detail::unorm8_mul(x, 0), 0);
        ASSERT_EQ(refraster::detail::unorm8_mul(x, 255), x);
        for (std::uint32_t y = 0; y < 256; ++y) {
            const auto m = refraster::detail::unorm8_mul(x, y);
            ASSERT_EQ(m, refraster::detail::unorm8_mul(y, x));
            const double q = static_cast<double>(x * y) / 255.0;
            ASSERT_LE(std::abs(m - q), 0.5 + 1.0 / 255.0) << x << " * " << y;
            rounded_down += m != (2 * x * y + 255) / 510;
        }
    }
    EXPECT_GT(rounded_down, 0);
    EXPECT_EQ(refraster::detail::unorm8_mul(152, 229), 136);  // 136.502 rounds down
}

refraster::Draw one_pixel_draw(refraster::BlendPreset blend, std::array<float, 4> color) {
    refraster::Draw d;
    d.primitive = PrimitiveType::Points;
    d.state.viewport = {0, 0, 1, 1};
    d.state.blend = blend;
    d.vertices.attributes = {{"color", 4}};
    d.vertices.data = {0, 0, 0, 1, color[0], color[1], color[2], color[3]};
    return d;
}

TEST(UnormBlending, PresetsOnBytes) {
    // Source bytes from the output conversion (tested with the attribute scenes); alpha: M(s, a) +
    // M(d, 255 - a), saturated; add: s + d, saturated.
    refraster::DrawList l;
    l.target = {1, 1, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    l.clear.color = {0.2f, 0.6f, 1.0f, 0.0f};
    const std::array<float, 4> src{0.9f, 0.3f, 0.5f, 0.25f};
    refraster::Framebuffer cleared;
    (void)refraster::render(l, cleared);
    const auto byte = [](float c) { return std::uint32_t{refraster::detail::color_to_unorm8(c)}; };
    const auto mul = [](std::uint32_t x, std::uint32_t y) {
        return (x * y + ((x * y) >> 8) + 128) >> 8;
    };
    for (auto blend : {refraster::BlendPreset::Alpha, refraster::BlendPreset::Add}) {
        l.draws = {one_pixel_draw(blend, src)};
        refraster::Framebuffer fb;
        ASSERT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
        const std::uint32_t a = byte(src[3]);
        for (std::size_t k = 0; k < 4; ++k) {
            const std::uint32_t s = byte(src[k]);
            const std::uint32_t d = cleared.color8[k];
            const std::uint32_t want = blend == refraster::BlendPreset::Alpha
                                           ? std::min(255u, mul(s, a) + mul(d, 255 - a))
                                           : std::min(255u, s + d);
            EXPECT_EQ(fb.color8[k], want) << "channel " << k;
        }
    }
}

refraster::DrawList target(std::uint32_t w, std::uint32_t h) {
    refraster::DrawList l;
    l.target = {w, h, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    l.clear.color = {0, 0, 0, 1};
    return l;
}

// Window-space positions into a draw over the whole target (w = 1).
refraster::Draw window_draw(PrimitiveType p, const refraster::Target& t,
                            const std::vector<std::array<float, 2>>& pos) {
    refraster::Draw d;
    d.primitive = p;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(t.width),
                        static_cast<std::int32_t>(t.height)};
    d.vertices.attributes = {{"color", 4}};
    for (const auto& v : pos) {
        const float x = v[0] / static_cast<float>(t.width) * 2.0f - 1.0f;
        const float y = v[1] / static_cast<float>(t.height) * 2.0f - 1.0f;
        d.vertices.data.insert(d.vertices.data.end(), {x, y, 0, 1, 1, 1, 1, 1});
    }
    return d;
}

// Lit pixels per column (x-major) or row (y-major).
std::map<int, int> lit_per(const refraster::Framebuffer& fb, bool columns) {
    std::map<int, int> n;
    for (std::uint32_t y = 0; y < fb.height; ++y) {
        for (std::uint32_t x = 0; x < fb.width; ++x) {
            if (fb.color8[4 * fb.index(x, y)] != 0) ++n[static_cast<int>(columns ? x : y)];
        }
    }
    return n;
}

TEST(LineCoverage, OneFragmentPerMajorStepTimesTheRoundedWidth) {
    // GL's line rasterization (OpenGL 4.6, 14.5.1 and 14.5.2): a width-1 x-major line gives
    // one fragment per column between its ends, a y-major one one per row; a wide line
    // util_iround(width) fragments per column (row). llvmpipe's parallelogram keeps this for
    // ends away from pixel centres.
    for (float width : {1.0f, 2.0f, 2.4f, 3.0f, 5.0f}) {
        const int per = static_cast<int>(std::lround(width));
        for (bool x_major : {true, false}) {
            auto l = target(64, 64);
            // Ends at fractional positions (no diamond ties), slopes below 1 in the major axis.
            const std::array<float, 2> a =
                x_major ? std::array<float, 2>{8.3f, 20.2f} : std::array<float, 2>{20.2f, 8.3f};
            const std::array<float, 2> b =
                x_major ? std::array<float, 2>{50.3f, 37.7f} : std::array<float, 2>{37.7f, 50.3f};
            auto d = window_draw(PrimitiveType::Lines, l.target, {a, b});
            d.state.line_width = width;
            l.draws = {d};
            refraster::Framebuffer fb;
            ASSERT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
            const auto n = lit_per(fb, x_major);
            // Columns (rows) 8 .. 49 hold the centres 8.5 .. 49.5 between the ends 8.3 and 50.3.
            EXPECT_EQ(n.size(), 42u) << "width " << width << (x_major ? " x-major" : " y-major");
            for (const auto& [c, k] : n) {
                EXPECT_EQ(k, per) << "width " << width << (x_major ? " column " : " row ") << c;
                EXPECT_GE(c, 8);
                EXPECT_LE(c, 49);
            }
        }
    }
}

TEST(ClipperEdgeFlags, EdgesMadeByTheClipperAreNotDrawn) {
    // Polygon mode line draws a polygon's boundary edges only (OpenGL 4.6, 14.6.4); the edges
    // the clipper creates along a clip plane are not boundary edges (draw_pipe_clip.c clears
    // their flags). A triangle reaching far beyond the right side of the viewport: its outline
    // inside the viewport is its two original edges; the viewport's last column is lit only
    // where those cross it, not along the cut.
    auto l = target(32, 32);
    auto d = window_draw(PrimitiveType::Triangles, l.target,
                         {{4.3f, 4.2f}, {90.7f, 16.4f}, {4.6f, 27.9f}});
    d.state.polygon_mode = refraster::PolygonMode::Line;
    l.draws = {d};
    refraster::Framebuffer fb;
    ASSERT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
    int last_column = 0, first_column = 0;
    for (std::uint32_t y = 0; y < 32; ++y) {
        last_column += fb.color8[4 * fb.index(31, y)] != 0;
        first_column += fb.color8[4 * fb.index(4, y)] != 0;
    }
    // The cut at x = 32 spans about 10 rows (y from about 11 to 21); only the two crossing
    // edges light the last column: at most two pixels each.
    EXPECT_GE(last_column, 2);
    EXPECT_LE(last_column, 4);
    // The unclipped left edge (x about 4.3 to 4.6, y 4 to 28) is drawn along its length.
    EXPECT_GE(first_column, 20);
    // Filled, the same triangle covers that column along the whole cut.
    l.draws[0].state.polygon_mode = refraster::PolygonMode::Fill;
    ASSERT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
    int filled = 0;
    for (std::uint32_t y = 0; y < 32; ++y) filled += fb.color8[4 * fb.index(31, y)] != 0;
    EXPECT_GE(filled, 8);
}

// A zero-area triangle of constant window z in polygon mode point or line, with polygon
// offset: draw_pipe_offset.c do_offset_tri's slopes are 0 * (1 / det) = 0 * inf = NaN, so the
// offset is NaN whatever the factor and units, and util/macros.h's SATURATE (CLAMP(z, 0, 1) =
// z > 0 ? (z > 1 ? 1 : z) : 0) makes every vertex depth 0, the near end: the points pass the
// depth test less against a cleared 0.5 and store 0. Measured with OSMesa llvmpipe and
// softpipe (z24 and z32f; less, equal, greater, notequal, always). Kept NaN
// (draw_offset_nan_to_zero=false), llvmpipe's fragment clamp makes it 1 and nothing is drawn.
TEST(DrawModuleOffset, ANanOffsetSaturatesToTheNearEnd) {
    for (const auto* profile_name : {"llvmpipe-22.3", "softpipe-22.3"}) {
        for (auto mode : {refraster::PolygonMode::Point, refraster::PolygonMode::Line}) {
            for (auto depth : {refraster::DepthFormat::Z32f, refraster::DepthFormat::Z24}) {
                for (bool nan_to_zero : {true, false}) {
                    // Kept NaN is llvmpipe's fragment clamp's to settle; softpipe's depth
                    // conversions of a NaN are another matter.
                    if (!nan_to_zero && std::string(profile_name) != "llvmpipe-22.3") continue;
                    SCOPED_TRACE(std::string(profile_name) +
                                 (mode == refraster::PolygonMode::Point ? " point" : " line") +
                                 (depth == refraster::DepthFormat::Z24 ? " z24" : " z32f") +
                                 (nan_to_zero ? "" : " kept NaN"));
                    auto l = target(16, 16);
                    l.target.depth = depth;
                    l.clear.depth = 0.5f;
                    // Collinear: det = (v0 - v2) x (v1 - v2) = (-9)(-4) - (-9)(-4) = 0 exactly.
                    auto d = window_draw(PrimitiveType::Triangles, l.target,
                                         {{3.5f, 3.5f}, {8.5f, 8.5f}, {12.5f, 12.5f}});
                    d.state.polygon_mode = mode;
                    d.state.depth_test = refraster::CompareFunc::Less;
                    d.state.polygon_offset = refraster::PolygonOffset{3.4e38f, 1e30f};
                    l.draws = {d};
                    refraster::RenderOptions o;
                    o.profile = refraster::builtin_profile(profile_name);
                    o.profile.quirks.draw_offset_nan_to_zero = nan_to_zero;
                    refraster::Framebuffer cleared;
                    refraster::Framebuffer fb;
                    ASSERT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
                    l.draws.clear();
                    ASSERT_EQ(refraster::render(l, o, cleared).status, refraster::RenderStatus::Ok);
                    // The first vertex's pixel.
                    const std::size_t i = fb.index(3, 3);
                    if (nan_to_zero) {
                        EXPECT_EQ(fb.color8[4 * i], 255);
                        EXPECT_EQ(fb.depth[i], 0u);  // z32f +0.0f and z24 0 alike
                    } else {
                        EXPECT_EQ(fb.color8[4 * i], 0);
                        EXPECT_EQ(fb.depth[i], cleared.depth[i]);
                    }
                }
            }
        }
    }
}

// offset_units_scale states another implementation's minimum resolvable difference r
// (OpenGL 4.6, 14.6.5) as a power of two times Mesa's: scale 2 with units u renders exactly as
// scale 1 with units 2u, in every model and through both offset paths (llvmpipe's setup for
// filled triangles, the draw module's stage for polygon mode line and under softpipe).
TEST(PolygonOffsetScale, ScaleTwoIsUnitsDoubled) {
    for (const auto* profile_name : {"llvmpipe-22.3", "softpipe-22.3", "gl-exact"}) {
        for (auto mode : {refraster::PolygonMode::Fill, refraster::PolygonMode::Line}) {
            if (mode == refraster::PolygonMode::Line && std::string(profile_name) == "gl-exact")
                continue;  // the exact model draws no polygon mode line
            for (auto depth : {refraster::DepthFormat::Z24, refraster::DepthFormat::Z16,
                               refraster::DepthFormat::Z32f}) {
                SCOPED_TRACE(std::string(profile_name) +
                             (mode == refraster::PolygonMode::Fill ? " fill " : " line ") +
                             std::to_string(static_cast<int>(depth)));
                const auto rendered = [&](float units, float scale) {
                    auto l = target(16, 16);
                    l.target.depth = depth;
                    auto d = window_draw(PrimitiveType::Triangles, l.target,
                                         {{1.5f, 1.5f}, {14.5f, 2.5f}, {3.5f, 13.5f}});
                    // A sloped depth: z = 0.25 + 0.01 x in clip space, so the factor term counts.
                    for (std::size_t v = 0; v < 3; ++v)
                        d.vertices.data[v * 8 + 2] = 0.25f + 0.01f * d.vertices.data[v * 8];
                    d.state.polygon_mode = mode;
                    d.state.depth_test = refraster::CompareFunc::Always;
                    d.state.polygon_offset = refraster::PolygonOffset{0.5f, units};
                    l.draws = {d};
                    refraster::RenderOptions o;
                    o.profile = refraster::builtin_profile(profile_name);
                    o.profile.gl.offset_units_scale = scale;
                    refraster::Framebuffer fb;
                    EXPECT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
                    return fb.depth;
                };
                const auto doubled = rendered(6.0f, 1.0f);
                EXPECT_EQ(rendered(3.0f, 2.0f), doubled);
                EXPECT_EQ(rendered(12.0f, 0.5f), doubled);
                EXPECT_NE(rendered(3.0f, 1.0f), doubled);  // the scale is read at all
            }
        }
    }
}

TEST(PolygonOffsetScale, OnlyPowersOfTwoFromASixteenthToSixteen) {
    refraster::Profile p = refraster::llvmpipe_22_3_profile();
    for (const char* ok : {"0.0625", "0.5", "1", "2", "16"}) {
        refraster::set_profile_parameter(p, "offset_units_scale", ok);
        EXPECT_EQ(p.gl.offset_units_scale, std::stof(ok)) << ok;
    }
    for (const char* bad : {"3", "0", "-2", "32", "0.03125", "nan", "inf", "2x", ""})
        EXPECT_THROW(refraster::set_profile_parameter(p, "offset_units_scale", bad),
                     refraster::ProfileError)
            << bad;
}

// point_line_clipping=pixels (Vulkan's rule, zink on lavapipe): a point whose centre is just
// outside the viewport still lights the pixels of it inside; no point lights a pixel outside
// the viewport. Under the default (GL's 13.7, by vertices) the first is dropped whole and a
// point inside near the edge lights pixels beyond it. Triangles keep their clipping.
TEST(PointLineClipping, PixelsClipsPointsToTheViewport) {
    const auto draw_points = [](const char* policy) {
        auto l = target(32, 32);
        refraster::Draw d;
        d.primitive = PrimitiveType::Points;
        d.state.viewport = {8, 8, 16, 16};
        d.state.point_size = 6.0f;
        d.vertices.attributes = {{"color", 4}};
        // Window (6.5, 16) is outside the viewport (x < 8); (9.5, 20) inside near its edge.
        for (const auto& p : {std::array<float, 2>{6.5f, 16.0f}, {9.5f, 20.0f}}) {
            const float x = (p[0] - 16.0f) / 8.0f;
            const float y = (p[1] - 16.0f) / 8.0f;
            d.vertices.data.insert(d.vertices.data.end(), {x, y, 0, 1, 1, 1, 1, 1});
        }
        l.draws = {d};
        refraster::RenderOptions o;
        o.profile = refraster::llvmpipe_22_3_profile();
        refraster::set_profile_parameter(o.profile, "point_line_clipping", policy);
        refraster::Framebuffer fb;
        EXPECT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
        return fb;
    };
    const auto lit = [](const refraster::Framebuffer& fb, std::uint32_t x, std::uint32_t y) {
        return fb.color8[4 * fb.index(x, y)] == 255;
    };
    const auto vertices = draw_points("vertices");
    const auto pixels = draw_points("pixels");
    // The outside point: dropped by its vertex, drawn inside the viewport by its pixels.
    EXPECT_FALSE(lit(vertices, 8, 16));
    EXPECT_TRUE(lit(pixels, 8, 16));
    // The inside point near the edge: beyond the viewport only by its vertex.
    EXPECT_TRUE(lit(vertices, 7, 20));
    EXPECT_FALSE(lit(pixels, 7, 20));
    EXPECT_TRUE(lit(pixels, 9, 20));
    for (std::uint32_t y = 0; y < 32; ++y)
        for (std::uint32_t x = 0; x < 8; ++x) EXPECT_FALSE(lit(pixels, x, y)) << x << "," << y;
    // The exact model has no clipper to apply it to.
    refraster::Profile exact = refraster::builtin_profile("gl-exact");
    EXPECT_TRUE(refraster::unread_parameter(exact, "point_line_clipping").has_value());
}

// A square over the whole target in clip space, as one polygon with a fill rule and a
// constant colour.
refraster::Draw fill_square(const refraster::Target& t, refraster::FillRule rule,
                            refraster::BlendPreset blend, std::array<float, 4> c) {
    refraster::Draw d;
    d.primitive = PrimitiveType::Polygon;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(t.width),
                        static_cast<std::int32_t>(t.height)};
    d.state.fill_rule = rule;
    d.state.blend = blend;
    d.vertices.attributes = {{"color", 4}};
    for (const auto& p : {std::array<float, 2>{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        d.vertices.data.insert(d.vertices.data.end(), {p[0], p[1], 0, 1, c[0], c[1], c[2], c[3]});
    }
    return d;
}

// softpipe keeps colours as floats in its tile cache until a tile is written back
// (softpipe_tiles.hpp). A draw with a fill rule starts with a clear of the stencil alone, which
// softpipe does with util_clear_depth_stencil, whose map of the depth-stencil surface flushes
// the context (sp_clear.c softpipe_clear, sp_texture.c softpipe_transfer_map, sp_flush.c
// softpipe_flush_resource): every colour tile is written back as bytes, so a blend in or after
// that draw reads byte * (1/255), not the raw clear colour or the earlier draw's floats.
TEST(SoftpipeFillRule, TheStencilClearWritesTheColourTilesBack) {
    const auto byte = [](float c) { return refraster::detail::color_to_unorm8(c); };
    const auto reload = [&](float c) { return static_cast<float>(byte(c)) * (1.0f / 255.0f); };
    // sp_quad_blend.c: src * a + dst * (1 - a) in float, then float_to_ubyte on write-back.
    const auto alpha_blend = [&](float s, float a, float d) {
        return byte(s * a + d * (1.0f - a));
    };
    const std::array<float, 4> clear{0.3f, 0.1f, 0.7f, 1.0f};
    const std::array<float, 4> first{0.65f, 0.3f, 0.45f, 1.0f};
    const std::array<float, 4> src{0.5f, 0.5f, 0.25f, 0.3f};
    for (bool writes_back : {true, false}) {
        SCOPED_TRACE(writes_back ? "written back" : "floats kept (fill_clear_writes_tiles=false)");
        refraster::RenderOptions o;
        o.profile = refraster::softpipe_22_3_profile();
        o.profile.quirks.fill_clear_writes_tiles = writes_back;
        // 1. Over the clear colour.
        auto l = target(8, 8);
        l.clear.color = clear;
        l.draws = {fill_square(l.target, refraster::FillRule::NonZero,
                               refraster::BlendPreset::Alpha, src)};
        refraster::Framebuffer fb;
        ASSERT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
        int differ = 0;
        for (std::size_t k = 0; k < 4; ++k) {
            const auto bytes = alpha_blend(src[k], src[3], reload(clear[k]));
            const auto floats = alpha_blend(src[k], src[3], clear[k]);
            differ += bytes != floats;
            EXPECT_EQ(fb.color8[4 * fb.index(5, 2) + k], writes_back ? bytes : floats)
                << "channel " << k;
        }
        EXPECT_GT(differ, 0);  // the two rules differ here: 91 against 92 in red
        // 2. Over an earlier fill's colour.
        l.clear.color = {0, 0, 0, 1};
        l.draws = {fill_square(l.target, refraster::FillRule::EvenOdd, refraster::BlendPreset::None,
                               first),
                   fill_square(l.target, refraster::FillRule::NonZero,
                               refraster::BlendPreset::Alpha, src)};
        ASSERT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
        differ = 0;
        for (std::size_t k = 0; k < 4; ++k) {
            const auto bytes = alpha_blend(src[k], src[3], reload(first[k]));
            const auto floats = alpha_blend(src[k], src[3], first[k]);
            differ += bytes != floats;
            EXPECT_EQ(fb.color8[4 * fb.index(2, 6) + k], writes_back ? bytes : floats)
                << "channel " << k;
        }
        EXPECT_GT(differ, 0);  // green 91 against 92, blue 100 against 99
    }
}

}  // namespace
