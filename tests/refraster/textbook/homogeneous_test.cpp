// Homogeneous rasterization (homogeneous.hpp) against clip-then-rasterize, the reference that
// divides: clipped against w = near_w in homogeneous coordinates, projected, the convex polygon
// tested at each centre with 1024-bit determinants.
// - Triangles whose vertices all have w >= near_w are never clipped: the two must be equal,
//   pixel for pixel, with and without the w > 0 test (there is no external triangle then).
// - Triangles crossing w = 0: every pixel where they differ must be explained, as lying
//   between the eye and the near plane (0 < w <= near_w) with the w test; without it, also as
//   the external triangle (w < 0). No difference may be on an edge or unexplained, and
//   both kinds must occur (the tests are not vacuous).
// - Independently of both, a pixel's w from the plane equation decides the explanation's
//   category: the centre's w, solved here in rationals from the vertices, is in (0, near_w]
//   for every clipped-sliver pixel.
#include "refraster/textbook/homogeneous.hpp"

#include <gtest/gtest.h>

#include <random>

#include "exact_support.hpp"

namespace {

using refraster::textbook::ClipTriangle;
using refraster::textbook::HomogeneousDifference;
using refraster::textbook::Viewport;
using textbook_test::Rational;

constexpr int kSize = 16;
constexpr double kNear = 1.0 / 16.0;

double sixteenth(std::mt19937& rng, int lo, int hi) {
    return std::uniform_int_distribution<int>(16 * lo, 16 * hi)(rng) / 16.0;
}

Rational exact(double v) {
    return Rational(static_cast<long long>(std::llround(v * 16.0)), 16);
}

// w at the centre of pixel (i, j) on the triangle's plane, from the homogeneous vertices
// V_k = (vx w_k + (x_k + w_k) W / 2, ..., w_k): 1/w = sum of (M^-1 p).
Rational w_at(const ClipTriangle& t, Viewport vp, int i, int j) {
    std::array<std::array<Rational, 3>, 3> m;  // m[row][col], columns the vertices
    for (std::size_t k = 0; k < 3; ++k) {
        const Rational w = exact(t[k].w);
        m[0][k] = Rational(vp.x) * w + (exact(t[k].x) + w) * Rational(vp.width, 2);
        m[1][k] = Rational(vp.y) * w + (exact(t[k].y) + w) * Rational(vp.height, 2);
        m[2][k] = w;
    }
    const std::array<Rational, 3> p = {Rational(2 * i + 1, 2), Rational(2 * j + 1, 2), 1};
    // Solve m b = p by Cramer's rule; 1/w = b0 + b1 + b2.
    const auto det3 = [](const std::array<std::array<Rational, 3>, 3>& a) {
        return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
               a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
               a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    const Rational d = det3(m);
    Rational inverse_w;
    for (std::size_t c = 0; c < 3; ++c) {
        auto mc = m;
        for (std::size_t r = 0; r < 3; ++r) mc[r][c] = p[r];
        inverse_w = inverse_w + det3(mc) / d;
    }
    return Rational(1) / inverse_w;
}

ClipTriangle random_triangle(std::mt19937& rng, double w_lo, double w_hi) {
    ClipTriangle t;
    std::uniform_int_distribution<int> wd(static_cast<int>(16 * w_lo), static_cast<int>(16 * w_hi));
    for (auto& v : t) {
        v.w = wd(rng) / 16.0;
        v.x = sixteenth(rng, -3, 3);
        v.y = sixteenth(rng, -3, 3);
    }
    return t;
}

TEST(TextbookHomogeneous, TrianglesInFrontOfTheNearPlaneEqualClipThenRasterize) {
    std::mt19937 rng(1997);
    const Viewport vp{0, 0, kSize, kSize};
    int covered = 0;
    for (int n = 0; n < 1500; ++n) {
        const ClipTriangle t = random_triangle(rng, kNear, 3.0);
        const auto h = refraster::textbook::homogeneous_rasterize(t, vp, kSize, kSize);
        const auto naive = refraster::textbook::homogeneous_rasterize(t, vp, kSize, kSize, false);
        const auto c = refraster::textbook::clip_then_rasterize(t, vp, kNear, kSize, kSize);
        ASSERT_EQ(h, c) << "triangle " << n;
        ASSERT_EQ(naive, c) << "triangle " << n;
        covered += h.count_nonzero();
    }
    EXPECT_GT(covered, 10000);
}

TEST(TextbookHomogeneous, TrianglesCrossingWZeroDifferOnlyWhereExplained) {
    std::mt19937 rng(1998);
    const Viewport vp{2, 1, 12, 14};  // the raster is larger: no scissor, a guard band
    int sliver = 0;
    int external = 0;
    for (int n = 0; n < 1500; ++n) {
        ClipTriangle t = random_triangle(rng, -2.0, 3.0);
        // At least one vertex on each side of w = 0.
        t[0].w = std::abs(t[0].w) + 1.0 / 16.0;
        t[1].w = -std::abs(t[1].w) - 1.0 / 16.0;
        const auto h = refraster::textbook::homogeneous_rasterize(t, vp, kSize, kSize);
        const auto naive = refraster::textbook::homogeneous_rasterize(t, vp, kSize, kSize, false);
        const auto c = refraster::textbook::clip_then_rasterize(t, vp, kNear, kSize, kSize);
        for (int j = 0; j < kSize; ++j) {
            for (int i = 0; i < kSize; ++i) {
                if (h.at(i, j) != c.at(i, j)) {
                    const auto why = refraster::textbook::explain_difference(t, vp, kNear, i, j);
                    ASSERT_EQ(why, HomogeneousDifference::BetweenEyeAndNearPlane)
                        << "triangle " << n << " pixel (" << i << ", " << j
                        << "): " << refraster::textbook::to_string(why);
                    ASSERT_EQ(h.at(i, j), 1.0);  // the sliver is drawn, never dropped
                    const Rational w = w_at(t, vp, i, j);
                    ASSERT_GT(w.sign(), 0);
                    ASSERT_LE(w, exact(kNear));
                    ++sliver;
                }
                if (naive.at(i, j) != h.at(i, j)) {
                    const auto why = refraster::textbook::explain_difference(t, vp, kNear, i, j);
                    ASSERT_EQ(why, HomogeneousDifference::ExternalTriangle)
                        << "triangle " << n << " pixel (" << i << ", " << j << ")";
                    ASSERT_LT(w_at(t, vp, i, j).sign(), 0);
                    ++external;
                }
            }
        }
    }
    EXPECT_GT(sliver, 0);
    EXPECT_GT(external, 100);
}

TEST(TextbookHomogeneous, TheExternalTriangleOfAHandBuiltCase) {
    // One vertex behind the eye: the naive sign test also draws the mirrored part.
    const ClipTriangle t = {{{-0.5, -0.5, 1.0}, {0.5, -0.5, 1.0}, {0.0, -0.25, -0.5}}};
    const Viewport vp{0, 0, kSize, kSize};
    const auto h = refraster::textbook::homogeneous_rasterize(t, vp, kSize, kSize);
    const auto naive = refraster::textbook::homogeneous_rasterize(t, vp, kSize, kSize, false);
    const auto c = refraster::textbook::clip_then_rasterize(t, vp, kNear, kSize, kSize);
    EXPECT_EQ(h, c);  // near_w = 1/16 clips nothing visible in this raster
    EXPECT_GT(naive.count_nonzero(), h.count_nonzero());
    // The third vertex, behind the eye, projects to (0, 0.5) in NDC, (8, 12) in the window.
    // The w > 0 part hangs below the edge from (4, 4) to (12, 4), widening downwards; the
    // external triangle is the wedge above (8, 12), where w < 0.
    EXPECT_EQ(h.at(8, 2), 1.0);
    EXPECT_EQ(h.at(8, 8), 0.0);
    EXPECT_EQ(naive.at(8, 14), 1.0);
    EXPECT_EQ(h.at(8, 14), 0.0);
    EXPECT_EQ(refraster::textbook::explain_difference(t, vp, kNear, 8, 14),
              HomogeneousDifference::ExternalTriangle);
    EXPECT_LT(w_at(t, vp, 8, 14).sign(), 0);
}

TEST(TextbookHomogeneous, TraceHasTheSetupAndOneStepPerRow) {
    refraster::textbook::Trace trace;
    const ClipTriangle t = {{{-0.5, -0.5, 1.0}, {0.5, -0.5, 1.0}, {0.0, 0.5, 1.0}}};
    const auto h = refraster::textbook::homogeneous_rasterize(t, {0, 0, 8, 8}, 8, 8, true, &trace);
    ASSERT_EQ(trace.steps.size(), 1u + 8u);
    EXPECT_EQ(trace.steps[0].state.size(), 4u);  // det and three edge functions
    int pixels = 0;
    for (const auto& s : trace.steps) pixels += static_cast<int>(s.pixels.size());
    EXPECT_EQ(pixels, h.count_nonzero());
}

}  // namespace
