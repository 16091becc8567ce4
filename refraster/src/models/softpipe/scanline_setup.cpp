// scanline_setup.cpp: softpipe's triangle setup and span walk (scanline_setup.hpp).
#include "models/softpipe/scanline_setup.hpp"

#include <bit>
#include <cmath>
#include <limits>

namespace refraster::detail {
namespace {

// One edge of sp_setup.c's struct edge: the float steps of setup_tri_edges.
struct ScanEdge {
    float dx = 0.0f;
    float dy = 0.0f;
    float dxdy = 0.0f;
    float sx = 0.0f;
    float sy = 0.0f;
    int lines = 0;
};

// The pixel offset of GL's half-pixel centres (setup->pixel_offset).
constexpr float kPixelOffset = 0.5f;

void start_edge(ScanEdge& e, float x_start, float y_start, float y_end) {
    const float xs = x_start + kPixelOffset;
    const float ys = y_start - kPixelOffset;
    const float ye = y_end - kPixelOffset;
    e.sy = std::ceil(ys);
    e.lines = static_cast<int>(std::ceil(ye - e.sy));
    e.dxdy = e.dy != 0.0f ? e.dx / e.dy : 0.0f;
    e.sx = xs + (e.sy - ys) * e.dxdy;
}

// (int) of a float as softpipe's x86-64 build converts it (cvttss2si): towards zero, and
// INT_MIN for NaN or a value outside int's range. Clipped triangles stay far inside it.
int truncate(float v) {
    if (!(v > -2147483648.0f && v < 2147483648.0f)) return std::numeric_limits<int>::min();
    return static_cast<int>(v);
}

// subtriangle(): `lines` rows from the left edge's sy, clipped to the region, then both edges
// moved on.
void walk(ScanEdge& left, ScanEdge& right, int lines, const PixelRect& region,
          std::vector<ScanlineRow>& rows) {
    const int sy = truncate(left.sy);
    int start = sy < region.y0 ? region.y0 : sy;
    int finish = sy + lines;
    if (finish > region.y1 + 1) finish = region.y1 + 1;
    start -= sy;
    finish -= sy;
    for (int k = start; k < finish; ++k) {
        // sx + k*dxdy, multiplied rather than accumulated (as softpipe does).
        int l = truncate(left.sx + static_cast<float>(k) * left.dxdy);
        int r = truncate(right.sx + static_cast<float>(k) * right.dxdy);
        if (l < region.x0) l = region.x0;
        if (r > region.x1 + 1) r = region.x1 + 1;
        if (l < r) rows.push_back({sy + k, l, r});
    }
    left.sx += static_cast<float>(lines) * left.dxdy;
    right.sx += static_cast<float>(lines) * right.dxdy;
    left.sy += static_cast<float>(lines);
    right.sy += static_cast<float>(lines);
}

}  // namespace

ScanlineOutcome setup_scanline_triangle(const std::array<std::array<float, 2>, 3>& v, CullMode cull,
                                        bool front_ccw, const PixelRect& region,
                                        ScanlineTriangle& out) {
    out.rows.clear();
    // calc_det: e = v0 - v2, f = v1 - v2.
    const float ex = v[0][0] - v[2][0];
    const float ey = v[0][1] - v[2][1];
    const float fx = v[1][0] - v[2][0];
    const float fy = v[1][1] - v[2][1];
    out.det = ex * fy - ey * fx;

    // setup_sort_vertices: bottom to top with <=.
    const float y0 = v[0][1], y1 = v[1][1], y2 = v[2][1];
    if (y0 <= y1) {
        if (y1 <= y2) {
            out.order = {0, 1, 2};
        } else if (y2 <= y0) {
            out.order = {2, 0, 1};
        } else {
            out.order = {0, 2, 1};
        }
    } else {
        if (y0 <= y2) {
            out.order = {1, 0, 2};
        } else if (y2 <= y1) {
            out.order = {2, 1, 0};
        } else {
            out.order = {1, 2, 0};
        }
    }
    const auto& vmin = v[static_cast<std::size_t>(out.order[0])];
    const auto& vmid = v[static_cast<std::size_t>(out.order[1])];
    const auto& vmax = v[static_cast<std::size_t>(out.order[2])];
    ScanEdge ebot, emaj, etop;
    ebot.dx = vmid[0] - vmin[0];
    ebot.dy = vmid[1] - vmin[1];
    emaj.dx = vmax[0] - vmin[0];
    emaj.dy = vmax[1] - vmin[1];
    etop.dx = vmax[0] - vmid[0];
    etop.dy = vmax[1] - vmid[1];
    out.ebot_dx = ebot.dx;
    out.ebot_dy = ebot.dy;
    out.emaj_dx = emaj.dx;
    out.emaj_dy = emaj.dy;
    out.xmin = vmin[0];
    out.ymin = vmin[1];
    const float area = emaj.dx * ebot.dy - ebot.dx * emaj.dy;
    out.one_over_area = 1.0f / area;
    if (!std::isfinite(out.one_over_area)) return ScanlineOutcome::Degenerate;

    // 0 front, 1 back: (det < 0) ^ front_ccw.
    const bool back = (out.det < 0.0f) != front_ccw;
    out.front_facing = !back;
    if (cull == CullMode::FrontAndBack || (cull == CullMode::Front && !back) ||
        (cull == CullMode::Back && back)) {
        return ScanlineOutcome::Culled;
    }

    // setup_tri_edges.
    start_edge(emaj, vmin[0], vmin[1], vmax[1]);
    start_edge(etop, vmid[0], vmid[1], vmax[1]);
    start_edge(ebot, vmin[0], vmin[1], vmid[1]);

    if (out.one_over_area < 0.0f) {
        // The major edge on the left.
        walk(emaj, ebot, ebot.lines, region, out.rows);
        walk(emaj, etop, etop.lines, region, out.rows);
    } else {
        walk(ebot, emaj, ebot.lines, region, out.rows);
        walk(etop, emaj, etop.lines, region, out.rows);
    }
    return ScanlineOutcome::Ok;
}

namespace {

ScanlinePlane plane_of(const ScanlineTriangle& t, float vmin, float vmid, float vmax) {
    const float botda = vmid - vmin;
    const float majda = vmax - vmin;
    const float a = t.ebot_dy * majda - botda * t.emaj_dy;
    const float b = t.emaj_dx * botda - majda * t.ebot_dx;
    ScanlinePlane p;
    p.dadx = a * t.one_over_area;
    p.dady = b * t.one_over_area;
    p.a0 = vmin - (p.dadx * (t.xmin - kPixelOffset) + p.dady * (t.ymin - kPixelOffset));
    return p;
}

}  // namespace

ScanlinePlane scanline_plane(const ScanlineTriangle& t, const std::array<float, 3>& v) {
    const auto at = [&](int k) {
        return v[static_cast<std::size_t>(t.order[static_cast<std::size_t>(k)])];
    };
    return plane_of(t, at(0), at(1), at(2));
}

ScanlinePlane scanline_persp_plane(const ScanlineTriangle& t, const std::array<float, 3>& v,
                                   const std::array<float, 3>& one_over_w) {
    const auto at = [&](int k) {
        const auto i = static_cast<std::size_t>(t.order[static_cast<std::size_t>(k)]);
        return v[i] * one_over_w[i];
    };
    return plane_of(t, at(0), at(1), at(2));
}

std::array<float, 4> scanline_quad(const ScanlinePlane& p, int x0, int y0) {
    const float q = (p.a0 + p.dadx * static_cast<float>(x0)) + p.dady * static_cast<float>(y0);
    return {q, q + p.dadx, q + p.dady, (q + p.dadx) + p.dady};
}

std::uint32_t scanline_depth_value(float z, DepthFormat format) {
    const float c = z < 0.0f ? 0.0f : (z > 1.0f ? 1.0f : z);
    switch (format) {
        case DepthFormat::Z24:
            return static_cast<std::uint32_t>(c * 16777215.0f);
        case DepthFormat::Z16:
            return static_cast<std::uint32_t>(c * 65535.0f);
        case DepthFormat::Z32f:
            return std::bit_cast<std::uint32_t>(c);
        case DepthFormat::None:
            break;
    }
    return 0;
}

}  // namespace refraster::detail
