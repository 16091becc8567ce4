// edge_rules.hpp: GL's coverage rule in integers: snapped positions, edge functions and the
// tie rule, with the bit budget that keeps them exact.
//
// Implements, as every snapped model shares them (llvmpipe's lp_setup_tri.c states the same
// arithmetic): the draw's setup parameters from the profile and state (sub-pixel bits,
// rounding, pixel centre, tie rule, cull and front face, the draw region), snapping
// X = round((x - pixel_center_offset) * 2^bits) with the subtraction and the multiplication in
// float (calc_fixed_position; cvtps2dq rounds to nearest even), and the edge function
// E(px, py) = c - a*(px << bits) + b*(py << bits), a = Y_i - Y_j, b = X_i - X_j,
// c = a*X_i - b*Y_i plus 1 when the tie rule owns the edge, so that a pixel is covered iff
// E > 0 on every edge.
//
// Deliberately does not: orient, cull or bound a triangle, or walk llvmpipe's tiles (each
// model's setup does: models/llvmpipe/setup.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "common/float_ops.hpp"
#include "common/pixel_rect.hpp"
#include "refraster/draw.hpp"
#include "refraster/fixed.hpp"
#include "refraster/profile.hpp"

namespace refraster::detail {

// Bit budget of the snapped path. Window coordinates stay below 2^16 in magnitude (viewport
// origin in [-32768, 32767] plus a width of at most 16384, and the clipper keeps vertices
// inside the viewport up to float rounding), so with at most 8 subpixel bits:
//   snapped coordinates      |X|      < 2^24
//   edge deltas a, b         |a|,|b|  < 2^25
//   edge constants c         |c|      < 2^25 * 2^24 * 2 = 2^50
//   edge value at a pixel    |E|      < 2^50 + 2 * 2^25 * 2^(14+8) = 2^51 (framebuffer < 2^14)
inline constexpr int kMaxSubpixelBits = 8;
inline constexpr int kWindowCoordinateBits = 16;
inline constexpr int kSnappedBits = kWindowCoordinateBits + kMaxSubpixelBits;  // 24
inline constexpr int kEdgeDeltaBits = kSnappedBits + 1;                        // 25
inline constexpr int kEdgeConstantBits = kEdgeDeltaBits + kSnappedBits + 1;    // 50
inline constexpr int kFramebufferBits = 14;                                    // 16384
inline constexpr int kEdgeValueBits = kEdgeConstantBits + 1;                   // 51
static_assert(kSnappedBits < 31, "snapped coordinates must fit int32 (llvmpipe's 24.8)");
static_assert(kEdgeDeltaBits < 31, "edge deltas must fit int32");
static_assert(kEdgeDeltaBits + kFramebufferBits + kMaxSubpixelBits + 1 <= kEdgeConstantBits,
              "stepping across the framebuffer must stay within the constant's budget");
static_assert(kEdgeValueBits < 63, "edge values must fit int64");

using Subpixel = Fixed<kMaxSubpixelBits, std::int32_t>;

struct EdgeFunction {
    std::int32_t a = 0;  // dE/dpx = -a << bits
    std::int32_t b = 0;  // dE/dpy = +b << bits
    std::int64_t c = 0;  // includes the tie bias
    bool owns_ties = false;

    // E at the pixel (px, py); the pixel centre is the origin of the snapped grid (its
    // bottom-left corner when multisampling).
    std::int64_t at(int px, int py, int bits) const {
        const std::int64_t one = std::int64_t{1} << bits;
        return checked_add(checked_sub(c, checked_mul(wide_mul(a, px), one)),
                           checked_mul(wide_mul(b, py), one));
    }
    // What a sample at (sx, sy) subpixels from the pixel's origin adds to at(px, py): the
    // multisample rasterizer's (sy * dcdy - sx * dcdx) >> FIXED_ORDER, exact because dcdx and
    // dcdy are pre-shifted (lp_rast_tri_tmp.h, MULTISAMPLE).
    std::int64_t sample_offset(std::int32_t sx, std::int32_t sy) const {
        return checked_sub(wide_mul(b, sy), wide_mul(a, sx));
    }
};

struct SetupParams {
    int bits = 8;
    SnapRounding rounding = SnapRounding::NearestEven;
    float pixel_center_offset = 0.5f;
    // The profile's pixel centre offset even when multisampling zeroes the one above
    // (llvmpipe's setup->pixel_offset, from half_pixel_center alone).
    float half_pixel_center = 0.5f;
    TieRule tie_rule = TieRule::LeftBottom;
    CullMode cull = CullMode::None;
    bool front_ccw = false;  // gallium's rasterizer front_ccw (FBO: flipped from GL)
    bool provoking_first = false;
    PixelRect draw_region;  // framebuffer, intersected with the scissor
    PixelRect framebuffer;
    // Profile.wrapping_arithmetic: reproduce llvmpipe's conversion of out-of-range
    // positions and its 32-bit wrapping (llvmpipe_walk.hpp) instead of refusing them.
    bool wrapping = true;
    // A 4x target drawn with GL_MULTISAMPLE on: positions snap without the half-pixel offset
    // (pixel_center_offset is 0) and coverage is tested at each sample (samples.hpp).
    bool multisample = false;
};

// The profile's subpixel bits must be at most kMaxSubpixelBits and the target at most
// 2^kFramebufferBits pixels a side: the bit budget above rests on both.
SetupParams setup_params(const Profile& profile, const DrawState& state, const Target& target);

// Whether the tie rule gives an edge the pixel centres lying exactly on it (see setup.cpp).
bool owns_ties(std::int32_t a, std::int32_t b, TieRule rule);

// The edge function of the snapped edge (xi, yi) -> (xj, yj), tie bias included; the
// interior of a polygon oriented as set-up triangles are is where it is positive. Inline: a
// line or point makes four, and a call would return each through memory.
inline EdgeFunction make_edge(std::int32_t xi, std::int32_t yi, std::int32_t xj, std::int32_t yj,
                              TieRule rule) {
    EdgeFunction e;
    e.a = checked_sub(yi, yj);
    e.b = checked_sub(xi, xj);
    e.owns_ties = owns_ties(e.a, e.b, rule);
    e.c = checked_add(checked_sub(wide_mul(e.a, xi), wide_mul(e.b, yi)),
                      std::int64_t{e.owns_ties ? 1 : 0});
    return e;
}

// One window position snapped as setup_triangle snaps a vertex (calc_fixed_position): the
// pixel centre of (px, py) is (px << bits, py << bits). nullopt for a position outside the
// budget above (setup then takes llvmpipe's own walk).
std::optional<std::array<std::int32_t, 2>> snap_position(float x, float y, const SetupParams& p);

inline constexpr std::int32_t kIndefinite =
    INT32_MIN;  // cvtps2dq of NaN or of a value outside int32

// A window coordinate snapped to the sub-pixel grid as calc_fixed_position's cvtps2dq does it;
// `beyond` is set when the result leaves the 24.8 budget above (kSnappedBits).
[[gnu::always_inline]] inline std::int32_t snap_to_subpixel(float v, const SetupParams& p,
                                                            bool& beyond) {
    const float scaled = (v - p.pixel_center_offset) * static_cast<float>(1 << p.bits);
    if (p.rounding == SnapRounding::NearestEven) {
        // INT32_MIN (kIndefinite) for a value that does not fit, as the instruction gives it;
        // it lies outside the budget too.
        const std::int32_t r = round_nearest_even_or_indefinite(scaled);
        if (r <= -(1 << kSnappedBits) || r >= (1 << kSnappedBits)) beyond = true;
        return r;
    }
    const auto r = round_scaled<std::int32_t>(scaled, p.rounding);
    if (!r) {
        beyond = true;
        return kIndefinite;
    }
    if (*r <= -(1 << kSnappedBits) || *r >= (1 << kSnappedBits)) beyond = true;
    return *r;
}

}  // namespace refraster::detail
