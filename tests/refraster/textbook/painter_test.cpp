// The painter's algorithm and the z-buffer (painter.hpp) against a per-pixel oracle in
// rational arithmetic (exact_support.hpp), computed by different formulas:
// - coverage: the centre moved to (x_c + e, y_c + e^2) with the concrete e = 2^-12, then the
//   plain strict point-in-triangle test. With vertices on the 1/4 grid inside 32 pixels, an
//   edge function is a multiple of 1/16 and the nudge changes it by less than 32 e + 32 e^2 <
//   1/16, so the concrete nudge decides exactly as the infinitesimal one;
// - depth: the plane through the three vertices, z(p) = z_a + grad z . (p - a), the gradient by
//   Cramer's rule;
// - the z-buffer shows the covering triangle of least depth, the earliest on a tie; the
//   painter shows the covering triangle drawn last in the stable back-to-front order of the
//   key; their first difference in row-major order from the bottom is found by scanning.
// Random scenes of layers at distinct constant depths must agree everywhere; hand-built
// cyclic overlaps and interpenetrations must differ, at the pixel and triangles the oracle
// names.
#include "refraster/textbook/painter.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "exact_support.hpp"

namespace {

using refraster::textbook::DepthTriangle;
using refraster::textbook::PainterKey;
using textbook_test::Rational;
using textbook_test::RPoint;

Rational exact(double v) {
    const auto q = static_cast<long long>(std::llround(v * 65536.0));
    EXPECT_EQ(static_cast<double>(q) / 65536.0, v);
    return Rational(q, 65536);
}

bool oracle_covers(const DepthTriangle& t, int x, int y) {
    const Rational e(1, 4096);
    const RPoint p{Rational(2 * x + 1, 2) + e, Rational(2 * y + 1, 2) + e * e};
    std::array<RPoint, 3> v;
    for (std::size_t i = 0; i < 3; ++i) v[i] = {exact(t.position[i].x), exact(t.position[i].y)};
    const int s = textbook_test::orient(v[0], v[1], v[2]).sign();
    if (s == 0) return false;
    for (std::size_t i = 0; i < 3; ++i) {
        if (textbook_test::orient(v[i], v[(i + 1) % 3], p).sign() != s) return false;
    }
    return true;
}

Rational oracle_depth(const DepthTriangle& t, int x, int y) {
    const Rational ax = exact(t.position[0].x), ay = exact(t.position[0].y);
    const Rational bx = exact(t.position[1].x) - ax, by = exact(t.position[1].y) - ay;
    const Rational cx = exact(t.position[2].x) - ax, cy = exact(t.position[2].y) - ay;
    const Rational za = exact(t.depth[0]);
    const Rational zb = exact(t.depth[1]) - za, zc = exact(t.depth[2]) - za;
    // Solve [bx by; cx cy] [gx; gy] = [zb; zc].
    const Rational det = bx * cy - by * cx;
    const Rational gx = (zb * cy - by * zc) / det;
    const Rational gy = (bx * zc - zb * cx) / det;
    return za + gx * (Rational(2 * x + 1, 2) - ax) + gy * (Rational(2 * y + 1, 2) - ay);
}

struct Oracle {
    std::vector<int> painter;
    std::vector<int> z_buffer;
};

Oracle oracle(const std::vector<DepthTriangle>& tris, PainterKey key, int w, int h) {
    std::vector<int> order(tris.size());
    std::iota(order.begin(), order.end(), 0);
    const auto key_of = [&](int i) {
        const auto& d = tris[static_cast<std::size_t>(i)].depth;
        return key == PainterKey::FarthestVertex ? std::max({d[0], d[1], d[2]})
                                                 : (d[0] + d[1] + d[2]) / 3.0;
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return key_of(a) > key_of(b); });
    Oracle o;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            int painted = -1;
            for (const int i : order) {
                if (oracle_covers(tris[static_cast<std::size_t>(i)], x, y)) painted = i;
            }
            int nearest = -1;
            Rational best;
            for (std::size_t i = 0; i < tris.size(); ++i) {
                if (!oracle_covers(tris[i], x, y)) continue;
                const Rational z = oracle_depth(tris[i], x, y);
                if (nearest < 0 || z < best) {
                    nearest = static_cast<int>(i);
                    best = z;
                }
            }
            o.painter.push_back(painted);
            o.z_buffer.push_back(nearest);
        }
    }
    return o;
}

void expect_matches_oracle(const std::vector<DepthTriangle>& tris, PainterKey key, int w, int h,
                           bool expect_equal) {
    const auto painted = refraster::textbook::painter(tris, key, w, h);
    const auto buffered = refraster::textbook::z_buffer(tris, w, h);
    const Oracle o = oracle(tris, key, w, h);
    ASSERT_EQ(painted.visible, o.painter);
    ASSERT_EQ(buffered.visible, o.z_buffer);
    const auto diff = refraster::textbook::first_difference(painted, buffered);
    std::optional<refraster::textbook::VisibilityDifference> want;
    for (int i = 0; i < w * h && !want; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (o.painter[k] != o.z_buffer[k]) {
            want = refraster::textbook::VisibilityDifference{i % w, i / w, o.painter[k],
                                                             o.z_buffer[k]};
        }
    }
    ASSERT_EQ(diff, want);
    ASSERT_EQ(diff.has_value(), !expect_equal);
}

double quarter(std::mt19937& rng, int lo, int hi) {
    return std::uniform_int_distribution<int>(4 * lo, 4 * hi)(rng) / 4.0;
}

TEST(TextbookPainter, LayersAtDistinctConstantDepthsMatchTheZBuffer) {
    std::mt19937 rng(1972);
    for (int scene = 0; scene < 150; ++scene) {
        const int n = 1 + scene % 6;
        std::vector<double> depths;
        for (int i = 0; i < n; ++i) depths.push_back((i + 1) / 16.0);
        std::shuffle(depths.begin(), depths.end(), rng);
        std::vector<DepthTriangle> tris;
        for (int i = 0; i < n; ++i) {
            DepthTriangle t;
            for (auto& p : t.position) p = {quarter(rng, -2, 14), quarter(rng, -2, 14)};
            const double z = depths[static_cast<std::size_t>(i)];
            t.depth = {z, z, z};
            tris.push_back(t);
        }
        SCOPED_TRACE("scene " + std::to_string(scene));
        expect_matches_oracle(tris, PainterKey::FarthestVertex, 12, 12, true);
        expect_matches_oracle(tris, PainterKey::MeanDepth, 12, 12, true);
        if (HasFatalFailure()) return;
    }
}

TEST(TextbookPainter, TiltedRandomScenesDifferWhereTheOracleSays) {
    std::mt19937 rng(1974);
    int differing = 0;
    for (int scene = 0; scene < 150; ++scene) {
        std::vector<DepthTriangle> tris;
        for (int i = 0; i < 4; ++i) {
            DepthTriangle t;
            for (auto& p : t.position) p = {quarter(rng, -2, 14), quarter(rng, -2, 14)};
            for (auto& z : t.depth) z = std::uniform_int_distribution<int>(0, 64)(rng) / 64.0;
            tris.push_back(t);
        }
        const auto painted = refraster::textbook::painter(tris, PainterKey::FarthestVertex, 12, 12);
        const auto buffered = refraster::textbook::z_buffer(tris, 12, 12);
        const bool same = !refraster::textbook::first_difference(painted, buffered).has_value();
        differing += same ? 0 : 1;
        SCOPED_TRACE("scene " + std::to_string(scene));
        expect_matches_oracle(tris, PainterKey::FarthestVertex, 12, 12, same);
        if (HasFatalFailure()) return;
    }
    EXPECT_GT(differing, 10);
}

// Four wedges in a pinwheel, each tip (near) lying over the next one's base (far): no order
// of the four is right.
std::vector<DepthTriangle> pinwheel() {
    const double near = 0.125;
    const double far = 0.875;
    return {
        {{{{0, 2}, {0, 9}, {14, 5.5}}}, {far, far, near}},
        {{{{9, 0}, {16, 0}, {12.5, 14}}}, {far, far, near}},
        {{{{16, 7}, {16, 14}, {2, 10.5}}}, {far, far, near}},
        {{{{0, 16}, {7, 16}, {3.5, 2}}}, {far, far, near}},
    };
}

TEST(TextbookPainter, ACyclicOverlapDiffersAtThePixelAndTrianglesTheOracleNames) {
    const auto tris = pinwheel();
    expect_matches_oracle(tris, PainterKey::FarthestVertex, 16, 16, false);
    expect_matches_oracle(tris, PainterKey::MeanDepth, 16, 16, false);
    const auto d = refraster::textbook::first_difference(
        refraster::textbook::painter(tris, PainterKey::FarthestVertex, 16, 16),
        refraster::textbook::z_buffer(tris, 16, 16));
    ASSERT_TRUE(d.has_value());
    EXPECT_NE(d->painter_triangle, d->z_buffer_triangle);
    EXPECT_GE(d->painter_triangle, 0);
    EXPECT_GE(d->z_buffer_triangle, 0);
    // The overlap is cyclic: every one of the 24 drawing orders disagrees with the z-buffer
    // somewhere.
    const Oracle o = oracle(tris, PainterKey::FarthestVertex, 16, 16);
    std::vector<int> order = {0, 1, 2, 3};
    do {
        bool differs = false;
        for (int i = 0; i < 256 && !differs; ++i) {
            int painted = -1;
            for (const int t : order) {
                if (oracle_covers(tris[static_cast<std::size_t>(t)], i % 16, i / 16)) painted = t;
            }
            differs = painted != o.z_buffer[static_cast<std::size_t>(i)];
        }
        EXPECT_TRUE(differs) << order[0] << order[1] << order[2] << order[3];
    } while (std::next_permutation(order.begin(), order.end()));
}

TEST(TextbookPainter, InterpenetratingTrianglesDifferOnTheSideTheSortGetsWrong) {
    // T0 tilts from near on the left to far on the right through T1's constant depth: the
    // sort draws T0 first (its farthest vertex is farther), so T1 wrongly covers T0's near
    // left half.
    const std::vector<DepthTriangle> tris = {
        {{{{0, 0}, {16, 0}, {8, 16}}}, {0.25, 0.75, 0.5}},
        {{{{0, 1}, {16, 1}, {8, 15}}}, {0.5, 0.5, 0.5}},
    };
    expect_matches_oracle(tris, PainterKey::FarthestVertex, 16, 16, false);
    const auto d = refraster::textbook::first_difference(
        refraster::textbook::painter(tris, PainterKey::FarthestVertex, 16, 16),
        refraster::textbook::z_buffer(tris, 16, 16));
    ASSERT_TRUE(d.has_value());
    EXPECT_EQ(d->painter_triangle, 1);
    EXPECT_EQ(d->z_buffer_triangle, 0);
    EXPECT_EQ(d->y, 1);
    EXPECT_LT(d->x, 8);
}

TEST(TextbookPainter, TraceHasTheSortAndOneStepPerTriangle) {
    refraster::textbook::Trace trace;
    const auto tris = pinwheel();
    refraster::textbook::painter(tris, PainterKey::FarthestVertex, 16, 16, &trace);
    ASSERT_EQ(trace.steps.size(), 1 + tris.size());
    EXPECT_EQ(trace.steps[0].state[0].second, "[T0, T1, T2, T3]");
    refraster::textbook::Trace zt;
    refraster::textbook::z_buffer(tris, 16, 16, &zt);
    EXPECT_EQ(zt.steps.size(), tris.size());
}

}  // namespace
