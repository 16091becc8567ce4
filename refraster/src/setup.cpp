#include "setup.hpp"

#include <algorithm>
#include <cstdint>

namespace refraster::detail {

PixelRect intersect(const PixelRect& a, const PixelRect& b) {
    return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

SetupParams setup_params(const Profile& profile, const DrawState& state, const Target& target) {
    SetupParams p;
    p.bits = profile.gl.subpixel_bits;
    p.rounding = profile.gl.snap_rounding;
    p.pixel_center_offset = profile.gl.pixel_center_offset;
    p.tie_rule = profile.gl.tie_rule;
    p.cull = state.cull;
    // st_atom_rasterizer.c: front_ccw = (FrontFace == GL_CCW), flipped for an FBO.
    p.front_ccw = state.front_face != FrontFace::Ccw;
    p.provoking_first = state.provoking_vertex == ProvokingVertex::First;
    // lp_setup.c: the draw region is the framebuffer, intersected with the scissor.
    p.draw_region = {0, 0, static_cast<int>(target.width) - 1, static_cast<int>(target.height) - 1};
    p.framebuffer = p.draw_region;
    if (profile.gl.clipping == Clipping::GuardBand) {
        // With the guard band the viewport is applied as a scissor (lp_setup.c, draw_regions).
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

std::optional<std::int32_t> snap_coordinate(float v, const SetupParams& p) {
    // lp_setup_tri.c calc_fixed_position: (v - pixel_offset) * FIXED_ONE in float, then the
    // conversion. Both float operations are exact for window coordinates below 2^16 except
    // the subtraction's rounding of far-out values, which is part of the rule.
    const float scaled = (v - p.pixel_center_offset) * static_cast<float>(1 << p.bits);
    const auto r = round_scaled<std::int32_t>(scaled, p.rounding);
    if (!r || *r <= -(1 << kSnappedBits) || *r >= (1 << kSnappedBits)) return std::nullopt;
    return r;
}

// The interior is where E grows: dE/dx = -a, dE/dy = b. A left edge has the interior to its
// right (dE/dx > 0); a horizontal bottom edge has it above (dE/dy > 0).
bool owns_ties(std::int32_t a, std::int32_t b, TieRule rule) {
    const bool left = rule == TieRule::LeftBottom || rule == TieRule::LeftTop;
    const bool bottom = rule == TieRule::LeftBottom || rule == TieRule::RightBottom;
    if (a != 0) return (-a > 0) == left;
    return (b > 0) == bottom;
}

EdgeFunction make_edge(std::int32_t xi, std::int32_t yi, std::int32_t xj, std::int32_t yj,
                       TieRule rule) {
    EdgeFunction e;
    e.a = checked_sub(yi, yj);
    e.b = checked_sub(xi, xj);
    e.owns_ties = owns_ties(e.a, e.b, rule);
    e.c = checked_add(checked_sub(wide_mul(e.a, xi), wide_mul(e.b, yi)),
                      std::int64_t{e.owns_ties ? 1 : 0});
    return e;
}

namespace {

// lp_setup_tri.c, lp_setup_bin_triangle: a box (x0 and y0 clamped to 0, x1 and y1 not) that
// crosses no 64-pixel boundary is binned as one tile with every plane in its mask (the
// 4x4 and 16x16 commands of a triangle too large for the 32-bit rasterizer go the same way),
// so lp_rast_tri_tmp.h tests even the edges that are positive over the whole tile. Its
// RASTER_64 block tests keep (c >> FIXED_ORDER) in int32, and an edge whose value there
// leaves int32 wraps: whole blocks are rejected or filled. Modelled only where every other
// step is exact: no scissor plane (the box inside the draw region, which is the
// framebuffer), dcdx, dcdy and eo still fit 32 bits after the << FIXED_ORDER of
// do_triangle_ccw.
void mark_wrapped_tile(const PixelRect& raw, const SetupParams& p, TriangleSetup& t) {
    if (p.bits != 8 || !(p.draw_region == p.framebuffer)) return;
    const int x0 = std::max(raw.x0, 0);
    const int y0 = std::max(raw.y0, 0);
    if (((x0 ^ raw.x1) | (y0 ^ raw.y1)) >= 64) return;
    const PixelRect& d = p.draw_region;
    if (x0 < d.x0 || raw.x1 > d.x1 || y0 < d.y0 || raw.y1 > d.y1) return;
    const int tx = x0 & ~63;
    const int ty = y0 & ~63;
    bool wraps = false;
    for (const EdgeFunction& e : t.edges) {
        const std::int64_t a = e.a;
        const std::int64_t b = e.b;
        const std::int64_t eo = (a < 0 ? -a : 0) + (b > 0 ? b : 0);
        const std::int64_t lim = std::int64_t{1} << 23;
        if (a <= -lim || a >= lim || b <= -lim || b >= lim || eo >= lim) return;
        const std::int64_t q = e.at(tx, ty, p.bits) >> p.bits;
        const std::int64_t reach = 128 * ((a < 0 ? -a : a) + (b < 0 ? -b : b));
        if (q - reach <= INT32_MIN || q + reach >= INT32_MAX) wraps = true;
    }
    if (!wraps) return;
    t.wrapped_tile = true;
    t.tile_x = tx;
    t.tile_y = ty;
    t.tile_clip = d;
}

}  // namespace

SetupOutcome setup_triangle(const std::array<std::array<float, 2>, 3>& w, const SetupParams& p,
                            TriangleSetup& t) {
    t.bits = p.bits;
    for (std::size_t i = 0; i < 3; ++i) {
        const auto x = snap_coordinate(w[i][0], p);
        const auto y = snap_coordinate(w[i][1], p);
        if (!x || !y) return SetupOutcome::OutOfRange;
        t.x[i] = *x;
        t.y[i] = *y;
    }
    t.order = {0, 1, 2};
    t.area = checked_sub(wide_mul(checked_sub(t.x[0], t.x[1]), checked_sub(t.y[2], t.y[0])),
                         wide_mul(checked_sub(t.x[2], t.x[0]), checked_sub(t.y[0], t.y[1])));
    if (t.area == 0) return SetupOutcome::ZeroArea;
    // triangle_both / _cw / _ccw: area > 0 is gallium's counter-clockwise.
    t.front_facing = (t.area > 0) == p.front_ccw;
    const bool culled = p.cull == CullMode::FrontAndBack ||
                        (p.cull == CullMode::Front && t.front_facing) ||
                        (p.cull == CullMode::Back && !t.front_facing);
    if (culled) return SetupOutcome::Culled;
    if (t.area < 0) {
        // rotate_fixed_position_12 with the first-vertex convention, _01 otherwise: the
        // provoking vertex keeps its place.
        const std::size_t i = p.provoking_first ? 1 : 0;
        std::swap(t.x[i], t.x[i + 1]);
        std::swap(t.y[i], t.y[i + 1]);
        std::swap(t.order[i], t.order[i + 1]);
    }
    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t j = (i + 1) % 3;
        t.edges[i] = make_edge(t.x[i], t.y[i], t.x[j], t.y[j], p.tie_rule);
    }
    // do_triangle_ccw's bounding box: x0 and y0 by arithmetic shift (floor); x1 and y1 from
    // max - 1, which leaves out a column (row) whose centres lie exactly on the rightmost
    // (topmost) extent: only a rule owning right (top) edges could cover those, and then the
    // box keeps them. For llvmpipe's left-bottom rule in an FBO this is the driver's box.
    const auto [xmin, xmax] = std::minmax({t.x[0], t.x[1], t.x[2]});
    const auto [ymin, ymax] = std::minmax({t.y[0], t.y[1], t.y[2]});
    const bool owns_right = p.tie_rule == TieRule::RightBottom || p.tie_rule == TieRule::RightTop;
    const bool owns_top = p.tie_rule == TieRule::LeftTop || p.tie_rule == TieRule::RightTop;
    const PixelRect raw{xmin >> p.bits, ymin >> p.bits, (xmax - (owns_right ? 0 : 1)) >> p.bits,
                        (ymax - (owns_top ? 0 : 1)) >> p.bits};
    t.bbox = intersect(raw, p.draw_region);
    if (t.bbox.empty()) return SetupOutcome::Outside;
    mark_wrapped_tile(raw, p, t);
    return SetupOutcome::Ok;
}

}  // namespace refraster::detail
