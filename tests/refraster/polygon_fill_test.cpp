// The polygon filler (polygon_fill.hpp) against hand-derived pixels, against direct summation of
// the winding number at every nudged centre, and against llvmpipe's own triangle coverage of
// the polygon's fan (the stencil method's count), for every tie rule that is a nudge.
#include "stages/polygon_fill.hpp"

#include <gtest/gtest.h>

#include <random>

#include "models/llvmpipe/setup.hpp"

namespace {

using refraster::FillRule;
using refraster::TieRule;
using refraster::detail::Contour;
using refraster::detail::FillMask;
using refraster::detail::PixelRect;
using refraster::detail::scanline_fill;
using refraster::detail::SnappedPoint;
using refraster::detail::winding_at;

constexpr int kBits = 8;
constexpr TieRule kNudgeRules[] = {TieRule::LeftBottom, TieRule::LeftTop, TieRule::RightBottom,
                                   TieRule::RightTop};

// The pixel centre of (px, py) in snapped units, plus an offset in 1/256 pixel.
SnappedPoint centre(int px, int py, int dx = 0, int dy = 0) {
    return {px * 256 + dx, py * 256 + dy};
}

bool lit(FillRule rule, std::int64_t winding) {
    return rule == FillRule::EvenOdd ? (winding & 1) != 0 : (winding & 0xff) != 0;
}

// A square through the centres of pixels (2, 2) and (5, 5): under the left-bottom rule the
// left and bottom edges' centres are in, the right and top edges' out: 3 x 3 pixels.
TEST(PolygonFill, SquareThroughCentresOwnsLeftAndBottomEdges) {
    const std::vector<Contour> square{{centre(2, 2), centre(5, 2), centre(5, 5), centre(2, 5)}};
    const PixelRect region{0, 0, 7, 7};
    for (const TieRule rule : kNudgeRules) {
        const FillMask m = scanline_fill(square, FillRule::EvenOdd, rule, kBits, region);
        const auto [sx, sy] = refraster::detail::nudge_of(rule);
        const int x0 = sx > 0 ? 2 : 3;
        const int y0 = sy > 0 ? 2 : 3;
        for (int y = 0; y <= 7; ++y) {
            for (int x = 0; x <= 7; ++x) {
                const bool in = x >= x0 && x < x0 + 3 && y >= y0 && y < y0 + 3;
                EXPECT_EQ(m.test(x, y), in) << to_string(rule) << " pixel " << x << "," << y;
            }
        }
        EXPECT_EQ(m.count(), 9u);
    }
}

// Both orientations, and a vertex exactly on a centre, give the same pixels.
TEST(PolygonFill, OrientationDoesNotMatter) {
    const Contour ccw{centre(1, 1), centre(9, 3), centre(4, 9)};
    const Contour cw{ccw[2], ccw[1], ccw[0]};
    const PixelRect region{0, 0, 11, 11};
    for (const FillRule rule : {FillRule::EvenOdd, FillRule::NonZero}) {
        const FillMask a =
            scanline_fill(std::vector<Contour>{ccw}, rule, TieRule::LeftBottom, kBits, region);
        const FillMask b =
            scanline_fill(std::vector<Contour>{cw}, rule, TieRule::LeftBottom, kBits, region);
        for (int y = 0; y <= 11; ++y)
            for (int x = 0; x <= 11; ++x) EXPECT_EQ(a.test(x, y), b.test(x, y)) << x << "," << y;
        EXPECT_GT(a.count(), 20u);
    }
}

// A contour wound 256 times wraps the stencil's 8 bits: the non-zero rule lights nothing;
// 257 times lights the triangle; the even-odd rule follows the parity.
TEST(PolygonFill, WindingWrapsAtTwoHundredFiftySix) {
    const Contour once{centre(1, 1, 17), centre(14, 2, 0, 33), centre(6, 13, -5)};
    const PixelRect region{0, 0, 15, 15};
    const auto wound = [&](int times) {
        Contour c;
        for (int k = 0; k < times; ++k) c.insert(c.end(), once.begin(), once.end());
        return std::vector<Contour>{c};
    };
    const auto single = scanline_fill(std::vector<Contour>{once}, FillRule::NonZero,
                                      TieRule::LeftBottom, kBits, region)
                            .count();
    EXPECT_GT(single, 30u);
    EXPECT_EQ(
        scanline_fill(wound(256), FillRule::NonZero, TieRule::LeftBottom, kBits, region).count(),
        0u);
    EXPECT_EQ(
        scanline_fill(wound(257), FillRule::NonZero, TieRule::LeftBottom, kBits, region).count(),
        single);
    EXPECT_EQ(
        scanline_fill(wound(2), FillRule::EvenOdd, TieRule::LeftBottom, kBits, region).count(), 0u);
}

// Random contours in three vertex regimes: the filler's pixels equal the rule applied to the
// winding number summed edge by edge at each nudged centre.
TEST(PolygonFill, EqualsDirectSummationAtEveryCentre) {
    std::mt19937_64 rng(99);
    const PixelRect region{0, 0, 23, 23};
    int lit_total = 0;
    for (int trial = 0; trial < 300; ++trial) {
        std::vector<Contour> contours(1 + static_cast<std::size_t>(trial % 3));
        for (auto& c : contours) {
            const int n = std::uniform_int_distribution<int>(3, 12)(rng);
            for (int k = 0; k < n; ++k) {
                const int regime = trial % 3;
                const auto coord = [&] {
                    if (regime == 0) return std::uniform_int_distribution<int>(-2, 26)(rng) * 256;
                    if (regime == 1) return std::uniform_int_distribution<int>(-4, 52)(rng) * 128;
                    return std::uniform_int_distribution<int>(-600, 6700)(rng);
                };
                c.push_back({coord(), coord()});
            }
        }
        for (const TieRule tie : kNudgeRules) {
            for (const FillRule rule : {FillRule::EvenOdd, FillRule::NonZero}) {
                const FillMask m = scanline_fill(contours, rule, tie, kBits, region);
                for (int y = region.y0; y <= region.y1; ++y) {
                    for (int x = region.x0; x <= region.x1; ++x) {
                        const bool want = lit(rule, winding_at(contours, tie, kBits, x, y));
                        ASSERT_EQ(m.test(x, y), want) << "trial " << trial << " " << to_string(tie)
                                                      << " pixel " << x << "," << y;
                        lit_total += want;
                    }
                }
            }
        }
    }
    EXPECT_GT(lit_total, 10000);
}

// The stencil method's count: llvmpipe's coverage (setup.hpp's edge functions and tie rule) of
// each triangle (v0, v[i-1], v[i]) of the polygon, added up with the triangle's orientation.
// The filler over the polygon's own edges must light exactly the pixels whose count passes the
// rule (docs/precision.md, "Polygons and fill rules"), centres on edges and diagonals included.
TEST(PolygonFill, EqualsTheFanTrianglesCoverageCount) {
    std::mt19937_64 rng(2024);
    const PixelRect region{0, 0, 19, 19};
    int on_edges = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const int n = std::uniform_int_distribution<int>(4, 12)(rng);
        Contour c;
        for (int k = 0; k < n; ++k) {
            // Pixel centres and the half-pixel grid put many centres on edges and diagonals.
            const bool grid = trial % 2 == 0;
            const auto coord = [&] {
                return grid ? std::uniform_int_distribution<int>(0, 19)(rng) * 256
                            : std::uniform_int_distribution<int>(0, 39)(rng) * 128;
            };
            c.push_back({coord(), coord()});
        }
        for (const TieRule tie : kNudgeRules) {
            refraster::detail::SetupParams p;
            p.tie_rule = tie;
            p.draw_region = region;
            p.framebuffer = region;
            std::vector<std::int64_t> count(400, 0);
            for (int i = 2; i < n; ++i) {
                const SnappedPoint v[3] = {c[0], c[static_cast<std::size_t>(i - 1)],
                                           c[static_cast<std::size_t>(i)]};
                const std::int64_t area =
                    (std::int64_t{v[0].x} - v[1].x) * (std::int64_t{v[2].y} - v[0].y) -
                    (std::int64_t{v[2].x} - v[0].x) * (std::int64_t{v[0].y} - v[1].y);
                if (area == 0) continue;  // llvmpipe drops it
                // Setup's orientation: a negative area swaps two vertices.
                const SnappedPoint o[3] = {area < 0 ? v[1] : v[0], area < 0 ? v[0] : v[1], v[2]};
                const auto e0 = refraster::detail::make_edge(o[0].x, o[0].y, o[1].x, o[1].y, tie);
                const auto e1 = refraster::detail::make_edge(o[1].x, o[1].y, o[2].x, o[2].y, tie);
                const auto e2 = refraster::detail::make_edge(o[2].x, o[2].y, o[0].x, o[0].y, tie);
                for (int y = 0; y < 20; ++y) {
                    for (int x = 0; x < 20; ++x) {
                        if (e0.at(x, y, kBits) > 0 && e1.at(x, y, kBits) > 0 &&
                            e2.at(x, y, kBits) > 0) {
                            count[static_cast<std::size_t>(20 * y + x)] += area < 0 ? -1 : 1;
                        }
                    }
                }
            }
            for (const FillRule rule : {FillRule::EvenOdd, FillRule::NonZero}) {
                const FillMask m = scanline_fill(std::vector<Contour>{c}, rule, tie, kBits, region);
                for (int y = 0; y < 20; ++y) {
                    for (int x = 0; x < 20; ++x) {
                        ASSERT_EQ(m.test(x, y),
                                  lit(rule, count[static_cast<std::size_t>(20 * y + x)]))
                            << "trial " << trial << " " << to_string(tie) << " "
                            << (rule == FillRule::EvenOdd ? "evenodd" : "nonzero") << " pixel " << x
                            << "," << y;
                    }
                }
            }
        }
        // How many centres lie exactly on a polygon edge (the regime that needs the rule).
        for (int y = 0; y < 20; ++y) {
            for (int x = 0; x < 20; ++x) {
                for (int k = 0; k < n; ++k) {
                    const SnappedPoint a = c[static_cast<std::size_t>(k)];
                    const SnappedPoint b = c[static_cast<std::size_t>((k + 1) % n)];
                    const std::int64_t cross =
                        (std::int64_t{b.x} - a.x) * (std::int64_t{y} * 256 - a.y) -
                        (std::int64_t{b.y} - a.y) * (std::int64_t{x} * 256 - a.x);
                    const bool within =
                        std::min(a.x, b.x) <= x * 256 && x * 256 <= std::max(a.x, b.x) &&
                        std::min(a.y, b.y) <= y * 256 && y * 256 <= std::max(a.y, b.y);
                    if (cross == 0 && within && !(a == b)) {
                        ++on_edges;
                        break;
                    }
                }
            }
        }
    }
    EXPECT_GT(on_edges, 2000);
}

// The trace names every scanline an edge crosses and the runs it lit, and they are the mask's.
TEST(PolygonFill, TraceRecordsTheActiveEdgesAndSpans) {
    const std::vector<Contour> tri{{centre(1, 1, 40), centre(9, 2, 0, 100), centre(3, 8, 10, 7)}};
    std::vector<refraster::detail::FillScanline> trace;
    const FillMask m =
        scanline_fill(tri, FillRule::EvenOdd, TieRule::LeftBottom, kBits, {0, 0, 11, 11}, &trace);
    std::uint64_t from_spans = 0;
    std::size_t added = 0;
    for (const auto& line : trace) {
        EXPECT_EQ(line.crossings.size() % 2, 0u) << "row " << line.y;
        for (const auto& s : line.lit_spans) {
            for (int x = s[0]; x <= s[1]; ++x) EXPECT_TRUE(m.test(x, line.y));
            from_spans += static_cast<std::uint64_t>(s[1] - s[0] + 1);
        }
        added += line.edges_added.size();
    }
    EXPECT_EQ(from_spans, m.count());
    EXPECT_EQ(added, 3u);  // every edge of the triangle enters the list once
    EXPECT_GT(m.count(), 15u);
}

}  // namespace
