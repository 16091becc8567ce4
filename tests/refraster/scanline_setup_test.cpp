// softpipe's scanline triangle setup (refraster/src/models/softpipe/scanline_setup.cpp) against
// coverage derived by hand from its rule: a pixel centre (x + 0.5, y + 0.5) is covered when it lies
// inside the triangle, or on a right or bottom edge (gallium y = GL y, an FBO), never on a left or
// top one.
#include "models/softpipe/scanline_setup.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>

namespace {

using refraster::CullMode;
using refraster::detail::PixelRect;
using refraster::detail::ScanlineOutcome;
using refraster::detail::ScanlineTriangle;
using Pixels = std::set<std::pair<int, int>>;

Pixels covered(const std::array<std::array<float, 2>, 3>& v, PixelRect region = {0, 0, 63, 63}) {
    ScanlineTriangle t;
    const auto r = refraster::detail::setup_scanline_triangle(v, CullMode::None, false, region, t);
    EXPECT_EQ(r, ScanlineOutcome::Ok);
    Pixels out;
    for (const auto& row : t.rows) {
        for (int x = row.x0; x < row.x1; ++x) {
            EXPECT_TRUE(out.insert({x, row.y}).second) << "pixel twice: " << x << ", " << row.y;
        }
    }
    return out;
}

TEST(ScanlineSetup, CentresOnLeftAndTopEdgesAreOutsideOnRightAndBottomInside) {
    // (2.5, 2.5), (6.5, 2.5), (2.5, 6.5): the bottom edge runs through row 2's centres (inside),
    // the left edge through column 2's (outside), the long edge x + y = 9 through the centres
    // with x + y = 8 (a right edge: inside); the top vertex's row 6 centre lies at 6.5 (the top,
    // outside).
    Pixels want;
    for (int y = 2; y <= 5; ++y)
        for (int x = 3; x + y <= 8; ++x) want.insert({x, y});
    EXPECT_EQ(covered({{{2.5f, 2.5f}, {6.5f, 2.5f}, {2.5f, 6.5f}}}), want);
    // The same triangle in the other winding and vertex order covers the same pixels.
    EXPECT_EQ(covered({{{6.5f, 2.5f}, {2.5f, 2.5f}, {2.5f, 6.5f}}}), want);
    EXPECT_EQ(covered({{{2.5f, 6.5f}, {6.5f, 2.5f}, {2.5f, 2.5f}}}), want);
}

TEST(ScanlineSetup, NoSnappingAHairAwayFromACentreDecides) {
    // A vertical left edge at x = 3.5 - 2^-11: column 3's centres are just inside. llvmpipe's
    // 1/256 snap would put the edge on them (and its left-edge rule would take them too), so
    // use the right edge: at x = 6.5 + 2^-11 column 6 is inside, at 6.5 - 2^-11 outside.
    const float e = 1.0f / 2048.0f;
    const auto with_right = [&](float x) {
        return covered({{{1.0f, 1.0f}, {x, 1.0f}, {x, 9.0f}}});
    };
    const Pixels in = with_right(6.5f + e);
    const Pixels out = with_right(6.5f - e);
    EXPECT_EQ(in.count({6, 4}), 1u);
    EXPECT_EQ(out.count({6, 4}), 0u);
    EXPECT_EQ(with_right(6.5f).count({6, 4}), 1u);  // exactly on a right edge: inside
}

TEST(ScanlineSetup, EveryCentreStrictlyInsideIsCoveredAndNoOther) {
    // Random triangles away from ties: a centre is covered iff it is strictly inside (the
    // three edge functions, in double, agree in sign); centres within 1e-3 of an edge are
    // skipped.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 40.0f);
    int checked = 0;
    for (int n = 0; n < 500; ++n) {
        const std::array<std::array<float, 2>, 3> v{
            {{u(rng), u(rng)}, {u(rng), u(rng)}, {u(rng), u(rng)}}};
        ScanlineTriangle t;
        if (refraster::detail::setup_scanline_triangle(v, CullMode::None, false, {0, 0, 63, 63},
                                                       t) != ScanlineOutcome::Ok)
            continue;
        Pixels got;
        for (const auto& row : t.rows)
            for (int x = row.x0; x < row.x1; ++x) got.insert({x, row.y});
        for (int y = 0; y < 41; ++y) {
            for (int x = 0; x < 41; ++x) {
                const double px = x + 0.5, py = y + 0.5;
                double s[3];
                double len[3];
                for (int i = 0; i < 3; ++i) {
                    const auto& a = v[static_cast<std::size_t>(i)];
                    const auto& b = v[static_cast<std::size_t>((i + 1) % 3)];
                    const double ax = a[0], ay = a[1];
                    const double dx = double{b[0]} - ax, dy = double{b[1]} - ay;
                    s[i] = dx * (py - ay) - dy * (px - ax);
                    len[i] = std::hypot(dx, dy);
                }
                bool near = false;
                for (int i = 0; i < 3; ++i) near = near || std::fabs(s[i]) < 1e-3 * len[i];
                if (near) continue;
                const bool inside =
                    (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
                EXPECT_EQ(got.count({x, y}) == 1, inside)
                    << "triangle " << n << " pixel " << x << ", " << y;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 100000);
}

TEST(ScanlineSetup, RegionClipsRowsAndColumnsAndFacingCulls) {
    const std::array<std::array<float, 2>, 3> v{{{0.0f, 0.0f}, {20.0f, 0.0f}, {0.0f, 20.0f}}};
    for (const auto& p : covered(v, {4, 5, 9, 7})) {
        EXPECT_GE(p.first, 4);
        EXPECT_LE(p.first, 9);
        EXPECT_GE(p.second, 5);
        EXPECT_LE(p.second, 7);
    }
    EXPECT_EQ(covered(v, {4, 5, 9, 7}).size(), 18u);  // 6 columns x 3 rows, all inside
    // Counter-clockwise in GL's y-up window space: det = ex*fy - ey*fx with e = v0 - v2 and
    // f = v1 - v2 is 400 > 0. In an FBO gallium's front_ccw is false for GL's default front
    // face (CCW): facing = (det < 0) ^ front_ccw = 0, the front face.
    ScanlineTriangle t;
    EXPECT_EQ(
        refraster::detail::setup_scanline_triangle(v, CullMode::Front, false, {0, 0, 63, 63}, t),
        ScanlineOutcome::Culled);
    EXPECT_EQ(t.det, 400.0f);
    EXPECT_EQ(
        refraster::detail::setup_scanline_triangle(v, CullMode::Back, false, {0, 0, 63, 63}, t),
        ScanlineOutcome::Ok);
    EXPECT_TRUE(t.front_facing);
    EXPECT_EQ(
        refraster::detail::setup_scanline_triangle(v, CullMode::Back, true, {0, 0, 63, 63}, t),
        ScanlineOutcome::Culled);
    // Three points on a line: 1/area is infinite.
    EXPECT_EQ(refraster::detail::setup_scanline_triangle({{{0, 0}, {1, 1}, {2, 2}}}, CullMode::None,
                                                         false, {0, 0, 63, 63}, t),
              ScanlineOutcome::Degenerate);
}

TEST(ScanlineSetup, PlanesReproduceALinearAttributeAtPixelCentresAQuadAtATime) {
    // f(x, y) = 2x + 3y + 1 at the vertices, all values exact in float: the plane has slopes
    // 2 and 3 (up to the rounding of 1/area: within 4 ulps), and at integer pixel (x, y) the value
    // f(x + 0.5, y + 0.5) (the half-pixel offset lives in a0); the quad's four values are its
    // pixels' in the order (x0, y0), (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1).
    const std::array<std::array<float, 2>, 3> v{{{4.0f, 2.0f}, {20.0f, 6.0f}, {8.0f, 18.0f}}};
    ScanlineTriangle t;
    ASSERT_EQ(
        refraster::detail::setup_scanline_triangle(v, CullMode::None, false, {0, 0, 63, 63}, t),
        ScanlineOutcome::Ok);
    const auto f = [](float x, float y) { return 2.0f * x + 3.0f * y + 1.0f; };
    const auto p = refraster::detail::scanline_plane(t, {f(4, 2), f(20, 6), f(8, 18)});
    EXPECT_FLOAT_EQ(p.dadx, 2.0f);
    EXPECT_FLOAT_EQ(p.dady, 3.0f);
    const auto q = refraster::detail::scanline_quad(p, 10, 6);
    EXPECT_NEAR(double{q[0]}, double{f(10.5f, 6.5f)}, 1e-4);
    EXPECT_NEAR(double{q[1]}, double{f(11.5f, 6.5f)}, 1e-4);
    EXPECT_NEAR(double{q[2]}, double{f(10.5f, 7.5f)}, 1e-4);
    EXPECT_NEAR(double{q[3]}, double{f(11.5f, 7.5f)}, 1e-4);
    // Perspective: the values times each vertex's 1/w (here 1/2 everywhere) before the plane.
    const auto pp = refraster::detail::scanline_persp_plane(t, {f(4, 2), f(20, 6), f(8, 18)},
                                                            {0.5f, 0.5f, 0.5f});
    EXPECT_FLOAT_EQ(pp.dadx, 1.0f);
    EXPECT_FLOAT_EQ(pp.dady, 1.5f);
}

}  // namespace
