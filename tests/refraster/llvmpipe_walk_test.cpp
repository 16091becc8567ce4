// llvmpipe's own planes, binning and tile walk (llvmpipe_walk.hpp): within the 24.8 budget
// its tests decide exactly what the edge functions decide, so on triangles that do not wrap
// the walk must cover the pixels of the plain per-pixel test, no more, no fewer, each once.
// Beyond the budget, positions convert to 0x80000000 and the triangle is walked, not refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "models/llvmpipe/setup.hpp"
#include "models/llvmpipe/traverse.hpp"

namespace {

using refraster::detail::SetupOutcome;
using refraster::detail::SetupParams;
using refraster::detail::TriangleSetup;

constexpr int kW = 300;  // not a multiple of the 64-pixel tile
constexpr int kH = 200;

std::vector<std::uint8_t> walked(const TriangleSetup& t) {
    std::vector<std::uint8_t> m(static_cast<std::size_t>(kW) * kH, 0);
    refraster::detail::traverse_triangle(t, [&](int y, int x0, int x1) {
        for (int x = x0; x < x1; ++x)
            ++m[static_cast<std::size_t>(y) * kW + static_cast<std::size_t>(x)];
    });
    return m;
}

std::vector<std::uint8_t> plain(const TriangleSetup& t) {
    std::vector<std::uint8_t> m(static_cast<std::size_t>(kW) * kH, 0);
    for (int y = t.bbox.y0; y <= t.bbox.y1; ++y) {
        for (int x = t.bbox.x0; x <= t.bbox.x1; ++x) {
            if (refraster::detail::covers_pixel(t, x, y))
                m[static_cast<std::size_t>(y) * kW + static_cast<std::size_t>(x)] = 1;
        }
    }
    return m;
}

SetupParams params() {
    SetupParams p;
    p.framebuffer = {0, 0, kW - 1, kH - 1};
    p.draw_region = p.framebuffer;
    return p;
}

TEST(LlvmpipeWalk, EqualsPerPixelTestOnTrianglesThatDoNotWrap) {
    std::mt19937 rng(20261201);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::uniform_int_distribution<int> coin(0, 3);
    int compared = 0;
    int multi_tile = 0;
    int with_region_planes = 0;
    for (int n = 0; compared < 20000; ++n) {
        SetupParams p = params();
        p.tie_rule = static_cast<refraster::TieRule>(coin(rng));
        if (n % 4 == 0) {  // a scissor: region planes on the sides the box reaches past
            const int x0 = static_cast<int>(unit(rng) * kW), y0 = static_cast<int>(unit(rng) * kH);
            p.draw_region = refraster::detail::intersect(
                p.draw_region, {x0, y0, x0 + static_cast<int>(unit(rng) * kW),
                                y0 + static_cast<int>(unit(rng) * kH)});
        }
        // From a pixel to far beyond the target, a third with vertices on pixel centres.
        const float size = std::exp2(unit(rng) * 11.0f);
        const float cx = unit(rng) * kW;
        const float cy = unit(rng) * kH;
        std::array<std::array<float, 2>, 3> v;
        for (auto& q : v) {
            q = {cx + (unit(rng) - 0.5f) * size, cy + (unit(rng) - 0.5f) * size};
            if (n % 3 == 0) q = {std::floor(q[0]) + 0.5f, std::floor(q[1]) + 0.5f};
        }
        TriangleSetup t;
        if (refraster::detail::setup_triangle(v, p, t) != SetupOutcome::Ok || t.llvmpipe_walk)
            continue;
        const auto expected = plain(t);
        refraster::detail::attach_llvmpipe_walk(p, t);
        ASSERT_TRUE(t.llvmpipe_walk);
        ++compared;
        multi_tile += ((t.walk.box.x0 ^ t.walk.box.x1) | (t.walk.box.y0 ^ t.walk.box.y1)) >= 64;
        with_region_planes += t.walk.count > 3;
        ASSERT_EQ(walked(t), expected)
            << "triangle " << n << ": (" << v[0][0] << "," << v[0][1] << ") (" << v[1][0] << ","
            << v[1][1] << ") (" << v[2][0] << "," << v[2][1] << ")";
    }
    // Both binning paths and the draw-region planes took part.
    EXPECT_GT(multi_tile, 5000);
    EXPECT_GT(compared - multi_tile, 5000);
    EXPECT_GT(with_region_planes, 5000);
}

// A vertex at infinity (the clipper's vertex of w = 0) converts to 0x80000000 in both
// coordinates; with wrapping arithmetic the triangle is set up and walked, without it refused.
TEST(LlvmpipeWalk, NonFinitePositionsConvertToTheIntegerIndefinite) {
    const float inf = std::numeric_limits<float>::infinity();
    const std::array<std::array<float, 2>, 3> v{{{32.0f, 32.0f}, {inf, inf}, {11.25f, 41.5f}}};
    SetupParams p = params();
    TriangleSetup t;
    ASSERT_EQ(refraster::detail::setup_triangle(v, p, t), SetupOutcome::Ok);
    EXPECT_TRUE(t.llvmpipe_walk);
    EXPECT_EQ(t.x[0] == INT32_MIN || t.x[1] == INT32_MIN || t.x[2] == INT32_MIN, true);
    // do_triangle_ccw's box: the minimum is 0x80000000 >> 8, clamped to 0 before binning.
    EXPECT_EQ(t.walk.box.x0, 0);
    EXPECT_EQ(t.walk.box.y0, 0);
    // A NaN coordinate converts the same way.
    const std::array<std::array<float, 2>, 3> vn{
        {{32.0f, 32.0f}, {std::nanf(""), 5.0f}, {11.25f, 41.5f}}};
    TriangleSetup tn;
    const auto outcome = refraster::detail::setup_triangle(vn, p, tn);
    EXPECT_TRUE(outcome != SetupOutcome::OutOfRange);
    EXPECT_TRUE(tn.x[0] == INT32_MIN || tn.x[1] == INT32_MIN || tn.x[2] == INT32_MIN);

    p.wrapping = false;
    TriangleSetup refused;
    EXPECT_EQ(refraster::detail::setup_triangle(v, p, refused), SetupOutcome::OutOfRange);
}

// The planes of do_triangle_ccw's SSE branch: the delta shifted by FIXED_ORDER wraps in int32,
// and eo takes the shifted values under the signs of the unshifted ones.
TEST(LlvmpipeWalk, EdgePlaneWrapsLikeThe32BitLanes) {
    namespace lp = refraster::detail::lp;
    // dcdx = 0 - (1 << 24) = -2^24, shifted: -2^32 wraps to 0; dcdy = 2^23, shifted: 2^31 wraps to
    // INT32_MIN.
    const lp::Plane e = lp::edge_plane(1 << 23, 0, 0, 1 << 24, false);
    EXPECT_EQ(e.dcdx, 0);
    EXPECT_EQ(e.dcdy, INT32_MIN);
    // eo = (dcdy >= 0 ? INT32_MIN : 0) - (dcdx < 0 ? 0 : 0) = 0x80000000 as uint32.
    EXPECT_EQ(e.eo, 0x80000000u);
    // c = dcdx * x_i - dcdy * y_i in int64: -2^24 * 2^23 - 2^23 * 0.
    EXPECT_EQ(e.c, -(std::int64_t{1} << 47));
}

}  // namespace
