// Coverage rules, each checked on pixels derived by hand from the rule it states
// (docs/precision.md "Snapping", "Edge functions and the tie rule"; the exact oracle;
// culling; clipping).
#include <gtest/gtest.h>

#include <set>

#include "refraster/renderer.hpp"

namespace {

using refraster::DrawList;
using refraster::PrimitiveType;
using Pixel = std::pair<int, int>;

constexpr int kSize = 32;  // power of two: window <-> clip conversions are exact

// A draw of window-space triangles (z = 0, w = 1) on a 32x32 target, flat white.
DrawList triangles(const std::vector<std::array<float, 2>>& win, refraster::DrawState state = {}) {
    DrawList l;
    l.target = {kSize, kSize, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    l.clear.color = {0, 0, 0, 1};
    refraster::Draw d;
    d.primitive = PrimitiveType::Triangles;
    state.viewport = {0, 0, kSize, kSize};
    state.shade = refraster::ShadeModel::Flat;
    d.state = state;
    d.vertices.attributes = {{"color", 4}};
    for (const auto& p : win) {
        const float x = p[0] / (kSize / 2.0f) - 1.0f;
        const float y = p[1] / (kSize / 2.0f) - 1.0f;
        d.vertices.data.insert(d.vertices.data.end(), {x, y, 0.0f, 1.0f, 1, 1, 1, 1});
    }
    l.draws.push_back(d);
    return l;
}

std::set<Pixel> lit(const DrawList& l, const refraster::Profile& profile = {}) {
    refraster::Framebuffer fb;
    refraster::RenderOptions o;
    o.profile = profile;
    const auto r = refraster::render(l, o, fb);
    EXPECT_EQ(r.status, refraster::RenderStatus::Ok) << r.message;
    std::set<Pixel> s;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            if (fb.color8[4 * fb.index(static_cast<std::uint32_t>(x),
                                       static_cast<std::uint32_t>(y))] != 0) {
                s.insert({x, y});
            }
        }
    }
    return s;
}

std::set<Pixel> box(int x0, int y0, int x1, int y1) {
    std::set<Pixel> s;
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) s.insert({x, y});
    }
    return s;
}

// Two triangles forming [x0,x1] x [y0,y1], counter-clockwise or clockwise.
std::vector<std::array<float, 2>> square(float x0, float y0, float x1, float y1, bool ccw) {
    if (ccw) return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y0}, {x1, y1}, {x0, y1}};
    return {{x0, y0}, {x1, y1}, {x1, y0}, {x0, y0}, {x0, y1}, {x1, y1}};
}

TEST(CoverageRules, SquareThroughCentresOwnsLeftAndBottom) {
    // Edges at 10.5 and 20.5 pass through pixel centres: llvmpipe lights the left column and
    // the bottom row, not the right column or the top row (1.4), in either winding.
    for (bool ccw : {true, false}) {
        EXPECT_EQ(lit(triangles(square(10.5f, 10.5f, 20.5f, 20.5f, ccw))), box(10, 10, 19, 19))
            << ccw;
    }
}

TEST(CoverageRules, FlippedTieRuleOwnsRightAndTop) {
    refraster::Profile p;
    p.gl.tie_rule = refraster::TieRule::RightTop;
    EXPECT_EQ(lit(triangles(square(10.5f, 10.5f, 20.5f, 20.5f, true)), p), box(11, 11, 20, 20));
}

TEST(CoverageRules, SnappingRoundsToNearestEvenAt256th) {
    // Left edge at 10.5 + 1/512: (x - 0.5) * 256 = 2560.5 rounds to even 2560, a tie the left
    // edge owns, so column 10 stays lit; at 10.5 + 3/512, 2561.5 rounds to 2562 and it goes.
    EXPECT_EQ(lit(triangles(square(10.5f + 1.0f / 512, 10.5f, 20.5f, 20.5f, true))),
              box(10, 10, 19, 19));
    EXPECT_EQ(lit(triangles(square(10.5f + 3.0f / 512, 10.5f, 20.5f, 20.5f, true))),
              box(11, 10, 19, 19));
    // A right edge at 20.5 + 1/512 snaps back onto the centre: column 20 stays dark (round
    // half up would have lit it).
    EXPECT_EQ(lit(triangles(square(10.5f, 10.5f, 20.5f + 1.0f / 512, 20.5f, true))),
              box(10, 10, 19, 19));
    // Offsets of 1/1024 snap back onto the centre both ways.
    EXPECT_EQ(lit(triangles(square(10.5f - 1.0f / 1024, 10.5f, 20.5f + 1.0f / 1024, 20.5f, true))),
              box(10, 10, 19, 19));
}

TEST(CoverageRules, ExactOracleDoesNotSnap) {
    // Without snapping a left edge 1/512 to the right of the centres no longer covers them.
    const auto exact = refraster::gl_exact_profile();
    EXPECT_EQ(lit(triangles(square(10.5f + 1.0f / 512, 10.5f, 20.5f, 20.5f, true)), exact),
              box(11, 10, 19, 19));
    // On the grid it agrees with the snapped rule, tie rule included.
    EXPECT_EQ(lit(triangles(square(10.5f, 10.5f, 20.5f, 20.5f, false)), exact),
              box(10, 10, 19, 19));
    auto flipped = exact;
    flipped.gl.tie_rule = refraster::TieRule::RightTop;
    EXPECT_EQ(lit(triangles(square(10.5f, 10.5f, 20.5f, 20.5f, false)), flipped),
              box(11, 11, 20, 20));
}

TEST(CoverageRules, VertexOnCentreLitOnlyWhenLeftmost) {
    // 1.5: a vertex exactly on a pixel centre is lit iff every edge through it owns the tie:
    // as the leftmost point (two left edges) it is; as the rightmost it is not.
    const auto left = lit(triangles({{4.5f, 16.5f}, {20.25f, 8.25f}, {20.25f, 24.75f}}));
    EXPECT_TRUE(left.count({4, 16}));
    const auto right = lit(triangles({{28.5f, 16.5f}, {12.25f, 24.75f}, {12.25f, 8.25f}}));
    EXPECT_FALSE(right.count({28, 16}));
    EXPECT_TRUE(right.count({27, 16}));
}

TEST(CoverageRules, CullingFollowsFrontFace) {
    const auto ccw = square(2.0f, 2.0f, 6.0f, 6.0f, true);
    const auto cw = square(2.0f, 2.0f, 6.0f, 6.0f, false);
    refraster::DrawState s;
    s.cull = refraster::CullMode::Back;
    EXPECT_EQ(lit(triangles(ccw, s)).size(), 16u);
    EXPECT_TRUE(lit(triangles(cw, s)).empty());
    s.front_face = refraster::FrontFace::Cw;
    EXPECT_TRUE(lit(triangles(ccw, s)).empty());
    EXPECT_EQ(lit(triangles(cw, s)).size(), 16u);
    s.cull = refraster::CullMode::FrontAndBack;
    EXPECT_TRUE(lit(triangles(ccw, s)).empty());
    s.front_face = refraster::FrontFace::Ccw;
    s.cull = refraster::CullMode::Front;
    EXPECT_EQ(lit(triangles(cw, s)).size(), 16u);
}

TEST(CoverageRules, ScissorLimitsCoverage) {
    refraster::DrawState s;
    s.scissor = refraster::Rect{3, 4, 2, 1};
    EXPECT_EQ(lit(triangles(square(0, 0, 32, 32, true), s)), box(3, 4, 4, 4));
    s.scissor = refraster::Rect{3, 4, 0, 5};
    EXPECT_TRUE(lit(triangles(square(0, 0, 32, 32, true), s)).empty());
}

TEST(CoverageRules, ClippedTriangleCoversTheVisiblePart) {
    // A triangle crossing the right and top of the viewport: the clipper cuts it at x = 32
    // and y = 32 with new vertices exactly on the hypotenuse x + y = 40, which passes through
    // pixel centres and is a right edge: centres on it stay dark, as without clipping.
    const auto got = lit(triangles({{0, 0}, {40, 0}, {0, 40}}));
    std::set<Pixel> want;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            if (x + y + 1 < 40) want.insert({x, y});
        }
    }
    EXPECT_EQ(got, want);
}

TEST(CoverageRules, GuardBandAppliesTheViewportAsScissor) {
    // A 16x16 viewport at the origin and a triangle reaching 1.5w to its right: within the
    // guard band it is not clipped, and the viewport scissor keeps it inside the viewport.
    refraster::DrawState s;
    DrawList l = triangles({{2, 2}, {28, 2}, {2, 12}}, s);
    l.draws[0].state.viewport = {0, 0, 16, 16};
    for (std::size_t v = 0; v < 3; ++v) {  // re-map the clip coordinates to the 16x16 viewport
        l.draws[0].vertices.data[v * 8] = (l.draws[0].vertices.data[v * 8] + 1.0f) * 2.0f - 1.0f;
        l.draws[0].vertices.data[v * 8 + 1] =
            (l.draws[0].vertices.data[v * 8 + 1] + 1.0f) * 2.0f - 1.0f;
    }
    refraster::Profile gb;
    gb.gl.clipping = refraster::Clipping::GuardBand;
    const auto with_gb = lit(l, gb);
    EXPECT_EQ(with_gb, lit(l));
    for (const auto& [x, y] : with_gb) {
        EXPECT_LT(x, 16);
        EXPECT_LT(y, 16);
    }
    EXPECT_TRUE(with_gb.count({15, 3}));
}

TEST(CoverageRules, BehindTheEyeIsClippedAway) {
    // Vertices with w < 0 fail the x/y planes; only the w > 0 part is drawn. A triangle with
    // all three w < 0 draws nothing, in both coverage models.
    DrawList l = triangles({{4, 4}, {12, 4}, {4, 12}});
    for (std::size_t v = 0; v < 3; ++v) {
        for (std::size_t k = 0; k < 4; ++k) l.draws[0].vertices.data[v * 8 + k] *= -1.0f;
    }
    EXPECT_TRUE(lit(l).empty());
    EXPECT_TRUE(lit(l, refraster::gl_exact_profile()).empty());
}

}  // namespace
