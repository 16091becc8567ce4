// Line setup at its ends (line_point.cpp, setup_line; docs/precision.md "Lines"): which pixels
// a width-1 line lights at its first and last vertex, and the snapped corners of its
// parallelogram. GL's diamond-exit rule (OpenGL 4.6, 14.5.1) lights a pixel when the segment
// leaves the pixel's diamond |x - xc| + |y - yc| < 1/2, so a line that starts inside a diamond
// lights that pixel and one that ends inside a diamond does not; llvmpipe's try_setup_line
// moves an end half a pixel along the major axis where its parallelogram would decide
// otherwise. Every expected value below is derived by hand from that rule; positions are
// binary fractions, so no float rounding enters.
#include "models/llvmpipe/line_point.hpp"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "models/llvmpipe/setup_list.hpp"
#include "models/llvmpipe/traverse.hpp"
#include "stages/vertex_stage.hpp"

namespace {

using refraster::detail::LineSetup;
using refraster::detail::PixelRect;
using refraster::detail::SetupParams;
using refraster::detail::StageVertex;

// llvmpipe's parameters: 8 subpixel bits, centres at .5, the left-bottom tie rule, a 64x64
// target without scissor.
SetupParams params() {
    SetupParams p;
    p.draw_region = {0, 0, 63, 63};
    p.framebuffer = p.draw_region;
    return p;
}

StageVertex at(float x, float y) {
    StageVertex v;
    v.window = {x, y, 0.0f, 1.0f};
    return v;
}

LineSetup line(std::array<float, 2> a, std::array<float, 2> b) {
    const auto l = refraster::detail::setup_line(at(a[0], a[1]), at(b[0], b[1]), 1.0f, params());
    EXPECT_TRUE(l.has_value());
    return l.value_or(LineSetup{});
}

// The pixels traversal finds covered, as (x, y).
std::set<std::pair<int, int>> lit(const LineSetup& l) {
    std::set<std::pair<int, int>> out;
    refraster::detail::traverse_convex(l, [&](int y, int x0, int x1) {
        for (int x = x0; x < x1; ++x) out.insert({x, y});
    });
    return out;
}

std::set<std::pair<int, int>> row(int y, int x0, int x1) {
    std::set<std::pair<int, int>> out;
    for (int x = x0; x <= x1; ++x) out.insert({x, y});
    return out;
}

std::set<std::pair<int, int>> column(int x, int y0, int y1) {
    std::set<std::pair<int, int>> out;
    for (int y = y0; y <= y1; ++y) out.insert({x, y});
    return out;
}

TEST(LineEnds, StartInsideADiamondLightsItsPixelEndInsideADiamondDoesNot) {
    // From (2.75, 10.5) to (6.75, 10.5), rightwards: the start lies 0.25 right of the centre of
    // pixel (2, 10), inside its diamond, so (2, 10) is lit although its centre lies behind the
    // start; the end lies 0.25 right of the centre of (6, 10), inside its diamond, so (6, 10)
    // is not lit although its centre lies before the end. The parallelogram alone would light
    // columns 3 to 6.
    const LineSetup l = line({2.75f, 10.5f}, {6.75f, 10.5f});
    EXPECT_TRUE(l.x_major);
    EXPECT_EQ(lit(l), row(10, 2, 5));
    // The ends, swapped so that the line runs leftwards from its last vertex, each moved to the
    // left border of its pixel (start to 2.0, end to 6.0), minus the centre offset, times 256;
    // y = (10.5 - 0.5) * 256 = 2560, plus and minus half the width (128).
    EXPECT_EQ(l.x, (std::array<std::int32_t, 4>{1408, 384, 384, 1408}));
    EXPECT_EQ(l.y, (std::array<std::int32_t, 4>{2432, 2432, 2688, 2688}));
    // The box: minimum rounded up, one below the rounded-up maximum: x from ceil(1.5) = 2 to
    // ceil(5.5) - 1 = 5, y from ceil(9.5) = 10 to ceil(10.5) - 1 = 10.
    EXPECT_EQ(l.bbox, (PixelRect{2, 10, 5, 10}));
}

TEST(LineEnds, TheSameSegmentReversedLightsTheOtherEnd) {
    // From (6.75, 10.5) to (2.75, 10.5), leftwards: now the start is inside the diamond of
    // (6, 10), which is lit, and the end inside that of (2, 10), which is not. Here the
    // parallelogram already agrees, so neither end moves: x from (6.75 - 0.5) * 256 = 1600 to
    // (2.75 - 0.5) * 256 = 576.
    const LineSetup l = line({6.75f, 10.5f}, {2.75f, 10.5f});
    EXPECT_EQ(lit(l), row(10, 3, 6));
    EXPECT_EQ(l.x, (std::array<std::int32_t, 4>{1600, 576, 576, 1600}));
    EXPECT_EQ(l.bbox, (PixelRect{3, 10, 6, 10}));
}

TEST(LineEnds, YMajorEndsFollowTheSameRule) {
    // From (10.5, 2.75) to (10.5, 6.75), upwards: the mirror of the first case in y. (10, 2)
    // is lit, (10, 6) is not; both ends move to the bottom border of their pixel (2.0, 6.0).
    const LineSetup l = line({10.5f, 2.75f}, {10.5f, 6.75f});
    EXPECT_FALSE(l.x_major);
    EXPECT_EQ(lit(l), column(10, 2, 5));
    EXPECT_EQ(l.x, (std::array<std::int32_t, 4>{2432, 2432, 2688, 2688}));
    EXPECT_EQ(l.y, (std::array<std::int32_t, 4>{384, 1408, 1408, 384}));
    EXPECT_EQ(l.bbox, (PixelRect{10, 2, 10, 5}));
}

TEST(LineEnds, StartOutsideTheDiamondBehindItsCentreLightsNothingThere) {
    // From (2.75, 10.875) to (6.25, 10.875), rightwards: the start is 0.25 + 0.375 = 0.625 from
    // the centre of (2, 10), outside its diamond, and past the diamond's extent at y = 10.875
    // (x in (2.375, 2.625)), so (2, 10) is not lit; the end is outside the diamond of (6, 10)
    // and before its extent (6.375, 6.625), so (6, 10) is not lit either. Columns 3 to 5; row 10
    // only (row 11's diamonds lie above y = 11). No end moves.
    const LineSetup l = line({2.75f, 10.875f}, {6.25f, 10.875f});
    EXPECT_EQ(lit(l), row(10, 3, 5));
    EXPECT_EQ(l.x, (std::array<std::int32_t, 4>{1472, 576, 576, 1472}));
    EXPECT_EQ(l.y, (std::array<std::int32_t, 4>{2528, 2528, 2784, 2784}));
}

TEST(LineEnds, AnEndOnTheBorderBelowAPixelRisingKeepsItsPlace) {
    // llvmpipe's quirk (docs/precision.md "Lines"): for an x-major line with dy < 0 (v1.y below
    // v2.y: rising) whose end lies exactly on a pixel's lower border (y2diff = -0.5), the end
    // test runs as if it lay on the upper border. From (2.5, 10.5) to (6.5, 11.0): the end tests
    // then say "draw the end" where the plain test says "do not", and the parallelogram, which
    // reaches the end's centre column, is left as it is: the end stays at x = 6.5, snapped
    // (6.5 - 0.5) * 256 = 1536, y (11 - 0.5) * 256 = 2688. Without the quirk the end would move
    // half a pixel back along the line, to x = 6.0 (1408) and y = 11 - 0.5 / 8 (2672).
    const LineSetup l = line({2.5f, 10.5f}, {6.5f, 11.0f});
    EXPECT_TRUE(l.x_major);
    EXPECT_EQ(l.x, (std::array<std::int32_t, 4>{1536, 512, 512, 1536}));
    EXPECT_EQ(l.y, (std::array<std::int32_t, 4>{2560, 2432, 2688, 2816}));
    // Coverage: the start (2, 10) is lit (inside its diamond); the parallelogram's right edge
    // runs through the centre of (6, 10), which the left-bottom rule leaves out. The segment
    // touches the diamonds of column 6 only at its end, on their border, so GL lights nothing
    // there either.
    EXPECT_EQ(lit(l), row(10, 2, 5));
}

}  // namespace

// Line attribute planes (line_point.cpp, line_planes; setup_line_coefficients and linear_coef
// in lp_setup_line.c): each plane equals linear_coef's operations on its attribute, in their
// order, each result flushed to the zero of its sign when it is denormal, as written out
// below one operation at a time. The values reach down to FLT_MIN and below, so that
// differences, gradients and A0 land among the denormals.
namespace {

using refraster::detail::FragmentOptions;
using refraster::detail::Plane;
using refraster::detail::SetupList;
using refraster::detail::SetupPrimitive;

float flushed(float v) {
    return std::fabs(v) < std::numeric_limits<float>::min() ? std::copysign(0.0f, v) : v;
}

struct Terms {
    float x0c, y0c, info_dx, info_dy, oneoverarea;
};

Terms terms(const StageVertex& a, const StageVertex& b) {
    const float dx = flushed(a.window[0] - b.window[0]);
    const float dy = flushed(a.window[1] - b.window[1]);
    const float area = flushed(flushed(dx * dx) + flushed(dy * dy));
    Terms t{flushed(a.window[0] - 0.5f), flushed(a.window[1] - 0.5f), dx, dy, flushed(1.0f / area)};
    if (std::fabs(dx) >= std::fabs(dy)) {
        const float dydx = flushed(dy / dx);
        t.info_dx = flushed(dx * flushed(1.0f + flushed(dydx * dydx)));
        t.info_dy = 0.0f;
    } else {
        const float dxdy = flushed(dx / dy);
        t.info_dx = 0.0f;
        t.info_dy = flushed(dy * flushed(1.0f + flushed(dxdy * dxdy)));
    }
    return t;
}

Plane expected_plane(const Terms& t, float a1, float a2) {
    const float da21 = flushed(a1 - a2);
    Plane p;
    p.dadx = flushed(flushed(da21 * t.info_dx) * t.oneoverarea);
    p.dady = flushed(flushed(da21 * t.info_dy) * t.oneoverarea);
    p.a0 = flushed(a1 - flushed(flushed(p.dadx * t.x0c) + flushed(p.dady * t.y0c)));
    return p;
}

bool same_bits(const Plane& a, const Plane& b) {
    return std::bit_cast<std::uint32_t>(a.a0) == std::bit_cast<std::uint32_t>(b.a0) &&
           std::bit_cast<std::uint32_t>(a.dadx) == std::bit_cast<std::uint32_t>(b.dadx) &&
           std::bit_cast<std::uint32_t>(a.dady) == std::bit_cast<std::uint32_t>(b.dady);
}

}  // namespace

TEST(LinePlanes, EachPlaneIsLinearCoefFlushedOperationByOperation) {
    // Attributes as they are (noperspective) and times 1 / w (smooth), 4 to 21 floats: one
    // vector of them, several, and a part of one.
    std::mt19937 rng(11);
    const auto value = [&] {
        const float scale = std::array{1.0f, 1e-36f, 1e-38f, 3e-39f}[rng() % 4];
        return scale * std::uniform_real_distribution<float>(-2.0f, 2.0f)(rng);
    };
    int flushed_terms = 0;
    for (int trial = 0; trial < 400; ++trial) {
        refraster::Draw draw;
        draw.primitive = refraster::PrimitiveType::Lines;
        draw.state.shade =
            trial % 2 == 0 ? refraster::ShadeModel::NoPerspective : refraster::ShadeModel::Smooth;
        const auto floats = static_cast<std::uint32_t>(4 + trial % 18);
        draw.vertices.attributes = {{"color", floats}};
        for (int v = 0; v < 2; ++v) {
            for (float c : {0.0f, 0.0f, 0.0f, 1.0f}) draw.vertices.data.push_back(c);
            for (std::uint32_t k = 0; k < floats; ++k) draw.vertices.data.push_back(value());
        }
        refraster::detail::VertexStage stage(draw, {});
        std::uniform_real_distribution<float> pos(0.0f, 64.0f);
        std::array<StageVertex, 2> ends;
        for (std::uint32_t v = 0; v < 2; ++v) {
            ends[v].window = {pos(rng), pos(rng), value(), 1.0f / (0.5f + pos(rng))};
            ends[v].attributes = v * (4 + floats) + 4;
        }
        if (ends[0].window[0] == ends[1].window[0] && ends[0].window[1] == ends[1].window[1])
            continue;
        SetupList list;
        list.attribute_floats = floats;
        SetupPrimitive prim;
        FragmentOptions options;
        refraster::detail::line_planes(ends[0], ends[1], stage, draw, false, options, list, prim);
        ASSERT_EQ(list.planes.size(), prim.planes + 2 + floats);
        const Terms t = terms(ends[0], ends[1]);
        const auto& a = ends[0].window;
        const auto& b = ends[1].window;
        std::vector<Plane> want{expected_plane(t, a[2], b[2]), expected_plane(t, a[3], b[3])};
        for (std::uint32_t k = 0; k < floats; ++k) {
            const float c1 = draw.vertices.data[ends[0].attributes + k];
            const float c2 = draw.vertices.data[ends[1].attributes + k];
            if (draw.state.shade == refraster::ShadeModel::Smooth) {
                want.push_back(expected_plane(t, flushed(c1 * a[3]), flushed(c2 * b[3])));
            } else {
                want.push_back(expected_plane(t, c1, c2));
            }
            if (std::fabs(c1) < std::numeric_limits<float>::min() && c1 != 0.0f) ++flushed_terms;
        }
        for (std::size_t i = 0; i < want.size(); ++i) {
            const Plane& got = list.planes[prim.planes + i];
            EXPECT_TRUE(same_bits(got, want[i]))
                << "trial " << trial << ", plane " << i << ": got (" << got.a0 << ", " << got.dadx
                << ", " << got.dady << "), want (" << want[i].a0 << ", " << want[i].dadx << ", "
                << want[i].dady << ")";
        }
    }
    EXPECT_GT(flushed_terms, 100);  // the flush was exercised
}
