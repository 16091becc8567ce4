// The scanline fill (scanline_fill.hpp) against the exact point-in-polygon test at every pixel
// centre, computed per pixel by a different method: for each edge active at the centre's
// height (ymin <= y_c < ymax), an integer orientation test says whether its crossing is at or
// left of x_c, and the winding number is the sum of those edges' directions. That is the
// polygon's winding number at the nudged point (x_c + e, y_c + e^2): the nudged horizontal
// line meets exactly the edges with ymin <= y_c < ymax, and a crossing exactly at x_c lies
// left of x_c + e. Vertices are multiples of 1/2 or 1/4 pixel (exact in the 1/256 snap), so
// centres on edges and vertices at centre heights are frequent, or of 1/256 pixel, so that
// crossings fall within 1/256 pixel of centres on either side.
#include "refraster/textbook/scanline_fill.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace {

using refraster::textbook::Contour;
using refraster::textbook::FillRule;
using refraster::textbook::Point2;

// The winding number at pixel (i, j)'s centre nudged by (+e, +e^2), in 1/256 pixel: the
// centre is (256i + 128, 256j + 128) and the vertices are integers in those units.
int winding_at_centre(const std::vector<Contour>& contours, int i, int j) {
    const long long px = 256LL * i + 128;
    const long long py = 256LL * j + 128;
    int winding = 0;
    for (const Contour& c : contours) {
        for (std::size_t k = 0; k < c.size(); ++k) {
            const Point2 a = c[k];
            const Point2 b = c[(k + 1) % c.size()];
            const auto ax = static_cast<long long>(a.x * 256);
            const auto ay = static_cast<long long>(a.y * 256);
            const auto bx = static_cast<long long>(b.x * 256);
            const auto by = static_cast<long long>(b.y * 256);
            if (ay == by) continue;
            const bool up = by > ay;
            const long long lx = up ? ax : bx;
            const long long ly = up ? ay : by;
            const long long hx = up ? bx : ax;
            const long long hy = up ? by : ay;
            if (!(ly <= py && py < hy)) continue;
            // orient(low, high, p) <= 0 exactly when the crossing is at or left of p.
            const long long o = (hx - lx) * (py - ly) - (hy - ly) * (px - lx);
            if (o <= 0) winding += up ? 1 : -1;
        }
    }
    return winding;
}

void expect_exact(const std::vector<Contour>& contours, FillRule rule, int width, int height) {
    const auto result = refraster::textbook::scanline_fill(contours, rule, width, height);
    for (int j = 0; j < height; ++j) {
        for (int i = 0; i < width; ++i) {
            const int w = winding_at_centre(contours, i, j);
            const bool inside = rule == FillRule::EvenOdd ? (w % 2) != 0 : w != 0;
            ASSERT_EQ(result.raster.at(i, j), inside ? 1.0 : 0.0)
                << "pixel (" << i << ", " << j << "), winding " << w;
        }
    }
    int from_spans = 0;
    for (const auto& s : result.spans) from_spans += s.x_end - s.x_begin;
    EXPECT_EQ(from_spans, result.raster.count_nonzero());
}

std::vector<Contour> random_contours(std::mt19937& rng, int denominator) {
    std::uniform_int_distribution<int> contour_count(1, 3);
    std::uniform_int_distribution<int> vertex_count(3, 9);
    std::uniform_int_distribution<int> coord(-denominator, 9 * denominator);
    std::vector<Contour> out(static_cast<std::size_t>(contour_count(rng)));
    for (Contour& c : out) {
        const int n = vertex_count(rng);
        for (int k = 0; k < n; ++k) {
            c.push_back({static_cast<double>(coord(rng)) / denominator,
                         static_cast<double>(coord(rng)) / denominator});
        }
    }
    return out;
}

TEST(TextbookScanlineFill, RandomSelfIntersectingPolygonsEqualTheExactTestAtEveryCentre) {
    std::mt19937 rng(20240601);
    for (int n = 0; n < 6000; ++n) {
        const int denominators[] = {2, 4, 256};
        const auto contours = random_contours(rng, denominators[n % 3]);
        expect_exact(contours, FillRule::EvenOdd, 8, 8);
        expect_exact(contours, FillRule::NonZero, 8, 8);
        if (HasFatalFailure()) return;
    }
}

TEST(TextbookScanlineFill, EdgesThroughCentresFollowTheHalfOpenRules) {
    // A square with its edges on centre lines: the left and bottom centres are in, the right
    // and top ones out, so the 2 x 2 block of pixels (0..1, 0..1) is filled.
    const std::vector<Contour> square = {{{0.5, 0.5}, {2.5, 0.5}, {2.5, 2.5}, {0.5, 2.5}}};
    const auto r = refraster::textbook::scanline_fill(square, FillRule::EvenOdd, 4, 4);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) EXPECT_EQ(r.raster.at(x, y), (x < 2 && y < 2) ? 1.0 : 0.0);
    }
    expect_exact(square, FillRule::EvenOdd, 4, 4);
}

TEST(TextbookScanlineFill, TrianglesTilingThePlaneFillEveryPixelExactlyOnce) {
    // A jittered lattice over [-2, 10]^2, every cell split along a diagonal: each pixel of the
    // 8 x 8 raster is filled by exactly one triangle, whichever way the shared edges run.
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> jitter(-1, 1);  // quarter pixels
    for (int round = 0; round < 50; ++round) {
        constexpr int kCells = 6;
        std::vector<std::vector<Point2>> lattice(kCells + 1, std::vector<Point2>(kCells + 1));
        for (int i = 0; i <= kCells; ++i) {
            for (int j = 0; j <= kCells; ++j) {
                lattice[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = {
                    -2.0 + 2.0 * i + jitter(rng) / 4.0, -2.0 + 2.0 * j + jitter(rng) / 4.0};
            }
        }
        refraster::textbook::Raster sum(8, 8);
        for (std::size_t i = 0; i < kCells; ++i) {
            for (std::size_t j = 0; j < kCells; ++j) {
                const Point2 a = lattice[i][j];
                const Point2 b = lattice[i + 1][j];
                const Point2 c = lattice[i + 1][j + 1];
                const Point2 d = lattice[i][j + 1];
                const bool other_diagonal = (i + j + static_cast<std::size_t>(round)) % 2 == 0;
                const std::vector<Contour> t1 = {other_diagonal ? Contour{a, b, d}
                                                                : Contour{a, b, c}};
                // The second triangle runs clockwise: orientation must not matter.
                const std::vector<Contour> t2 = {other_diagonal ? Contour{b, d, c}
                                                                : Contour{a, d, c}};
                for (const auto& t : {t1, t2}) {
                    const auto r = refraster::textbook::scanline_fill(t, FillRule::NonZero, 8, 8);
                    for (int y = 0; y < 8; ++y) {
                        for (int x = 0; x < 8; ++x) sum.add(x, y, r.raster.at(x, y));
                    }
                }
            }
        }
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 8; ++x) ASSERT_EQ(sum.at(x, y), 1.0) << x << ", " << y;
        }
    }
}

TEST(TextbookScanlineFill, APentagramsCentreIsOutsideByEvenOddAndInsideByNonZero) {
    const std::vector<Contour> star = {{{4, 0}, {6.5, 8}, {0, 3}, {8, 3}, {1.5, 8}}};
    const auto even_odd = refraster::textbook::scanline_fill(star, FillRule::EvenOdd, 8, 8);
    const auto non_zero = refraster::textbook::scanline_fill(star, FillRule::NonZero, 8, 8);
    EXPECT_EQ(even_odd.raster.at(4, 4), 0.0);
    EXPECT_EQ(non_zero.raster.at(4, 4), 1.0);
    expect_exact(star, FillRule::EvenOdd, 8, 8);
    expect_exact(star, FillRule::NonZero, 8, 8);
}

TEST(TextbookScanlineFill, TraceHasTheEdgeTableAndOneStepPerScanline) {
    refraster::textbook::Trace trace;
    const std::vector<Contour> tri = {{{0.5, 0.25}, {7.5, 2.5}, {3, 6.75}}};
    const auto r = refraster::textbook::scanline_fill(tri, FillRule::EvenOdd, 8, 8, &trace);
    ASSERT_EQ(trace.steps.size(), 1u + 7u);  // rows 0..6 have centres in [0.25, 6.75)
    int pixels = 0;
    for (const auto& s : trace.steps) pixels += static_cast<int>(s.pixels.size());
    EXPECT_EQ(pixels, r.raster.count_nonzero());
    EXPECT_EQ(trace.steps[1].state[0].first, "AEL");
    // Crossings print as the exact fractions they are: row 0's centre (y 0.5) meets the edge
    // from (0.5, 0.25) to (7.5, 2.5) at x = 0.5 + 0.25 * 7 / 2.25 = 23/18 (not 1.2777...).
    const std::string& ael = trace.steps[1].state[0].second;
    EXPECT_NE(ael.find("x=23/18"), std::string::npos) << ael;
    EXPECT_EQ(ael.find('.'), std::string::npos) << ael;
}

}  // namespace
