// The trace hook records, for one pixel, the decisions that covered it or not.
#include <gtest/gtest.h>

#include "refraster/renderer.hpp"

namespace {

// Two triangles forming [10.5, 20.5]^2 on a 32x32 target (window = clip * 16 + 16).
refraster::DrawList square() {
    refraster::DrawList l;
    l.target = {32, 32, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    l.clear.color = {0, 0, 0, 1};
    refraster::Draw d;
    d.primitive = refraster::PrimitiveType::Triangles;
    d.state.viewport = {0, 0, 32, 32};
    d.state.shade = refraster::ShadeModel::Flat;
    d.vertices.attributes = {{"color", 4}};
    const float lo = 10.5f / 16 - 1, hi = 20.5f / 16 - 1;
    for (auto [x, y] : {std::pair{lo, lo}, {hi, lo}, {hi, hi}, {lo, lo}, {hi, hi}, {lo, hi}}) {
        d.vertices.data.insert(d.vertices.data.end(), {x, y, 0, 1, 1, 1, 1, 1});
    }
    l.draws.push_back(d);
    return l;
}

refraster::PixelTrace trace_at(int x, int y, const refraster::Profile& p = {}) {
    refraster::PixelTrace t;
    t.x = x;
    t.y = y;
    refraster::RenderOptions o;
    o.profile = p;
    o.trace = &t;
    refraster::Framebuffer fb;
    EXPECT_EQ(refraster::render(square(), o, fb).status, refraster::RenderStatus::Ok);
    return t;
}

TEST(Trace, LeftEdgeTieIsRecordedAndOwned) {
    // Pixel (10, 15): its centre (10.5, 15.5) lies on the square's left edge.
    const auto t = trace_at(10, 15);
    EXPECT_EQ(t.profile, "llvmpipe-22.3");
    int ties = 0;
    bool covered = false;
    for (const auto& p : t.primitives) {
        for (const auto& s : p.setups) {
            for (const auto& e : s.edges) {
                if (e.tie) {
                    ++ties;
                    EXPECT_TRUE(e.owns_ties);
                    EXPECT_EQ(e.value, 1);  // E = 0 plus the bias
                }
            }
            EXPECT_EQ(s.x[0] % 256, 0);  // snapped onto the pixel-centre grid
        }
        covered = covered || p.covered;
    }
    EXPECT_GE(ties, 1);
    EXPECT_TRUE(covered);
    EXPECT_EQ(t.final_color[0], 255.0f);
}

TEST(Trace, RightEdgeTieIsRecordedAndNotOwned) {
    // Pixel (20, 15): on the right edge, which the left-bottom rule does not own.
    const auto t = trace_at(20, 15);
    bool saw_unowned_tie = false;
    for (const auto& p : t.primitives) {
        EXPECT_FALSE(p.covered);
        for (const auto& s : p.setups) {
            for (const auto& e : s.edges)
                saw_unowned_tie = saw_unowned_tie || (e.tie && !e.owns_ties && e.value == 0);
        }
    }
    EXPECT_TRUE(saw_unowned_tie);
    EXPECT_EQ(t.final_color[0], 0.0f);
    // With the rule flipped the same tie is owned and the pixel lit.
    refraster::Profile flipped;
    flipped.gl.tie_rule = refraster::TieRule::RightTop;
    EXPECT_EQ(trace_at(20, 15, flipped).final_color[0], 255.0f);
}

TEST(Trace, FarPixelRecordsNothing) {
    EXPECT_TRUE(trace_at(2, 2).primitives.empty());
}

}  // namespace

namespace {

refraster::DrawList one_primitive(refraster::PrimitiveType p, std::vector<std::array<float, 2>> win,
                                  float size) {
    refraster::DrawList l;
    l.target = {32, 32, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    l.clear.color = {0, 0, 0, 1};
    refraster::Draw d;
    d.primitive = p;
    d.state.viewport = {0, 0, 32, 32};
    d.state.line_width = size;
    d.state.point_size = size;
    d.vertices.attributes = {{"color", 4}};
    for (const auto& [x, y] : win)
        d.vertices.data.insert(d.vertices.data.end(), {x / 16 - 1, y / 16 - 1, 0, 1, 1, 1, 1, 1});
    l.draws.push_back(d);
    return l;
}

refraster::PixelTrace trace_of(const refraster::DrawList& l, int x, int y) {
    refraster::PixelTrace t;
    t.x = x;
    t.y = y;
    refraster::RenderOptions o;
    o.trace = &t;
    refraster::Framebuffer fb;
    EXPECT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
    return t;
}

TEST(Trace, LinesRecordFourEdgesAndTheFragment) {
    const auto t = trace_of(
        one_primitive(refraster::PrimitiveType::Lines, {{2.25f, 8.5f}, {20.75f, 8.5f}}, 1.0f), 10,
        8);
    ASSERT_EQ(t.primitives.size(), 1u);
    const auto& p = t.primitives[0];
    EXPECT_EQ(p.kind, "line");
    EXPECT_TRUE(p.covered);
    ASSERT_EQ(p.setups.size(), 1u);
    EXPECT_EQ(p.setups[0].edges.size(), 4u);
    EXPECT_TRUE(p.setups[0].has_fragment);
    EXPECT_EQ(p.setups[0].fragment.written[0], 255.0f);
    // A pixel a row away is not reported as covered.
    for (const auto& q : trace_of(one_primitive(refraster::PrimitiveType::Lines,
                                                {{2.25f, 8.5f}, {20.75f, 8.5f}}, 1.0f),
                                  10, 10)
                             .primitives) {
        EXPECT_FALSE(q.covered);
    }
}

TEST(Trace, PointsRecordTheirSquare) {
    const auto t =
        trace_of(one_primitive(refraster::PrimitiveType::Points, {{10.0f, 10.0f}}, 1.0f), 9, 9);
    ASSERT_EQ(t.primitives.size(), 1u);
    EXPECT_EQ(t.primitives[0].kind, "point");
    EXPECT_TRUE(t.primitives[0].covered);  // a size-1 point at (10, 10) lights pixel (9, 9)
    EXPECT_TRUE(
        trace_of(one_primitive(refraster::PrimitiveType::Points, {{10.0f, 10.0f}}, 1.0f), 10, 10)
            .primitives.empty());
}

}  // namespace
