// Wu's line (wu_line.hpp) against two exact statements, for every pair of endpoints on a grid
// of pixel centres and on a 1/4-pixel grid:
// 1. The weights are the usual formulation's, computed here in rational arithmetic: for each
//    column c (pixel centres at the integers after u = x - 1/2), its length L inside [u0, u1]
//    and the exact minor coordinate v_c = v0 + g (c - u0) at its centre give
//    (1 - frac(v_c)) L to row floor(v_c) and frac(v_c) L to the row above. Wu accumulates v_c
//    in double; the stated bound on the difference per pixel is 1e-12 (at most 30 additions
//    of values below 2^4, each off by at most 2^-49).
// 2. Against the exact area A of the 1-pixel-thick band {|v - v(u)| <= 1/2, u0 <= u <= u1}
//    inside each pixel (the integral of the piecewise-linear vertical overlap, exact), every
//    pixel's weight differs by at most |g| / 4 (plus the 1e-12 above), the bound is reached,
//    and each column's weights sum to its length, as the band's areas do.
#include "refraster/textbook/wu_line.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "exact_support.hpp"

namespace {

using textbook_test::Rational;

constexpr double kFloatBound = 1e-12;

// A line with endpoints on the 1/4 grid, in the exact centre-lattice frame.
struct ExactLine {
    bool steep = false;
    Rational u0, v0, u1, v1;
    Rational gradient;  // 0 when u0 == u1
};

ExactLine exact_line(long long ax4, long long ay4, long long bx4, long long by4) {
    // u = x - 1/2, in quarters: U = X - 2.
    Rational u0(ax4 - 2, 4), v0(ay4 - 2, 4), u1(bx4 - 2, 4), v1(by4 - 2, 4);
    ExactLine l;
    l.steep = abs(v1 - v0) > abs(u1 - u0);
    if (l.steep) {
        std::swap(u0, v0);
        std::swap(u1, v1);
    }
    if (u0 > u1) {
        std::swap(u0, u1);
        std::swap(v0, v1);
    }
    l.u0 = u0;
    l.v0 = v0;
    l.u1 = u1;
    l.v1 = v1;
    l.gradient = u1 == u0 ? Rational(0) : (v1 - v0) / (u1 - u0);
    return l;
}

Rational column_length(const ExactLine& l, long long c, long long first, long long last) {
    if (first == last) return l.u1 - l.u0;
    if (c == first) return Rational(c) + Rational(1, 2) - l.u0;
    if (c == last) return l.u1 - (Rational(c) - Rational(1, 2));
    return Rational(1);
}

long long round_half_up(const Rational& t) {
    return static_cast<long long>((t + Rational(1, 2)).floor());
}

// The raster the usual formulation gives, in exact arithmetic, keyed by (x, y).
std::map<std::pair<long long, long long>, Rational> exact_weights(const ExactLine& l) {
    std::map<std::pair<long long, long long>, Rational> out;
    const long long first = round_half_up(l.u0);
    const long long last = round_half_up(l.u1);
    for (long long c = first; c <= last; ++c) {
        const Rational len = column_length(l, c, first, last);
        const Rational vc = l.v0 + l.gradient * (Rational(c) - l.u0);
        const long long row = static_cast<long long>(vc.floor());
        const Rational frac = vc - Rational(row);
        const auto key = [&](long long r) { return l.steep ? std::pair{r, c} : std::pair{c, r}; };
        out[key(row)] = out[key(row)] + (Rational(1) - frac) * len;
        out[key(row + 1)] = out[key(row + 1)] + frac * len;
    }
    return out;
}

// The exact area of the band inside pixel (column c, row r) of the u-v frame: the integral
// over u in the column and in [u0, u1] of max(0, 1 - |v(u) - r|), piecewise linear with
// breakpoints where v(u) - r is -1, 0 or 1.
Rational band_area(const ExactLine& l, long long c, long long r) {
    const Rational lo = max(Rational(c) - Rational(1, 2), l.u0);
    const Rational hi = min(Rational(c) + Rational(1, 2), l.u1);
    if (!(lo < hi)) return Rational(0);
    std::vector<Rational> points{lo, hi};
    if (l.gradient.sign() != 0) {
        for (long long k = -1; k <= 1; ++k) {
            const Rational u = l.u0 + (Rational(r + k) - l.v0) / l.gradient;
            if (lo < u && u < hi) points.push_back(u);
        }
    }
    std::sort(points.begin(), points.end());
    const auto overlap = [&](const Rational& u) {
        const Rational d = abs(l.v0 + l.gradient * (u - l.u0) - Rational(r));
        return d < Rational(1) ? Rational(1) - d : Rational(0);
    };
    Rational area;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
        area = area + (points[i + 1] - points[i]) * (overlap(points[i]) + overlap(points[i + 1])) *
                          Rational(1, 2);
    }
    return area;
}

struct Stats {
    double worst_ratio = 0.0;  // max over pixels of |weight - area| / (|g| / 4)
    int lines = 0;
};

void check_line(long long ax4, long long ay4, long long bx4, long long by4, int size,
                bool check_area, Stats& stats) {
    const refraster::textbook::Point2 a{static_cast<double>(ax4) / 4.0,
                                        static_cast<double>(ay4) / 4.0};
    const refraster::textbook::Point2 b{static_cast<double>(bx4) / 4.0,
                                        static_cast<double>(by4) / 4.0};
    const auto result = refraster::textbook::wu_line(a, b, size, size);
    const ExactLine l = exact_line(ax4, ay4, bx4, by4);
    const auto expected = exact_weights(l);
    ++stats.lines;
    // Statement 1, pixel by pixel.
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const auto it = expected.find({x, y});
            const double want = it == expected.end() ? 0.0 : it->second.to_double();
            ASSERT_NEAR(result.raster.at(x, y), want, kFloatBound)
                << "pixel (" << x << ", " << y << ") of (" << a.x << ", " << a.y << ") to (" << b.x
                << ", " << b.y << ")";
        }
    }
    // Each column's weights sum to its length.
    const long long first = round_half_up(l.u0);
    const long long last = round_half_up(l.u1);
    ASSERT_EQ(static_cast<long long>(result.columns.size()), last - first + 1);
    for (std::size_t i = 0; i < result.columns.size(); ++i) {
        const auto& col = result.columns[i];
        const long long c = first + static_cast<long long>(i);
        const double len = column_length(l, c, first, last).to_double();
        EXPECT_NEAR(col.weight_low + col.weight_high, len, kFloatBound);
        EXPECT_NEAR(col.length, len, kFloatBound);
    }
    if (!check_area) return;
    // Statement 2: against the band's exact area, on every pixel near the line.
    const double bound = std::fabs(l.gradient.to_double()) / 4.0 + kFloatBound;
    const long long vmin = static_cast<long long>(min(l.v0, l.v1).floor()) - 2;
    const long long vmax = static_cast<long long>(max(l.v0, l.v1).floor()) + 3;
    for (long long c = first; c <= last; ++c) {
        Rational column_area;
        for (long long r = vmin; r <= vmax; ++r) {
            const Rational area = band_area(l, c, r);
            column_area = column_area + area;
            const int x = static_cast<int>(l.steep ? r : c);
            const int y = static_cast<int>(l.steep ? c : r);
            const double err = std::fabs(result.raster.at(x, y) - area.to_double());
            EXPECT_LE(err, bound) << "pixel (" << x << ", " << y << ")";
            if (l.gradient.sign() != 0) {
                stats.worst_ratio =
                    std::max(stats.worst_ratio, err / (std::fabs(l.gradient.to_double()) / 4.0));
            }
        }
        EXPECT_EQ(column_area, column_length(l, c, first, last));
    }
}

TEST(TextbookWu, EveryPairOfPixelCentresGetsTheExactColumnWeights) {
    constexpr int kSize = 10;
    Stats stats;
    for (int a = 0; a < 64; ++a) {
        for (int b = 0; b < 64; ++b) {
            // Centres of an 8 x 8 block inside a 10 x 10 raster: x = i + 1/2 + 1.
            const long long ax4 = 4 * (a % 8 + 1) + 2;
            const long long ay4 = 4 * (a / 8 + 1) + 2;
            const long long bx4 = 4 * (b % 8 + 1) + 2;
            const long long by4 = 4 * (b / 8 + 1) + 2;
            check_line(ax4, ay4, bx4, by4, kSize, false, stats);
            if (HasFatalFailure()) return;
        }
    }
    // Between centres, the end columns carry half a column each.
    const auto r = refraster::textbook::wu_line({1.5, 1.5}, {5.5, 2.5}, 8, 8);
    ASSERT_EQ(r.columns.size(), 5u);
    EXPECT_DOUBLE_EQ(r.columns.front().length, 0.5);
    EXPECT_DOUBLE_EQ(r.columns.back().length, 0.5);
    EXPECT_DOUBLE_EQ(r.columns[2].weight_low, 0.5);
    EXPECT_DOUBLE_EQ(r.columns[2].weight_high, 0.5);
}

TEST(TextbookWu, QuarterPixelEndpointsMatchTheExactBandAreaWithinAQuarterOfTheSlope) {
    // Every pair of endpoints on the 1/4 grid over [1, 4]^2, in a 6 x 6 raster.
    constexpr long long kLo = 4;
    constexpr long long kHi = 16;
    constexpr long long kSide = kHi - kLo + 1;
    Stats stats;
    for (long long a = 0; a < kSide * kSide; ++a) {
        for (long long b = 0; b < kSide * kSide; ++b) {
            check_line(kLo + a % kSide, kLo + a / kSide, kLo + b % kSide, kLo + b / kSide, 6, true,
                       stats);
            if (HasFatalFailure()) return;
        }
    }
    EXPECT_EQ(stats.lines, static_cast<int>(kSide * kSide * kSide * kSide));
    // The bound |g| / 4 is reached (a line through a pixel centre at a column centre).
    EXPECT_NEAR(stats.worst_ratio, 1.0, 1e-9);
}

TEST(TextbookWu, TraceHasOneStepPerColumn) {
    refraster::textbook::Trace trace;
    const auto r = refraster::textbook::wu_line({0.5, 0.5}, {6.25, 2.75}, 8, 8, &trace);
    ASSERT_EQ(trace.steps.size(), r.columns.size() + 1);
    for (std::size_t i = 0; i < r.columns.size(); ++i) {
        ASSERT_EQ(trace.steps[i + 1].pixels.size(), 2u);
        EXPECT_EQ(trace.steps[i + 1].pixels[0].weight, r.columns[i].weight_low);
    }
}

}  // namespace
