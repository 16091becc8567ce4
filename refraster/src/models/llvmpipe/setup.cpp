#include "models/llvmpipe/setup.hpp"

#include <algorithm>
#include <cstdint>

#include "refraster/assert.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

namespace {

// The orientation swap of triangle_both / triangle_cw: rotate_fixed_position_12 with the
// first-vertex convention, _01 otherwise, so that the provoking vertex keeps its place.
void swap_to_ccw(const SetupParams& p, TriangleSetup& t) {
    const std::size_t i = p.provoking_first ? 1 : 0;
    std::swap(t.x[i], t.x[i + 1]);
    std::swap(t.y[i], t.y[i + 1]);
    std::swap(t.order[i], t.order[i + 1]);
}

// do_triangle_ccw's bounding box: x0 and y0 by arithmetic shift (floor); x1 and y1 from
// max - 1 (a 32-bit subtraction), which leaves out a column (row) whose centres lie exactly
// on the rightmost (topmost) extent: only a rule owning right (top) edges could cover those,
// and then the box keeps them. For llvmpipe's left-bottom rule in an FBO this is the
// driver's box.
[[gnu::always_inline]] inline PixelRect raw_box(const SetupParams& p, const TriangleSetup& t) {
    const auto [xmin, xmax] = std::minmax({t.x[0], t.x[1], t.x[2]});
    const auto [ymin, ymax] = std::minmax({t.y[0], t.y[1], t.y[2]});
    const bool owns_right = owns_right_edges(p.tie_rule);
    const bool owns_top = owns_top_edges(p.tie_rule);
    return {xmin >> p.bits, ymin >> p.bits, lp::sub32(xmax, owns_right ? 0 : 1) >> p.bits,
            lp::sub32(ymax, owns_top ? 0 : 1) >> p.bits};
}

// do_triangle_ccw: the 32-bit rasterizer takes boxes of at most MAX_FIXED_LENGTH32 pixels,
// measured before x0 and y0 are clamped to the framebuffer.
bool uses_32bit_rasterizer(const PixelRect& raw) {
    const std::int32_t size = lp::sub32(raw.x1, raw.x0 & ~3) | lp::sub32(raw.y1, raw.y0 & ~3);
    return size <= lp::kMaxFixedLength32;
}

}  // namespace

void attach_llvmpipe_walk(const SetupParams& p, TriangleSetup& t) {
    const PixelRect raw = raw_box(p, t);
    lp::Triangle& w = t.walk;
    w = lp::Triangle{};
    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t j = (i + 1) % 3;
        const std::int32_t a = lp::sub32(t.y[i], t.y[j]);
        const std::int32_t b = lp::sub32(t.x[i], t.x[j]);
        w.planes[static_cast<std::size_t>(w.count++)] =
            lp::edge_plane(t.x[i], t.y[i], t.x[j], t.y[j], owns_ties(a, b, p.tie_rule));
    }
    w.box = {std::max(raw.x0, 0), std::max(raw.y0, 0), raw.x1, raw.y1};
    w.draw_region = p.draw_region;
    w.framebuffer = p.framebuffer;
    w.samples = p.multisample ? 4 : 1;
    lp::add_region_planes(w);
    t.llvmpipe_walk = true;
}

namespace {

// Whether llvmpipe's integer widths change the pixels of a triangle whose positions fit the
// budget: an edge delta whose << FIXED_ORDER leaves int32 (spans of 2^15 pixels, which only
// a guard band reaches), or the one-tile case: lp_setup_bin_triangle bins a box (x0 and y0
// clamped to 0, x1 and y1 not) that crosses no 64-pixel boundary as one tile with every
// plane in its mask (the 4x4 and 16x16 commands of a triangle too large for the 32-bit
// rasterizer go the same way), so lp_rast_tri_tmp.h tests even the edges that are positive
// over the whole tile; its RASTER_64 block tests keep (c >> FIXED_ORDER) in int32, and an
// edge whose value there leaves int32 wraps: whole blocks are rejected or filled.
bool widths_matter(const PixelRect& raw, const TriangleSetup& t) {
    const std::int64_t lim = std::int64_t{1} << 23;
    for (const EdgeFunction& e : t.edges) {
        const std::int64_t eo = (e.a < 0 ? -std::int64_t{e.a} : 0) + (e.b > 0 ? e.b : 0);
        if (e.a <= -lim || e.a >= lim || e.b <= -lim || e.b >= lim || eo >= lim) return true;
    }
    const int x0 = std::max(raw.x0, 0);
    const int y0 = std::max(raw.y0, 0);
    if (((x0 ^ raw.x1) | (y0 ^ raw.y1)) >= 64) return false;
    const int tx = x0 & ~63;
    const int ty = y0 & ~63;
    for (const EdgeFunction& e : t.edges) {
        const std::int64_t q = e.at(tx, ty, t.bits) >> t.bits;
        const std::int64_t reach =
            128 * ((e.a < 0 ? -std::int64_t{e.a} : e.a) + (e.b < 0 ? -std::int64_t{e.b} : e.b));
        if (q - reach <= INT32_MIN || q + reach >= INT32_MAX) return true;
    }
    return false;
}

// A triangle with a position outside the budget, set up as llvmpipe does it: the area from
// wrapping 32-bit differences in wrapping 64-bit arithmetic (calc_fixed_position, whose sign
// is bit 63), then the same orientation, culling and box as in range, and llvmpipe's walk.
SetupOutcome setup_beyond_budget(const SetupParams& p, TriangleSetup& t) {
    const std::int32_t dx01 = lp::sub32(t.x[0], t.x[1]);
    const std::int32_t dy01 = lp::sub32(t.y[0], t.y[1]);
    const std::int32_t dx20 = lp::sub32(t.x[2], t.x[0]);
    const std::int32_t dy20 = lp::sub32(t.y[2], t.y[0]);
    t.area = lp::sub64(std::int64_t{dx01} * dy20, std::int64_t{dx20} * dy01);
    if (t.area == 0) return SetupOutcome::ZeroArea;
    t.front_facing = (t.area > 0) == p.front_ccw;
    if (is_culled(p.cull, t.front_facing)) return SetupOutcome::Culled;
    if (t.area < 0) swap_to_ccw(p, t);
    const PixelRect raw = raw_box(p, t);
    t.bbox = intersect(raw, p.draw_region);
    if (t.bbox.empty()) return SetupOutcome::Outside;
    // Wrapped positions always span more than 128 pixels; anything else is not modelled.
    // The multisample commands are 64-bit whatever the box (lp_rast_ms_tri_tab).
    if (!p.multisample && uses_32bit_rasterizer(raw)) return SetupOutcome::OutOfRange;
    attach_llvmpipe_walk(p, t);
    return SetupOutcome::Ok;
}

}  // namespace

SetupOutcome setup_triangle(const std::array<std::array<float, 2>, 3>& w, const SetupParams& p,
                            TriangleSetup& t) {
    t.bits = p.bits;
    bool beyond = false;
    for (std::size_t i = 0; i < 3; ++i) {
        t.x[i] = snap_to_subpixel(w[i][0], p, beyond);
        t.y[i] = snap_to_subpixel(w[i][1], p, beyond);
    }
    t.order = {0, 1, 2};
    // llvmpipe's arithmetic is reproduced for its own precision and rounding only.
    const bool llvmpipe_widths =
        p.wrapping && p.bits == lp::kFixedOrder && p.rounding == SnapRounding::NearestEven;
    if (beyond) return llvmpipe_widths ? setup_beyond_budget(p, t) : SetupOutcome::OutOfRange;
    t.area = checked_sub(wide_mul(checked_sub(t.x[0], t.x[1]), checked_sub(t.y[2], t.y[0])),
                         wide_mul(checked_sub(t.x[2], t.x[0]), checked_sub(t.y[0], t.y[1])));
    if (t.area == 0) return SetupOutcome::ZeroArea;
    // triangle_both / _cw / _ccw: area > 0 is gallium's counter-clockwise.
    t.front_facing = (t.area > 0) == p.front_ccw;
    if (is_culled(p.cull, t.front_facing)) return SetupOutcome::Culled;
    if (t.area < 0) swap_to_ccw(p, t);
    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t j = (i + 1) % 3;
        t.edges[i] = make_edge(t.x[i], t.y[i], t.x[j], t.y[j], p.tie_rule);
    }
    const PixelRect raw = raw_box(p, t);
    t.bbox = intersect(raw, p.draw_region);
    if (t.bbox.empty()) return SetupOutcome::Outside;
    if (llvmpipe_widths && (p.multisample || !uses_32bit_rasterizer(raw)) && widths_matter(raw, t))
        attach_llvmpipe_walk(p, t);
    t.scissor_leak = multisample_scissor_leak(
        {std::max(raw.x0, 0), std::max(raw.y0, 0), raw.x1, raw.y1}, p, t.bbox);
    return SetupOutcome::Ok;
}

std::uint8_t multisample_scissor_leak(const PixelRect& binned, const SetupParams& p,
                                      PixelRect& bbox) {
    if (!p.multisample || bbox.empty()) return 0;
    const PixelRect& r = p.draw_region;
    // lp_setup_bin_triangle: one tile when the box crosses no power-of-two boundary of 64.
    const bool one_tile =
        ((binned.x0 ^ binned.x1) | (binned.y0 ^ binned.y1)) < (1 << lp::kTileOrder);
    std::uint8_t leak = 0;
    if (binned.x0 < r.x0 && (one_tile || r.x0 % (1 << lp::kTileOrder) != 0)) {
        bbox.x0 = r.x0 - 1;
        leak |= kLeakLeft;
    }
    if (binned.y0 < r.y0 && (one_tile || r.y0 % (1 << lp::kTileOrder) != 0)) {
        bbox.y0 = r.y0 - 1;
        leak |= kLeakBottom;
    }
    return leak;
}

}  // namespace refraster::detail
