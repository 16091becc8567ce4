// The textbook lines (lines.hpp) against the exact statement of what they draw: one pixel per
// major-axis step, whose minor coordinate is the integer nearest to the exact line through the
// two endpoint pixel centres at that step, computed here by an integer division (no floats),
// with a tie (the exact line exactly halfway) resolved by the named MinorTie. DDA is held to
// the same statement except at ties, where its float accumulation may land on either side;
// off ties it cannot err: the exact value is at least 1/(2a) from a half-integer for the major
// length a <= 23 here, while the accumulated float error after at most a additions of
// values below 2^5 is below a * 2^-48.
#include "refraster/textbook/lines.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdlib>
#include <set>
#include <utility>

namespace {

using refraster::textbook::LineResult;
using refraster::textbook::MinorTie;
using refraster::textbook::PixelIndex;
using refraster::textbook::Point2;

constexpr std::array<MinorTie, 4> kTies = {MinorTie::Keep, MinorTie::Step, MinorTie::TowardNegative,
                                           MinorTie::TowardPositive};

struct Expected {
    PixelIndex pixel;
    bool tie = false;
    PixelIndex other;  // the other candidate at a tie
};

// Floor division by a positive divisor.
long long floor_div(long long a, long long b) {
    long long q = a / b;
    if (a % b != 0 && a < 0) --q;
    return q;
}

// The pixel at major step i of the line from p0 to p1, nearest to the exact line, by direct
// division: the exact minor offset is minor_delta * i / major_length.
Expected nearest_at_step(PixelIndex p0, PixelIndex p1, int i, MinorTie tie) {
    const int dx = p1.x - p0.x;
    const int dy = p1.y - p0.y;
    const bool x_major = std::abs(dx) >= std::abs(dy);
    const int major_delta = x_major ? dx : dy;
    const int minor_delta = x_major ? dy : dx;
    const long long a = std::abs(major_delta);
    const int major_offset = (major_delta < 0 ? -1 : 1) * i;
    long long offset = 0;
    bool is_tie = false;
    long long other = 0;
    if (a != 0) {
        const long long num = static_cast<long long>(minor_delta) * i;
        const long long q = floor_div(num, a);
        const long long r = num - q * a;  // 0 <= r < a: the exact offset is q + r/a
        if (2 * r < a) {
            offset = q;
        } else if (2 * r > a) {
            offset = q + 1;
        } else {
            is_tie = true;
            const long long lower = q;
            const long long upper = q + 1;
            const bool lower_nearer_start = std::llabs(lower) < std::llabs(upper);
            switch (tie) {
                case MinorTie::Keep:
                    offset = lower_nearer_start ? lower : upper;
                    break;
                case MinorTie::Step:
                    offset = lower_nearer_start ? upper : lower;
                    break;
                case MinorTie::TowardNegative:
                    offset = lower;
                    break;
                case MinorTie::TowardPositive:
                    offset = upper;
                    break;
            }
            other = offset == lower ? upper : lower;
        }
    }
    const auto make = [&](long long minor_offset) {
        const int m = static_cast<int>(minor_offset);
        return x_major ? PixelIndex{p0.x + major_offset, p0.y + m}
                       : PixelIndex{p0.x + m, p0.y + major_offset};
    };
    return {make(offset), is_tie, make(other)};
}

int major_length(PixelIndex p0, PixelIndex p1) {
    return std::max(std::abs(p1.x - p0.x), std::abs(p1.y - p0.y));
}

// Checks a path and its raster against the exact statement; returns the number of ties.
int check_exact(const LineResult& r, PixelIndex p0, PixelIndex p1, MinorTie tie, int width,
                int height) {
    const int n = major_length(p0, p1);
    EXPECT_EQ(static_cast<int>(r.path.size()), n + 1);
    if (static_cast<int>(r.path.size()) != n + 1) return 0;
    int ties = 0;
    std::set<std::pair<int, int>> expected_lit;
    for (int i = 0; i <= n; ++i) {
        const Expected e = nearest_at_step(p0, p1, i, tie);
        ties += e.tie ? 1 : 0;
        EXPECT_EQ(r.path[static_cast<std::size_t>(i)], e.pixel)
            << "step " << i << " of (" << p0.x << ", " << p0.y << ") to (" << p1.x << ", " << p1.y
            << ")";
        if (e.pixel.x >= 0 && e.pixel.y >= 0 && e.pixel.x < width && e.pixel.y < height) {
            expected_lit.insert({e.pixel.x, e.pixel.y});
        }
    }
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            EXPECT_EQ(r.raster.at(x, y), expected_lit.count({x, y}) ? 1.0 : 0.0);
        }
    }
    return ties;
}

Point2 centre(int x, int y) {
    return {x + 0.5, y + 0.5};
}

constexpr int kGrid = 16;

TEST(TextbookBresenham, EveryEndpointPairOnAGridIsTheNearestPixelPerStep) {
    int ties = 0;
    for (int a = 0; a < kGrid * kGrid; ++a) {
        for (int b = 0; b < kGrid * kGrid; ++b) {
            const PixelIndex p0{a % kGrid, a / kGrid};
            const PixelIndex p1{b % kGrid, b / kGrid};
            for (const MinorTie tie : kTies) {
                const auto r = refraster::textbook::bresenham_line(
                    centre(p0.x, p0.y), centre(p1.x, p1.y), kGrid, kGrid, tie);
                ties += check_exact(r, p0, p1, tie, kGrid, kGrid);
            }
        }
    }
    EXPECT_GT(ties, 10000);  // the grid exercises the tie rules
}

TEST(TextbookMidpointLine, EveryEndpointPairOnAGridIsTheNearestPixelPerStep) {
    for (int a = 0; a < kGrid * kGrid; ++a) {
        for (int b = 0; b < kGrid * kGrid; ++b) {
            const PixelIndex p0{a % kGrid, a / kGrid};
            const PixelIndex p1{b % kGrid, b / kGrid};
            for (const MinorTie tie : kTies) {
                const auto r = refraster::textbook::midpoint_line(
                    centre(p0.x, p0.y), centre(p1.x, p1.y), kGrid, kGrid, tie);
                check_exact(r, p0, p1, tie, kGrid, kGrid);
            }
        }
    }
}

TEST(TextbookBresenham, DefaultTiesAreThePapersDiagonalMoveAndFoleysEastMove) {
    // (0, 0) to (2, 1): at x = 1 the line is at y = 1/2, a tie.
    const auto bres = refraster::textbook::bresenham_line(centre(0, 0), centre(2, 1), 4, 4);
    const auto mid = refraster::textbook::midpoint_line(centre(0, 0), centre(2, 1), 4, 4);
    EXPECT_EQ(bres.path[1], (PixelIndex{1, 1}));
    EXPECT_EQ(mid.path[1], (PixelIndex{1, 0}));
    // Drawn backwards, Keep and Step swap sides but TowardNegative does not.
    const auto back_keep = refraster::textbook::midpoint_line(centre(2, 1), centre(0, 0), 4, 4);
    EXPECT_EQ(back_keep.path[1], (PixelIndex{1, 1}));
    for (const auto& [from, to] :
         {std::pair{centre(0, 0), centre(2, 1)}, std::pair{centre(2, 1), centre(0, 0)}}) {
        const auto r =
            refraster::textbook::bresenham_line(from, to, 4, 4, MinorTie::TowardNegative);
        EXPECT_EQ(r.path[1], (PixelIndex{1, 0}));
    }
}

TEST(TextbookLines, EndpointsOffCentreGoToThePixelContainingThem) {
    // Every endpoint on a 1/4 grid over a 6 x 6 region: the algorithms draw between the
    // containing pixels' centres, so the result equals the line between those centres.
    constexpr int kQuarters = 24;
    for (int a = 0; a < kQuarters * kQuarters; a += 7) {
        for (int b = 0; b < kQuarters * kQuarters; b += 5) {
            const Point2 pa{(a % kQuarters) / 4.0, (a / kQuarters) / 4.0};
            const Point2 pb{(b % kQuarters) / 4.0, (b / kQuarters) / 4.0};
            const PixelIndex p0{(a % kQuarters) / 4, (a / kQuarters) / 4};
            const PixelIndex p1{(b % kQuarters) / 4, (b / kQuarters) / 4};
            check_exact(refraster::textbook::bresenham_line(pa, pb, 6, 6), p0, p1, MinorTie::Step,
                        6, 6);
            check_exact(refraster::textbook::midpoint_line(pa, pb, 6, 6), p0, p1, MinorTie::Keep, 6,
                        6);
        }
    }
}

TEST(TextbookDda, EqualsRoundingPerStepExceptAtTies) {
    constexpr int kSize = 24;
    int ties = 0;
    int ties_below = 0;
    for (int a = 0; a < kSize * kSize; ++a) {
        for (int b = 0; b < kSize * kSize; ++b) {
            const PixelIndex p0{a % kSize, a / kSize};
            const PixelIndex p1{b % kSize, b / kSize};
            const auto r =
                refraster::textbook::dda_line(centre(p0.x, p0.y), centre(p1.x, p1.y), kSize, kSize);
            const int n = major_length(p0, p1);
            ASSERT_EQ(static_cast<int>(r.path.size()), n + 1);
            for (int i = 0; i <= n; ++i) {
                const Expected e = nearest_at_step(p0, p1, i, MinorTie::TowardPositive);
                const PixelIndex got = r.path[static_cast<std::size_t>(i)];
                if (e.tie) {
                    ++ties;
                    EXPECT_TRUE(got == e.pixel || got == e.other);
                    if (got == e.other) ++ties_below;
                } else {
                    EXPECT_EQ(got, e.pixel);
                }
            }
        }
    }
    EXPECT_GT(ties, 0);
    // The float sum lands below the half-integer at some ties (e.g. 3 * (1/6) in double): the
    // statement's exception is real, not hypothetical.
    EXPECT_GT(ties_below, 0);
    EXPECT_LT(ties_below, ties);
}

TEST(TextbookLines, PixelsOutsideTheRasterAreDroppedFromTheRasterOnly) {
    const auto r = refraster::textbook::bresenham_line({-3.5, 1.5}, {5.5, 1.5}, 4, 4);
    EXPECT_EQ(r.path.size(), 10u);
    EXPECT_EQ(r.raster.count_nonzero(), 4);
}

TEST(TextbookLines, TraceHasOneStepPerPixelAfterTheSetup) {
    refraster::textbook::Trace trace;
    const auto r = refraster::textbook::bresenham_line(centre(0, 0), centre(5, 2), 8, 8,
                                                       MinorTie::Step, &trace);
    ASSERT_EQ(trace.steps.size(), r.path.size() + 1);
    EXPECT_EQ(trace.algorithm, "Bresenham line");
    for (std::size_t i = 0; i < r.path.size(); ++i) {
        ASSERT_EQ(trace.steps[i + 1].pixels.size(), 1u);
        EXPECT_EQ(trace.steps[i + 1].pixels[0].x, r.path[i].x);
        EXPECT_EQ(trace.steps[i + 1].pixels[0].y, r.path[i].y);
    }
}

}  // namespace
