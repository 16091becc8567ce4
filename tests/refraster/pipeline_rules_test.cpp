// GL-free tests of rules the golden hashes alone covered: llvmpipe's unorm8 blending
// arithmetic, line coverage (one fragment a column or row, width in whole pixels), and the
// clipper's edge flags in polygon mode line.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "models/llvmpipe/fragment.hpp"
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

}  // namespace
