// The edge functions of line and point setup (line_point.cpp): each of the four edges of
// setup_line and setup_point must be exactly make_edge (edge_rules.hpp) of its
// parallelogram's or square's snapped corners, tie bias included, under every tie rule. The
// sameness test cannot tell: every path it compares shares this setup.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <random>

#include "models/llvmpipe/line_point.hpp"
#include "stages/edge_rules.hpp"

namespace {

using refraster::TieRule;
using refraster::detail::EdgeFunction;
using refraster::detail::make_edge;
using refraster::detail::SetupParams;
using refraster::detail::StageVertex;

constexpr std::array<TieRule, 6> kRules{TieRule::LeftBottom, TieRule::LeftTop, TieRule::RightBottom,
                                        TieRule::RightTop,   TieRule::None,    TieRule::All};

SetupParams params(TieRule rule) {
    SetupParams p;
    p.tie_rule = rule;
    p.draw_region = {0, 0, 255, 255};
    p.framebuffer = p.draw_region;
    return p;
}

StageVertex at(float x, float y) {
    StageVertex v;
    v.window = {x, y, 0.5f, 1.0f};
    return v;
}

void expect_same(const EdgeFunction& got, const EdgeFunction& want) {
    EXPECT_EQ(got.a, want.a);
    EXPECT_EQ(got.b, want.b);
    EXPECT_EQ(got.c, want.c);
    EXPECT_EQ(got.owns_ties, want.owns_ties);
}

TEST(LinePointEdges, LineEdgesAreMakeEdgeOfTheCorners) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-8.0f, 264.0f);
    // Half the ends on the pixel grid's centres and borders, where the tie rule decides.
    std::uniform_int_distribution<int> grid(0, 2 * 256);
    std::uniform_int_distribution<int> width(1, 6);
    int checked = 0;
    for (int i = 0; i < 4000; ++i) {
        const bool on_grid = i % 2 == 0;
        const auto coord = [&] {
            return on_grid ? static_cast<float>(grid(rng)) * 0.5f : pos(rng);
        };
        const StageVertex a = at(coord(), coord());
        const StageVertex b = at(coord(), coord());
        const auto w = static_cast<float>(width(rng));
        for (const TieRule rule : kRules) {
            const auto l = refraster::detail::setup_line(a, b, w, params(rule));
            if (!l) continue;
            ++checked;
            for (std::size_t k = 0; k < 4; ++k) {
                const std::size_t j = (k + 1) % 4;
                expect_same(l->edges[k], make_edge(l->x[k], l->y[k], l->x[j], l->y[j], rule));
            }
            if (HasFailure()) return;
        }
    }
    EXPECT_GT(checked, 20000);
}

TEST(LinePointEdges, PointEdgesAreMakeEdgeOfTheSquare) {
    std::mt19937 rng(11);
    // Positions and sizes on the 1/256 grid, so that the snap is exact and the square's
    // corners are known here: centre (x - 0.5) * 256, side max(256, size * 256).
    std::uniform_int_distribution<int> pos(0, 256 * 256 - 1);
    std::uniform_int_distribution<int> size(1, 10 * 256);
    int checked = 0;
    for (int i = 0; i < 4000; ++i) {
        const int px = pos(rng);
        const int py = pos(rng);
        const int s = i % 3 == 0 ? 256 * (1 + i % 8) : size(rng);
        const StageVertex v = at(static_cast<float>(px) / 256.0f, static_cast<float>(py) / 256.0f);
        const std::int32_t fw = std::max(256, s);
        const std::int32_t x0 = (px - 128) - fw / 2;
        const std::int32_t y0 = (py - 128) - fw / 2;
        const std::int32_t x1 = x0 + fw;
        const std::int32_t y1 = y0 + fw;
        for (const TieRule rule : kRules) {
            const auto p =
                refraster::detail::setup_point(v, static_cast<float>(s) / 256.0f, params(rule));
            if (!p) continue;
            ++checked;
            EXPECT_EQ(p->fixed_width, fw);
            expect_same(p->edges[0], make_edge(x0, y0, x0, y1, rule));
            expect_same(p->edges[1], make_edge(x1, y1, x1, y0, rule));
            expect_same(p->edges[2], make_edge(x1, y0, x0, y0, rule));
            expect_same(p->edges[3], make_edge(x0, y1, x1, y1, rule));
            if (HasFailure()) return;
        }
    }
    EXPECT_GT(checked, 20000);
}

}  // namespace
