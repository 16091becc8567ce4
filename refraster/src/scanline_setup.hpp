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
// Deliberately does not: attribute planes or quads (softpipe evaluates attributes a 2x2 quad at
// a time), lines or points.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "pixel_rect.hpp"
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
    std::vector<ScanlineRow> rows;  // bottom to top, only rows with pixels
};

enum class ScanlineOutcome : std::uint8_t { Ok, Degenerate, Culled };

// `window` in gallium coordinates (an FBO's: GL's), `region` the draw region in pixels
// (inclusive bounds), `front_ccw` gallium's rasterizer front_ccw.
ScanlineOutcome setup_scanline_triangle(const std::array<std::array<float, 2>, 3>& window,
                                        CullMode cull, bool front_ccw, const PixelRect& region,
                                        ScanlineTriangle& out);

}  // namespace refraster::detail
