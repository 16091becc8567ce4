// scanline_setup.hpp: a window-space triangle to rows of pixels, as softpipe 22.3 rasterizes it.
//
// Implements (gallium/drivers/softpipe/sp_setup.c: calc_det, setup_sort_vertices,
// setup_tri_edges, subtriangle; docs/precision.md "softpipe"):
//  - no snapping: the float window positions themselves;
//  - the facing determinant det = ex*fy - ey*fx with e = v0 - v2, f = v1 - v2; a triangle is
//    front-facing when (det < 0) equals gallium's front_ccw is false, and culled by face;
//  - the vertices sorted by y with <= comparisons into vmin, vmid, vmax; the edges
//    ebot (vmin->vmid), emaj (vmin->vmax), etop (vmid->vmax); area = emaj.dx*ebot.dy -
//    ebot.dx*emaj.dy; 1/area in float, and a triangle whose 1/area is not finite draws
//    nothing; the major edge is on the left iff 1/area < 0;
//  - per edge, with x' = x + 0.5 and y' = y - 0.5 (the pixel offset): sy = ceilf(y'_start),
//    lines = (int)ceilf(y'_end - sy), dxdy = dy != 0 ? dx/dy : 0, sx = x'_start + (sy -
//    y'_start)*dxdy; row sy + k spans left = (int)(sx_l + k*dxdy_l) <= x < (int)(sx_r +
//    k*dxdy_r) = right; after the lower half the major edge moves on by lines*dxdy. All in
//    float, unfused, (int) truncating towards zero;
//  - the rows and columns clipped to the draw region (the scissor rectangle).
// The result is softpipe's tie rule without a rule of its own: a centre exactly on a left edge
// is outside, on a right edge inside; in an FBO (gallium y = GL y) a centre on a bottom edge is
// inside and on a top edge outside.
//
// Also the attribute planes (tri_linear_coeff, tri_persp_coeff) and their evaluation a 2x2
// quad at a time (tgsi_exec.c, eval_linear_coef; perspective values are then divided by the
// quad's interpolated 1/w, eval_perspective_coef).
//
// Also softpipe's depth quantisation (scanline_depth_value).
//
// Deliberately does not: the depth test's z16 fast path, fragment output, lines or points.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "common/pixel_rect.hpp"
#include "refraster/draw.hpp"

namespace refraster::detail {

struct ScanlineRow {
    int y = 0;
    int x0 = 0;  // first pixel
    int x1 = 0;  // one past the last
};

struct ScanlineTriangle {
    std::array<int, 3> order{0, 1, 2};  // the input vertex that is vmin, vmid, vmax
    float det = 0.0f;
    float one_over_area = 0.0f;
    bool front_facing = true;
    // What the attribute planes need: ebot's and emaj's deltas and vmin's position.
    float ebot_dx = 0.0f, ebot_dy = 0.0f, emaj_dx = 0.0f, emaj_dy = 0.0f;
    float xmin = 0.0f, ymin = 0.0f;
    std::vector<ScanlineRow> rows;  // bottom to top, only rows with pixels
};

// An attribute plane as softpipe sets it up: value = a0 + dadx * x + dady * y at integer
// pixel coordinates (the half-pixel offset is in a0).
struct ScanlinePlane {
    float a0 = 0.0f;
    float dadx = 0.0f;
    float dady = 0.0f;
};

// tri_linear_coeff: `v` the attribute at the input vertices (before sorting).
//   botda = v_mid - v_min, majda = v_max - v_min,
//   dadx = (ebot.dy*majda - botda*emaj.dy) * (1/area), dady = (emaj.dx*botda - majda*ebot.dx)
//   * (1/area), a0 = v_min - (dadx*(xmin - 0.5) + dady*(ymin - 0.5)).
// tri_persp_coeff is the same on v_i * (1/w)_i (`one_over_w` the window positions' w).
ScanlinePlane scanline_plane(const ScanlineTriangle& t, const std::array<float, 3>& v);
ScanlinePlane scanline_persp_plane(const ScanlineTriangle& t, const std::array<float, 3>& v,
                                   const std::array<float, 3>& one_over_w);

// The four values of a 2x2 quad whose first pixel is (x0, y0) (both even, gallium
// coordinates), in the order (x0, y0), (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1)
// (tgsi_exec.c, eval_linear_coef): q = (a0 + dadx*x0) + dady*y0, then q + dadx, q + dady,
// (q + dadx) + dady. Unfused.
std::array<float, 4> scanline_quad(const ScanlinePlane& p, int x0, int y0);

// softpipe's stored depth (sp_quad_depth_test.c, convert_quad_depth): z clamped to [0, 1],
// then truncated: (unsigned)(z * 16777215.0f) for z24, (unsigned)(z * 65535.0f) for z16, the
// float itself for z32f (its bits). z is the linear plane of window z, evaluated a quad at a
// time. (The z16 fast path, which steps by a truncated integer along the span, is not this.)
std::uint32_t scanline_depth_value(float z, DepthFormat format);

enum class ScanlineOutcome : std::uint8_t { Ok, Degenerate, Culled };

// `window` in gallium coordinates (an FBO's: GL's), `region` the draw region in pixels
// (inclusive bounds), `front_ccw` gallium's rasterizer front_ccw.
ScanlineOutcome setup_scanline_triangle(const std::array<std::array<float, 2>, 3>& window,
                                        CullMode cull, bool front_ccw, const PixelRect& region,
                                        ScanlineTriangle& out);

}  // namespace refraster::detail
