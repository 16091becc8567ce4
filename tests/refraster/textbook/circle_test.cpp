// The midpoint circle (circle.hpp) against the exact statement, for every radius 0..64:
// - the second-octant walk is (x, Y(x)) for every x with Y(x) >= x, where Y(x) is the integer
//   nearest to sqrt(R^2 - x^2), found here by integer comparison
//   (2Y - 1)^2 < 4(R^2 - x^2) < (2Y + 1)^2 (no square roots, no floats); when the octant does
//   not end on the diagonal, the walk's one extra step past it lands on the mirror image of
//   its last octant pixel (so it adds no pixel to the raster);
// - each step's choice is the sign of 4 F(M) = 4(x + 1)^2 + (2y - 1)^2 - 4R^2, which is never 0
//   (it is 1 mod 4), and the integer d the algorithm carries is F(M) - 1/4 exactly;
// - the raster is the union of the eight mirror images of that walk, and is symmetric under
//   all eight maps about the centre.
#include "refraster/textbook/circle.hpp"

#include <gtest/gtest.h>

#include <set>
#include <utility>

namespace {

using refraster::textbook::PixelIndex;

// The integer nearest to sqrt(n), n >= 0: the Y with (2Y - 1)^2 < 4n < (2Y + 1)^2.
long long nearest_sqrt(long long n) {
    long long y = 0;
    while ((2 * y + 1) * (2 * y + 1) < 4 * n) ++y;
    EXPECT_TRUE(y == 0 || (2 * y - 1) * (2 * y - 1) < 4 * n);
    return y;
}

TEST(TextbookMidpointCircle, EveryRadiusWalksTheNearestPixelsOfTheExactCircle) {
    for (int r = 0; r <= 64; ++r) {
        const long long rr = static_cast<long long>(r) * r;
        std::vector<PixelIndex> expected;
        for (long long x = 0;; ++x) {
            const long long y = nearest_sqrt(rr - x * x);
            if (y < x) break;
            expected.push_back({static_cast<int>(x), static_cast<int>(y)});
        }
        const int size = 2 * r + 3;
        const PixelIndex c{r + 1, r + 1};
        const auto result = refraster::textbook::midpoint_circle(c, r, size, size);
        ASSERT_GE(result.octant.size(), expected.size()) << "radius " << r;
        ASSERT_LE(result.octant.size(), expected.size() + 1) << "radius " << r;
        for (std::size_t i = 0; i < expected.size(); ++i) {
            EXPECT_EQ(result.octant[i], expected[i]) << "radius " << r << " step " << i;
        }
        if (result.octant.size() > expected.size()) {
            const PixelIndex last = expected.back();
            EXPECT_NE(last.x, last.y);
            EXPECT_EQ(result.octant.back(), (PixelIndex{last.y, last.x})) << "radius " << r;
        }
        // The decision quantity, exactly.
        ASSERT_EQ(result.decisions.size() + 1, result.octant.size());
        for (std::size_t i = 0; i < result.decisions.size(); ++i) {
            const long long x = result.octant[i].x;
            const long long y = result.octant[i].y;
            const long long four_f = 4 * (x + 1) * (x + 1) + (2 * y - 1) * (2 * y - 1) - 4 * rr;
            EXPECT_EQ(((four_f % 4) + 4) % 4, 1);  // never a tie
            EXPECT_EQ(4 * result.decisions[i], four_f - 1);
            const bool south_east = result.octant[i + 1].y == y - 1;
            EXPECT_EQ(south_east, four_f > 0);
            EXPECT_TRUE(south_east || result.octant[i + 1].y == y);
        }
        // The raster: the eight mirror images of the expected walk, and the 8-way symmetry.
        std::set<std::pair<int, int>> lit;
        for (const PixelIndex& p : expected) {
            for (const auto& [mx, my] : {std::pair{p.x, p.y},
                                         {p.y, p.x},
                                         {p.y, -p.x},
                                         {p.x, -p.y},
                                         {-p.x, -p.y},
                                         {-p.y, -p.x},
                                         {-p.y, p.x},
                                         {-p.x, p.y}}) {
                lit.insert({c.x + mx, c.y + my});
            }
        }
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                ASSERT_EQ(result.raster.at(x, y), lit.count({x, y}) ? 1.0 : 0.0)
                    << "radius " << r << " pixel (" << x << ", " << y << ")";
                const int dx = x - c.x;
                const int dy = y - c.y;
                const double w = result.raster.at(x, y);
                EXPECT_EQ(w, result.raster.at(c.x + dy, c.y + dx));
                EXPECT_EQ(w, result.raster.at(c.x - dx, c.y + dy));
                EXPECT_EQ(w, result.raster.at(c.x + dx, c.y - dy));
            }
        }
    }
}

TEST(TextbookMidpointCircle, PixelsOutsideTheRasterAreDropped) {
    // Radius 5: the octant is (0, 5), (1, 5), (2, 5), (3, 4); at (3, 4) F(M) = 16 + 3.5^2 - 25
    // > 0, so the walk steps SE to (4, 3), the mirror of (3, 4), and (4, 4) stays unlit.
    const auto result = refraster::textbook::midpoint_circle({0, 0}, 5, 8, 8);
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
            const bool on = (x == 0 && y == 5) || (x == 5 && y == 0) || (x == 3 && y == 4) ||
                            (x == 4 && y == 3) || (x == 5 && y == 1) || (x == 5 && y == 2) ||
                            (x == 1 && y == 5) || (x == 2 && y == 5);
            EXPECT_EQ(result.raster.at(x, y), on ? 1.0 : 0.0) << x << ", " << y;
        }
    }
}

TEST(TextbookMidpointCircle, TraceHasOneStepPerOctantPixelWithItsEightMirrors) {
    refraster::textbook::Trace trace;
    const auto result = refraster::textbook::midpoint_circle({10, 10}, 7, 21, 21, &trace);
    ASSERT_EQ(trace.steps.size(), result.octant.size());
    for (const auto& step : trace.steps) EXPECT_EQ(step.pixels.size(), 8u);
}

}  // namespace
