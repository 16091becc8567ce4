// rules.hpp: the GL rules that more than one stage applies, each written once.
//
// Implements:
//  - depth quantisation: a window z in [0, 1] to the value a depth format stores, and the
//    minimum resolvable difference of a fixed-point format (OpenGL 4.6 compatibility, 2.3.5.2
//    and 14.6.5);
//  - the offset units of polygon offset: llvmpipe's and the draw module's (float)(units * 2 *
//    mrd) for fixed-point depth, and the scale of the units for z32f, llvmpipe's from the
//    float's bits and the specification's exact one;
//  - the cull decision: whether a polygon of a given facing is culled (14.6.1);
//  - which edges a tie rule owns: left or right, bottom or top (14.6.1);
//  - which x/y clip test a draw's vertices take: the view volume or the guard band (13.7,
//    the profile's clipping and point_line_clipping).
//
// Deliberately does not: decide facing, clamp depth, or fix the order of the float operations
// around these rules (which maximum is taken first, which product rounds): each caller keeps the
// order of the driver code it reproduces.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <type_traits>

#include "common/float_ops.hpp"
#include "refraster/draw.hpp"
#include "refraster/profile.hpp"

namespace refraster::detail {

// The largest value a fixed-point depth format stores, 2^n - 1; 0 for z32f and no depth.
constexpr std::uint32_t depth_unorm_max(DepthFormat f) {
    switch (f) {
        case DepthFormat::Z16:
            return 65535u;
        case DepthFormat::Z24:
            return 16777215u;
        case DepthFormat::Z32f:
        case DepthFormat::None:
            return 0;
    }
    return 0;
}

// A depth value in [0, 1] as format `f` stores it: z16 and z24 RNE(z * (2^n - 1)), the product
// rounded in `Real` first (OpenGL 4.6, 2.3.5.2; for fragments in float as
// lp_build_clamped_float_to_unsigned_norm computes it, for clears in double as util_pack_z does,
// for the exact oracle in double); z32f the bits of z rounded to float; 0 without depth.
template <std::floating_point Real>
[[gnu::always_inline]] inline std::uint32_t quantise_depth(Real z, DepthFormat f) {
    switch (f) {
        case DepthFormat::Z16:
        case DepthFormat::Z24:
            if constexpr (std::is_same_v<Real, float>) {
                return static_cast<std::uint32_t>(
                    round_to_nearest_even(z * static_cast<Real>(depth_unorm_max(f))));
            } else {
                return static_cast<std::uint32_t>(
                    std::nearbyint(z * static_cast<Real>(depth_unorm_max(f))));
            }
        case DepthFormat::Z32f:
            return std::bit_cast<std::uint32_t>(static_cast<float>(z));
        case DepthFormat::None:
            return 0;
    }
    return 0;
}

// The same with truncation instead of rounding (a profile's depth_rounding=truncate): z16 and
// z24 (uint)(fl(z * (2^n - 1))) of a z in [0, 1]; z32f and no depth as above.
inline std::uint32_t truncate_depth(float z, DepthFormat f) {
    if (f == DepthFormat::Z16 || f == DepthFormat::Z24)
        return static_cast<std::uint32_t>(z * static_cast<float>(depth_unorm_max(f)));
    return quantise_depth(z, f);
}

// The minimum resolvable difference r of a fixed-point depth format, 1 / (2^n - 1) (OpenGL 4.6,
// 14.6.5; util_get_depth_format_mrd); 0 for z32f and no depth.
constexpr double depth_mrd(DepthFormat f) {
    const std::uint32_t max = depth_unorm_max(f);
    return max == 0 ? 0.0 : 1.0 / static_cast<double>(max);
}

// The units term of polygon offset for fixed-point depth as Mesa computes it:
// (float)(units * mrd * 2) in double (lp_make_setup_variant_key for llvmpipe's own offset,
// draw_pipe_offset.c offset_first_tri for the draw module's), twice the specification's r.
inline float fixed_depth_offset_units(float units, DepthFormat f) {
    return static_cast<float>(static_cast<double>(units) * depth_mrd(f) * 2);
}

// The scale of the units of polygon offset for z32f as Mesa computes it (lp_do_offset_tri,
// draw_pipe_offset.c do_offset_tri): 2^(exponent(max |z_i|) - 23) built from the exponent bits
// of the float, clamped at 0, so that a zero or subnormal maximum gives 0.
inline float z32f_offset_scale(float max_abs_z) {
    std::int32_t bits =
        static_cast<std::int32_t>(std::bit_cast<std::uint32_t>(max_abs_z) & (0xffu << 23)) -
        (23 << 23);
    bits = std::max(bits, 0);
    return std::bit_cast<float>(static_cast<std::uint32_t>(bits));
}

// The same scale as the specification states it (OpenGL 4.6, 14.6.5: r = 2^(e - 23), e the
// exponent of the largest |z| of the polygon), for the exact oracle: from the double's exponent,
// with no clamp (a zero maximum gives 2^-24).
inline double exact_z32f_offset_scale(double max_abs_z) {
    int e = 0;
    (void)std::frexp(max_abs_z, &e);  // max_abs_z = m * 2^e, m in [0.5, 1)
    return std::ldexp(1.0, e - 1 - 23);
}

// Whether face culling discards a polygon of this facing (OpenGL 4.6, 14.6.1, CullFace; the
// fixed-point cull of lp_setup_tri.c and the float cull of draw_pipe_cull.c cull_tri).
constexpr bool is_culled(CullMode cull, bool front_facing) {
    return cull == CullMode::FrontAndBack || (cull == CullMode::Front && front_facing) ||
           (cull == CullMode::Back && !front_facing);
}

// Which edges a tie rule gives the pixel centres lying exactly on them, in GL window terms
// (OpenGL 4.6, 14.6.1: a centre on an edge shared by two polygons belongs to exactly one;
// llvmpipe adds 1 to the edge functions of the edges it owns, lp_setup_tri.c
// do_triangle_ccw). Left: a non-horizontal edge with the interior to its right; bottom: a
// horizontal edge with the interior above.
constexpr bool owns_left_edges(TieRule r) {
    return r == TieRule::LeftBottom || r == TieRule::LeftTop || r == TieRule::All;
}
constexpr bool owns_right_edges(TieRule r) {
    return r == TieRule::RightBottom || r == TieRule::RightTop || r == TieRule::All;
}
constexpr bool owns_bottom_edges(TieRule r) {
    return r == TieRule::LeftBottom || r == TieRule::RightBottom || r == TieRule::All;
}
constexpr bool owns_top_edges(TieRule r) {
    return r == TieRule::LeftTop || r == TieRule::RightTop || r == TieRule::All;
}
// Whether the rule keeps GL's requirement of exactly one owner for a centre on a shared edge.
constexpr bool is_consistent(TieRule r) {
    return r != TieRule::None && r != TieRule::All;
}

// Whether a draw's vertices take the guard band's x/y clip test: under clipping=guard-band
// every draw; under point_line_clipping=pixels the draws of points and the polygons drawn in
// polygon mode point (Mesa 22.3's draw module, draw_pt_fetch_shade_pipeline_llvm.c
// llvm_middle_end_prepare: point_clip from the output primitive and fill_front selects
// guard_band_points_xy, which the rasterizer state's point_tri_clip sets).
inline bool clips_by_guard_band(const Profile& profile, PrimitiveType primitive,
                                const DrawState& state) {
    if (profile.gl.clipping == Clipping::GuardBand) return true;
    return profile.gl.point_line_clipping == PointLineClipping::Pixels &&
           (primitive == PrimitiveType::Points || state.polygon_mode == PolygonMode::Point);
}

// Whether a draw's points survive x/y clip bits (draw_pipe_clip.c: clip_first_point chooses
// clip_point_guard_xy, which drops a point only for z bits or w <= 0, whenever
// guard_band_points_xy is set, which guard_band_xy implies).
inline bool keeps_points_past_xy(const Profile& profile, PrimitiveType primitive) {
    return primitive == PrimitiveType::Points &&
           (profile.gl.clipping == Clipping::GuardBand ||
            profile.gl.point_line_clipping == PointLineClipping::Pixels);
}

// Whether the viewport limits a draw's pixels as a scissor (lp_setup.c: the draw region is
// intersected with the viewport for the guard band, and for point_tri_clip's point clipping,
// for every primitive).
inline bool viewport_scissors(const Profile& profile) {
    return profile.gl.clipping == Clipping::GuardBand ||
           profile.gl.point_line_clipping == PointLineClipping::Pixels;
}

}  // namespace refraster::detail
