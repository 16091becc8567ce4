// edge_rules.cpp: the draw's setup parameters and the edge functions (edge_rules.hpp).
#include "stages/edge_rules.hpp"

#include <algorithm>

#include "refraster/assert.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

SetupParams setup_params(const Profile& profile, const DrawState& state, const Target& target) {
    REFRASTER_ASSERT(profile.gl.subpixel_bits >= 0 && profile.gl.subpixel_bits <= kMaxSubpixelBits,
                     "subpixel bits within the snapped path's budget");
    REFRASTER_ASSERT(
        target.width <= (1u << kFramebufferBits) && target.height <= (1u << kFramebufferBits),
        "a target within the edge functions' budget");
    SetupParams p;
    p.bits = profile.gl.subpixel_bits;
    p.rounding = profile.gl.snap_rounding;
    p.pixel_center_offset = profile.gl.pixel_center_offset;
    p.half_pixel_center = profile.gl.pixel_center_offset;
    p.tie_rule = profile.gl.tie_rule;
    p.wrapping = profile.quirks.wrapping_arithmetic;
    // lp_setup_tri.c / lp_setup_line.c / lp_setup_point.c: with the rasterizer's
    // multisample state on, the snap has no pixel offset (docs/precision.md, "Multisampling (4x)").
    p.multisample = target.samples > 1 && state.multisample;
    if (p.multisample) p.pixel_center_offset = 0.0f;
    p.cull = state.cull;
    // st_atom_rasterizer.c: front_ccw = (FrontFace == GL_CCW), flipped for an FBO.
    p.front_ccw = state.front_face != FrontFace::Ccw;
    p.provoking_first = state.provoking_vertex == ProvokingVertex::First;
    // lp_setup.c: the draw region is the framebuffer, intersected with the scissor.
    p.draw_region = {0, 0, static_cast<int>(target.width) - 1, static_cast<int>(target.height) - 1};
    p.framebuffer = p.draw_region;
    if (viewport_scissors(profile)) {
        // With the guard band, or point_tri_clip's point clipping, the viewport is applied as
        // a scissor (lp_setup.c, draw_regions).
        const auto& v = state.viewport;
        p.draw_region = intersect(p.draw_region, {v.x, v.y, v.x + v.width - 1, v.y + v.height - 1});
    }
    if (state.scissor) {
        const auto& s = *state.scissor;
        const std::int64_t x1 = std::int64_t{s.x} + s.width - 1;
        const std::int64_t y1 = std::int64_t{s.y} + s.height - 1;
        p.draw_region = intersect(
            p.draw_region, {s.x, s.y, static_cast<int>(std::clamp<std::int64_t>(x1, -1, 1 << 30)),
                            static_cast<int>(std::clamp<std::int64_t>(y1, -1, 1 << 30))});
    }
    return p;
}

// The interior is where E grows: dE/dx = -a, dE/dy = b. A left edge has the interior to its
// right (dE/dx > 0); a horizontal bottom edge has it above (dE/dy > 0).
bool owns_ties(std::int32_t a, std::int32_t b, TieRule rule) {
    if (rule == TieRule::None) return false;
    if (rule == TieRule::All) return true;
    if (a != 0) return (-a > 0) == owns_left_edges(rule);
    return (b > 0) == owns_bottom_edges(rule);
}

std::optional<std::array<std::int32_t, 2>> snap_position(float x, float y, const SetupParams& p) {
    bool beyond = false;
    const std::int32_t sx = snap_to_subpixel(x, p, beyond);
    const std::int32_t sy = snap_to_subpixel(y, p, beyond);
    if (beyond) return std::nullopt;
    return std::array<std::int32_t, 2>{sx, sy};
}

}  // namespace refraster::detail
