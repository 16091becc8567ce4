// The antialiasing study's exact answers: big integers and rationals on cases with known
// answers beyond 64 bits, rational pixel areas against hand-computed pixels and the
// triangle's own area, and the filtered coverage against the rational area, full coverage, a
// finer quadrature and a brute-force sum.
#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <random>

#include "study/exact_area.hpp"

namespace harness::study {
// Failure messages show the fraction.
void PrintTo(const Rational& r, std::ostream* os) {
    *os << r.num().to_string() << "/" << r.den().to_string();
}
}  // namespace harness::study

namespace {

using harness::study::BigInt;
using harness::study::classify_support;
using harness::study::exact_pixel_area;
using harness::study::Filter;
using harness::study::filter_weight;
using harness::study::filtered_coverage;
using harness::study::GridPoint;
using harness::study::GridTriangle;
using harness::study::Quadrature;
using harness::study::Rational;
using harness::study::SupportOverlap;

BigInt pow2(std::size_t e) {
    return BigInt(1).shifted_left(e);
}

Rational frac(std::int64_t n, std::int64_t d) {
    return Rational(BigInt(n), BigInt(d));
}

// A vertex in pixel units (a multiple of 1/256).
GridPoint px(double x, double y) {
    return {static_cast<std::int64_t>(std::lround(x * 256.0)),
            static_cast<std::int64_t>(std::lround(y * 256.0))};
}

GridTriangle tri(GridPoint a, GridPoint b, GridPoint c) {
    return {a, b, c};
}

TEST(StudyExactArea, BigIntProductsBeyond64Bits) {
    // (2^64 + 1)(2^64 - 1) = 2^128 - 1.
    const BigInt a = pow2(64) + BigInt(1);
    const BigInt b = pow2(64) - BigInt(1);
    EXPECT_EQ((a * b).to_string(), "340282366920938463463374607431768211455");
    EXPECT_EQ(a * b, pow2(128) - BigInt(1));
    EXPECT_EQ(pow2(100).to_string(), "1267650600228229401496703205376");
    BigInt f(1);
    for (std::int64_t i = 2; i <= 30; ++i) f = f * BigInt(i);
    EXPECT_EQ(f.to_string(), "265252859812191058636308480000000");
    EXPECT_EQ(f.bit_length(), 108u);
    // Signs: (-x) y + x y = 0, and subtraction across zero.
    EXPECT_TRUE((-f * a + f * a).is_zero());
    EXPECT_EQ((BigInt(5) - pow2(70)).to_string(), "-1180591620717411303419");
    EXPECT_EQ((BigInt(-7) * BigInt(-9)).to_string(), "63");
    EXPECT_EQ(BigInt(INT64_MIN).to_string(), "-9223372036854775808");
    EXPECT_EQ((BigInt(INT64_MIN) * BigInt(INT64_MIN)).to_string(),
              "85070591730234615865843651857942052864");
    EXPECT_EQ(pow2(200).shifted_right(137), pow2(63));
    EXPECT_EQ((pow2(100) + BigInt(12345)).shifted_right(100), BigInt(1));
}

TEST(StudyExactArea, BigIntOrdering) {
    EXPECT_LT(BigInt(-1), BigInt(0));
    EXPECT_LT(-pow2(80), BigInt(-5));
    EXPECT_LT(BigInt(5), pow2(80));
    EXPECT_GT(pow2(80) + BigInt(1), pow2(80));
    EXPECT_LT(-(pow2(80) + BigInt(1)), -pow2(80));
    EXPECT_EQ(pow2(80) - pow2(80), BigInt(0));
    EXPECT_EQ(BigInt(0).sign(), 0);
    EXPECT_EQ((-pow2(90)).sign(), -1);
}

TEST(StudyExactArea, BigIntToDoubleRoundsCorrectly) {
    EXPECT_EQ(pow2(100).to_double(), std::ldexp(1.0, 100));
    EXPECT_EQ((pow2(100) + BigInt(1)).to_double(), std::ldexp(1.0, 100));
    // 2^53 + 1 is halfway: ties to even gives 2^53; 2^53 + 3 rounds up to 2^53 + 4.
    EXPECT_EQ((pow2(53) + BigInt(1)).to_double(), std::ldexp(1.0, 53));
    EXPECT_EQ((pow2(53) + BigInt(3)).to_double(), std::ldexp(1.0, 53) + 4.0);
    // Halfway far beyond 64 bits, then just above halfway: only the sticky bit tells them
    // apart.
    const BigInt half = pow2(200) + pow2(147);
    EXPECT_EQ(half.to_double(), std::ldexp(1.0, 200));
    EXPECT_EQ((half + BigInt(1)).to_double(), std::ldexp(1.0, 200) + std::ldexp(1.0, 148));
    EXPECT_EQ((-(half + BigInt(1))).to_double(), -(std::ldexp(1.0, 200) + std::ldexp(1.0, 148)));
    EXPECT_EQ(BigInt(-123456789).to_double(), -123456789.0);
}

TEST(StudyExactArea, RationalArithmetic) {
    EXPECT_EQ(frac(1, 3) + frac(1, 6), frac(1, 2));
    EXPECT_EQ(frac(1, 3) - frac(1, 2), frac(-1, 6));
    EXPECT_EQ(frac(2, -4), frac(-1, 2));
    EXPECT_GT(frac(2, -4).den().sign(), 0);
    EXPECT_EQ(frac(3, 4) * frac(8, 9), frac(2, 3));
    EXPECT_LT(frac(1, 3), frac(1, 2));
    EXPECT_LT(frac(-1, 2), frac(-1, 3));
    // 10^30 / (3 10^30) is 1/3, and converts like it.
    BigInt e30(1);
    for (int i = 0; i < 30; ++i) e30 = e30 * BigInt(10);
    const Rational third(e30, BigInt(3) * e30);
    EXPECT_EQ(third, frac(1, 3));
    EXPECT_EQ(third.to_double(), 1.0 / 3.0);
    // Numerator and denominator below 2^53 are exact doubles, so IEEE division is the
    // correctly rounded quotient to compare against.
    std::mt19937_64 rng(7);
    for (int i = 0; i < 2000; ++i) {
        const auto n = static_cast<std::int64_t>(rng() >> 11) - (std::int64_t{1} << 52);
        const auto d = static_cast<std::int64_t>(rng() >> (11 + rng() % 40)) + 1;
        ASSERT_EQ(frac(n, d).to_double(), static_cast<double>(n) / static_cast<double>(d))
            << n << " / " << d;
    }
}

TEST(StudyExactArea, HandComputedPixels) {
    // Half the pixel below its diagonal.
    const Rational half = exact_pixel_area(tri(px(0, 0), px(1, 0), px(0, 1)), 0, 0);
    EXPECT_EQ(half.num() * BigInt(2), half.den());
    // A triangle around the whole pixel.
    EXPECT_EQ(exact_pixel_area(tri(px(-10, -10), px(10, -10), px(0, 10)), 0, 0), frac(1, 1));
    // A corner cut with legs 1/4, alone and as the tip of a large triangle: pixel (3, 5)
    // below x + y = 8.25 is the triangle (3, 5), (3.25, 5), (3, 5.25).
    EXPECT_EQ(exact_pixel_area(tri(px(0, 0), px(0.25, 0), px(0, 0.25)), 0, 0), frac(1, 32));
    const GridTriangle big = tri(px(0, 0), px(8.25, 0), px(0, 8.25));
    EXPECT_EQ(exact_pixel_area(big, 3, 5), frac(1, 32));
    // Pixel (3, 4) loses the corner (4, 5) above the line, legs 3/4: 1 - 9/32.
    EXPECT_EQ(exact_pixel_area(big, 3, 4), frac(23, 32));
    // Pixel (4, 4) keeps its corner (4, 4) below the line, legs 1/4; (4, 5) only touches it.
    EXPECT_EQ(exact_pixel_area(big, 4, 4), frac(1, 32));
    EXPECT_EQ(exact_pixel_area(big, 4, 5), frac(0, 1));
    EXPECT_EQ(exact_pixel_area(big, 2, 2), frac(1, 1));
    // (0,0), (2,0), (0,2) over four pixels.
    const GridTriangle two = tri(px(0, 0), px(2, 0), px(0, 2));
    EXPECT_EQ(exact_pixel_area(two, 0, 0), frac(1, 1));
    EXPECT_EQ(exact_pixel_area(two, 1, 0), frac(1, 2));
    EXPECT_EQ(exact_pixel_area(two, 0, 1), frac(1, 2));
    EXPECT_EQ(exact_pixel_area(two, 1, 1), frac(0, 1));
    // Three edges crossing the pixel: x + y >= 1/4 and y >= x - 3/4 cut the two bottom
    // corners (1/32 each), y <= 7/8 a strip of 1/8: a hexagon of 13/16.
    const GridTriangle hex = tri(px(0.5, -0.25), px(1.625, 0.875), px(-0.625, 0.875));
    EXPECT_EQ(exact_pixel_area(hex, 0, 0), frac(13, 16));
    // A pixel far from the triangle, and negative pixel coordinates.
    EXPECT_EQ(exact_pixel_area(two, 5, 5), frac(0, 1));
    EXPECT_EQ(exact_pixel_area(tri(px(-1, -1), px(0, -1), px(-1, 0)), -1, -1), frac(1, 2));
}

TEST(StudyExactArea, DegenerateTrianglesCoverNothing) {
    const GridTriangle line = tri(px(0, 0), px(3, 3), px(1.5, 1.5));
    EXPECT_EQ(exact_pixel_area(line, 1, 1), frac(0, 1));
    const GridTriangle point = tri(px(0.5, 0.5), px(0.5, 0.5), px(0.5, 0.5));
    EXPECT_EQ(exact_pixel_area(point, 0, 0), frac(0, 1));
    EXPECT_EQ(filtered_coverage(line, 1, 1, Filter::gaussian), 0.0);
    EXPECT_EQ(classify_support(line, 1, 1, Filter::tent), SupportOverlap::outside);
}

GridTriangle random_triangle(std::mt19937_64& rng, std::int64_t span) {
    GridTriangle t;
    for (auto& p : t) {
        p.x = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(span)) - span / 4;
        p.y = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(span)) - span / 4;
    }
    return t;
}

TEST(StudyExactArea, PixelAreasSumToTheTriangleAndIgnoreOrientation) {
    std::mt19937_64 rng(11);
    for (int n = 0; n < 40; ++n) {
        const GridTriangle t = random_triangle(rng, 6 * 256);
        const GridTriangle reversed = {t[2], t[1], t[0]};
        Rational sum;
        for (std::int64_t y = -3; y <= 6; ++y) {
            for (std::int64_t x = -3; x <= 6; ++x) {
                const Rational a = exact_pixel_area(t, x, y);
                ASSERT_GE(a.sign(), 0);
                ASSERT_LE(a, frac(1, 1));
                ASSERT_EQ(a, exact_pixel_area(reversed, x, y));
                sum = sum + a;
            }
        }
        ASSERT_EQ(sum, harness::study::triangle_area(t)) << "triangle " << n;
    }
}

TEST(StudyExactArea, BoxQuadratureMatchesTheRationalArea) {
    std::mt19937_64 rng(12);
    for (int n = 0; n < 60; ++n) {
        const GridTriangle t = random_triangle(rng, 5 * 256);
        for (std::int64_t y = -2; y <= 4; ++y) {
            for (std::int64_t x = -2; x <= 4; ++x) {
                const double exact = exact_pixel_area(t, x, y).to_double();
                ASSERT_NEAR(filtered_coverage(t, x, y, Filter::box), exact, 1e-12);
                // Where the pixel lies is decided exactly, and agrees with the area.
                const SupportOverlap where = classify_support(t, x, y, Filter::box);
                const Rational area = exact_pixel_area(t, x, y);
                ASSERT_EQ(where == SupportOverlap::outside, area.sign() == 0);
                ASSERT_EQ(where == SupportOverlap::inside, area == frac(1, 1));
            }
        }
    }
}

TEST(StudyExactArea, FullCoverageIsOne) {
    const GridTriangle huge = tri(px(-1000, -1000), px(1000, -1000), px(0, 1000));
    for (const Filter f : harness::study::kFilters) {
        EXPECT_NEAR(filtered_coverage(huge, 3, -7, f), 1.0, 1e-12);
        EXPECT_EQ(classify_support(huge, 3, -7, f), SupportOverlap::inside);
    }
    // Half-planes through the pixel centre: each filter is symmetric, so exactly half.
    const GridTriangle lower = tri(px(-1000, 0.5), px(1000, 0.5), px(0, -1000));
    for (const Filter f : harness::study::kFilters) {
        EXPECT_NEAR(filtered_coverage(lower, 0, 0, f), 0.5, 1e-12);
        EXPECT_EQ(classify_support(lower, 0, 0, f), SupportOverlap::partial);
    }
}

TEST(StudyExactArea, TentAndGaussianOfTheHandComputedHalf) {
    // Below the diagonal through the pixel's centre, by symmetry, for every filter: the
    // diagonal y = x maps the support onto itself.
    const GridTriangle below = tri(px(-50, -50), px(50, -50), px(50, 50));
    for (const Filter f : harness::study::kFilters) {
        EXPECT_NEAR(filtered_coverage(below, 0, 0, f), 0.5, 1e-12);
        EXPECT_NEAR(filtered_coverage(below, 7, 7, f), 0.5, 1e-12);
    }
    // The tent over the quadrant x >= cx, y >= cy is a quarter.
    const GridTriangle quadrant = tri(px(0.5, 0.5), px(100, 0.5), px(0.5, 100));
    EXPECT_NEAR(filtered_coverage(quadrant, 0, 0, Filter::tent), 0.25, 1e-12);
}

TEST(StudyExactArea, GaussianQuadratureConverges) {
    std::mt19937_64 rng(13);
    double worst = 0.0;
    for (int n = 0; n < 41; ++n) {
        // First a steep edge from a vertex on the bottom row of pixel (1, 0)'s support: the
        // cross-section's top sweeps the whole support within 0.1 px of x.
        const GridTriangle t =
            n == 0 ? tri(px(0.515625, -1), px(2.26171875, 0.0859375), px(0.609375, 2.38671875))
                   : random_triangle(rng, 5 * 256);
        for (std::int64_t y = -2; y <= 4; ++y) {
            for (std::int64_t x = -2; x <= 4; ++x) {
                const double coarse = filtered_coverage(t, x, y, Filter::gaussian);
                const double fine = filtered_coverage(t, x, y, Filter::gaussian, {12, 0.125});
                const double finer = filtered_coverage(t, x, y, Filter::gaussian, {20, 0.0625});
                worst = std::max(worst, std::abs(coarse - fine));
                ASSERT_NEAR(coarse, finer, 1e-13);
            }
        }
    }
    EXPECT_LT(worst, 1e-13);
}

// The midpoint rule on a fine grid over the support, with the weight of every covered cell.
double brute_force(const GridTriangle& t, std::int64_t px_, std::int64_t py_, Filter f, int n) {
    const double r = harness::study::filter_radius(f);
    const double cx = static_cast<double>(px_) + 0.5;
    const double cy = static_cast<double>(py_) + 0.5;
    double ax[3], ay[3];
    for (int i = 0; i < 3; ++i) {
        ax[i] = static_cast<double>(t[static_cast<std::size_t>(i)].x) / 256.0;
        ay[i] = static_cast<double>(t[static_cast<std::size_t>(i)].y) / 256.0;
    }
    const double orient = (ax[1] - ax[0]) * (ay[2] - ay[0]) - (ax[2] - ax[0]) * (ay[1] - ay[0]);
    double covered = 0.0;
    double total = 0.0;
    const double h = 2.0 * r / n;
    for (int j = 0; j < n; ++j) {
        const double y = cy - r + (j + 0.5) * h;
        for (int i = 0; i < n; ++i) {
            const double x = cx - r + (i + 0.5) * h;
            const double w = filter_weight(f, x - cx, y - cy);
            total += w;
            bool in = true;
            for (int e = 0; e < 3; ++e) {
                const int k = (e + 1) % 3;
                const double side = (ax[k] - ax[e]) * (y - ay[e]) - (ay[k] - ay[e]) * (x - ax[e]);
                if (side * orient < 0) in = false;
            }
            if (in) covered += w;
        }
    }
    return covered / total;
}

TEST(StudyExactArea, AgreesWithABruteForceSum) {
    std::mt19937_64 rng(14);
    for (int n = 0; n < 6; ++n) {
        const GridTriangle t = random_triangle(rng, 4 * 256);
        for (const Filter f : harness::study::kFilters) {
            for (std::int64_t p = 0; p <= 2; ++p) {
                EXPECT_NEAR(filtered_coverage(t, p, 1, f), brute_force(t, p, 1, f, 1000), 1e-4)
                    << harness::study::filter_name(f) << " triangle " << n << " pixel " << p;
            }
        }
    }
}

TEST(StudyExactArea, ClassificationAgreesWithTheCoverage) {
    std::mt19937_64 rng(15);
    int partial = 0;
    for (int n = 0; n < 30; ++n) {
        const GridTriangle t = random_triangle(rng, 8 * 256);
        for (const Filter f : harness::study::kFilters) {
            for (std::int64_t y = -3; y <= 7; ++y) {
                for (std::int64_t x = -3; x <= 7; ++x) {
                    const double c = filtered_coverage(t, x, y, f);
                    switch (classify_support(t, x, y, f)) {
                        case SupportOverlap::outside:
                            ASSERT_EQ(c, 0.0);
                            break;
                        case SupportOverlap::inside:
                            ASSERT_NEAR(c, 1.0, 1e-12);
                            break;
                        case SupportOverlap::partial:
                            ++partial;
                            ASSERT_GT(c, 0.0);
                            ASSERT_LT(c, 1.0);
                            break;
                    }
                }
            }
        }
    }
    EXPECT_GT(partial, 1000);
}

}  // namespace
