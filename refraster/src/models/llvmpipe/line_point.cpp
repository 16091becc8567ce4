#include "models/llvmpipe/line_point.hpp"

#include <algorithm>
#include <cmath>

#include "refraster/assert.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

namespace {

// util_iround on x86-64 (util/u_math.h): (int)(f + 0.5f) or (int)(f - 0.5f), in float.
std::optional<std::int32_t> iround(float f) {
    const float r = f >= 0.0f ? f + 0.5f : f - 0.5f;
    if (!std::isfinite(r) || std::fabs(r) >= static_cast<float>(1 << kSnappedBits))
        return std::nullopt;
    return static_cast<std::int32_t>(r);
}

// subpixel_snap in lp_setup_line.c / lp_setup_point.c: util_iround(FIXED_ONE * a).
std::optional<std::int32_t> snap(float a, int bits) {
    return iround(static_cast<float>(1 << bits) * a);
}

bool nonneg(float x) {
    return x >= 0;
}  // lp_setup_line.c sign()

float fracf(float f) {
    return f - std::floor(f);
}

int ceil_shift(std::int32_t v, int bits) {
    return (v + (1 << bits) - 1) >> bits;
}

// linear_coef's shared terms (lp_setup_line.c): the start's position less the pixel offset,
// the gradient's direction and 1 / area.
struct LinearTerms {
    float x0c, y0c, info_dx, info_dy, oneoverarea;
};

// lp_setup_line.c linear_coef for one attribute from its values at the two ends, each result
// rounded to float and flushed as the model's FTZ says. Inline: every line makes six or more.
[[gnu::always_inline]] inline Plane linear_coef(const Fp& fp, const LinearTerms& t, float a1,
                                                float a2) {
    const float da21 = fp.f(a1 - a2);
    Plane pl;
    pl.dadx = fp.f(fp.f(da21 * t.info_dx) * t.oneoverarea);
    pl.dady = fp.f(fp.f(da21 * t.info_dy) * t.oneoverarea);
    pl.a0 = fp.f(a1 - fp.f(fp.f(pl.dadx * t.x0c) + fp.f(pl.dady * t.y0c)));
    return pl;
}

}  // namespace

std::optional<LineSetup> setup_line(const StageVertex& sv1, const StageVertex& sv2,
                                    float line_width, const SetupParams& p) {
    // try_setup_line, the non-rectangular branch, step by step in the driver's float order.
    const float* v1 = sv1.window.data();
    const float* v2 = sv2.window.data();
    const float width = std::max(1.0f, line_width);
    float dx = v1[0] - v2[0];
    float dy = v1[1] - v2[1];
    const float area = dx * dx + dy * dy;
    if (area == 0) return std::nullopt;
    const float pixel_offset = p.pixel_center_offset;

    float x_offset = 0, y_offset = 0, x_offset_end = 0, y_offset_end = 0;
    float x1diff = v1[0] - std::floor(v1[0]) - 0.5f;
    float y1diff = v1[1] - std::floor(v1[1]) - 0.5f;
    float x2diff = v2[0] - std::floor(v2[0]) - 0.5f;
    float y2diff = v2[1] - std::floor(v2[1]) - 0.5f;
    const auto iw = iround(width);
    if (!iw) return std::nullopt;
    const std::int32_t fixed_width = *iw * (1 << p.bits);
    // The result is built once its every member is known (a default-constructed one is
    // cleared first by a string store whose start-up cost a short line notices).
    bool x_major = true;
    bool draw_start = false;
    bool draw_end = false;
    std::array<std::optional<std::int32_t>, 8> s{};  // x[0..3], y[0..3] before the width

    if (std::fabs(dx) >= std::fabs(dy)) {
        x_major = true;
        const float dydx = dy / dx;
        if (y2diff == -0.5f && dy < 0) y2diff = 0.5f;
        if (std::fabs(x1diff) + std::fabs(y1diff) < 0.5f) {
            draw_start = true;
        } else if (nonneg(x1diff) == nonneg(-dx)) {
            draw_start = false;
        } else if (nonneg(-y1diff) != nonneg(dy)) {
            draw_start = true;
        } else {
            const float yintersect = fracf(v1[1]) + x1diff * dydx;
            draw_start = yintersect < 1.0f && yintersect > 0.0f;
        }
        if (std::fabs(x2diff) + std::fabs(y2diff) < 0.5f) {
            draw_end = false;
        } else if (nonneg(x2diff) != nonneg(-dx)) {
            draw_end = false;
        } else if (nonneg(-y2diff) == nonneg(dy)) {
            draw_end = true;
        } else {
            const float yintersect = fracf(v2[1]) + x2diff * dydx;
            draw_end = yintersect < 1.0f && yintersect > 0.0f;
        }
        const bool will_draw_start = nonneg(-x1diff) != nonneg(dx);
        const bool will_draw_end = nonneg(x2diff) == nonneg(-dx) || x2diff == 0;
        if (dx < 0) {
            std::swap(v1, v2);
            dx = -dx;
            dy = -dy;
            if (will_draw_start != draw_start) {
                x_offset_end = -x1diff - 0.5f;
                y_offset_end = x_offset_end * dydx;
            }
            if (will_draw_end != draw_end) {
                x_offset = -x2diff - 0.5f;
                y_offset = x_offset * dydx;
            }
        } else {
            if (will_draw_start != draw_start) {
                x_offset = -x1diff + 0.5f;
                y_offset = x_offset * dydx;
            }
            if (will_draw_end != draw_end) {
                x_offset_end = -x2diff + 0.5f;
                y_offset_end = x_offset_end * dydx;
            }
        }
        s[0] = snap(v1[0] + x_offset - pixel_offset, p.bits);
        s[1] = snap(v2[0] + x_offset_end - pixel_offset, p.bits);
        s[2] = s[1];
        s[3] = s[0];
        const auto ya = snap(v1[1] + y_offset - pixel_offset, p.bits);
        const auto yb = snap(v2[1] + y_offset_end - pixel_offset, p.bits);
        if (!ya || !yb) return std::nullopt;
        s[4] = *ya - fixed_width / 2;
        s[5] = *yb - fixed_width / 2;
        s[6] = *yb + fixed_width / 2;
        s[7] = *ya + fixed_width / 2;
    } else {
        x_major = false;
        const float dxdy = dx / dy;
        if (x2diff == -0.5f && dx < 0) x2diff = 0.5f;
        if (std::fabs(x1diff) + std::fabs(y1diff) < 0.5f) {
            draw_start = true;
        } else if (nonneg(-y1diff) == nonneg(dy)) {
            draw_start = false;
        } else if (nonneg(x1diff) != nonneg(-dx)) {
            draw_start = true;
        } else {
            const float xintersect = fracf(v1[0]) + y1diff * dxdy;
            draw_start = xintersect < 1.0f && xintersect > 0.0f;
        }
        if (std::fabs(x2diff) + std::fabs(y2diff) < 0.5f) {
            draw_end = false;
        } else if (nonneg(-y2diff) != nonneg(dy)) {
            draw_end = false;
        } else if (nonneg(x2diff) == nonneg(-dx)) {
            draw_end = true;
        } else {
            const float xintersect = fracf(v2[0]) + y2diff * dxdy;
            draw_end = xintersect < 1.0f && xintersect >= 0.0f;
        }
        const bool will_draw_start = nonneg(y1diff) == nonneg(dy);
        const bool will_draw_end = nonneg(-y2diff) == nonneg(dy) || y2diff == 0;
        if (dy > 0) {
            std::swap(v1, v2);
            dx = -dx;
            dy = -dy;
            if (will_draw_start != draw_start) {
                y_offset_end = -y1diff + 0.5f;
                x_offset_end = y_offset_end * dxdy;
            }
            if (will_draw_end != draw_end) {
                y_offset = -y2diff + 0.5f;
                x_offset = y_offset * dxdy;
            }
        } else {
            if (will_draw_start != draw_start) {
                y_offset = -y1diff - 0.5f;
                x_offset = y_offset * dxdy;
            }
            if (will_draw_end != draw_end) {
                y_offset_end = -y2diff - 0.5f;
                x_offset_end = y_offset_end * dxdy;
            }
        }
        const auto xa = snap(v1[0] + x_offset - pixel_offset, p.bits);
        const auto xb = snap(v2[0] + x_offset_end - pixel_offset, p.bits);
        if (!xa || !xb) return std::nullopt;
        s[0] = *xa - fixed_width / 2;
        s[1] = *xb - fixed_width / 2;
        s[2] = *xb + fixed_width / 2;
        s[3] = *xa + fixed_width / 2;
        s[4] = snap(v1[1] + y_offset - pixel_offset, p.bits);
        s[5] = snap(v2[1] + y_offset_end - pixel_offset, p.bits);
        s[6] = s[5];
        s[7] = s[4];
    }
    for (const auto& v : s) {
        if (!v) return std::nullopt;
    }
    std::array<std::int32_t, 4> x;
    std::array<std::int32_t, 4> y;
    for (std::size_t i = 0; i < 4; ++i) {
        x[i] = *s[i];
        y[i] = *s[4 + i];
    }
    // The box: inclusive x0, y0 rounded up; x1, y1 one below the rounded-up maximum (the
    // driver's, for rules owning left and bottom edges); rules owning right or top edges keep
    // the pixel on the maximum.
    const auto [xmin, xmax] = std::minmax_element(x.begin(), x.end());
    const auto [ymin, ymax] = std::minmax_element(y.begin(), y.end());
    const int x1 = owns_right_edges(p.tie_rule) ? (*xmax >> p.bits) : ceil_shift(*xmax, p.bits) - 1;
    const int y1 = owns_top_edges(p.tie_rule) ? (*ymax >> p.bits) : ceil_shift(*ymax, p.bits) - 1;
    const PixelRect bbox =
        intersect({ceil_shift(*xmin, p.bits), ceil_shift(*ymin, p.bits), x1, y1}, p.draw_region);
    if (bbox.empty()) return std::nullopt;
    const auto edge = [&](std::size_t i, std::size_t j) {
        return make_edge(x[i], y[i], x[j], y[j], p.tie_rule);
    };
    return LineSetup{p.bits, x,       y, {edge(0, 1), edge(1, 2), edge(2, 3), edge(3, 0)},
                     bbox,   x_major, 0};
}

std::optional<LineSetup> setup_rect_line(const StageVertex& sv1, const StageVertex& sv2,
                                         float line_width, const SetupParams& p) {
    // try_setup_line, the rectangular branch (line_rectangular, which the state tracker sets
    // for multisampling, st_atom_rasterizer.c): a rectangle of the unrounded width around
    // the segment, its half-width vector snapped once, no pixel offset and no diamond rule.
    const float* v1 = sv1.window.data();
    const float* v2 = sv2.window.data();
    const float dx = v1[0] - v2[0];
    const float dy = v1[1] - v2[1];
    const float area = dx * dx + dy * dy;
    if (area == 0) return std::nullopt;
    // GL clamps the width to the implementation's range (1..255 in llvmpipe).
    const float width = std::clamp(line_width, 1.0f, 255.0f);
    const float scale = (width * 0.5f) / std::sqrt(area);
    const auto tx = snap(-dy * scale, p.bits);
    const auto ty = snap(dx * scale, p.bits);
    const auto x1 = snap(v1[0] - p.pixel_center_offset, p.bits);
    const auto y1 = snap(v1[1] - p.pixel_center_offset, p.bits);
    const auto x2 = snap(v2[0] - p.pixel_center_offset, p.bits);
    const auto y2 = snap(v2[1] - p.pixel_center_offset, p.bits);
    if (!tx || !ty || !x1 || !y1 || !x2 || !y2) return std::nullopt;
    LineSetup L;
    L.bits = p.bits;
    L.x_major = std::fabs(dx) >= std::fabs(dy);
    L.x = {*x1 - *tx, *x2 - *tx, *x2 + *tx, *x1 + *tx};
    L.y = {*y1 - *ty, *y2 - *ty, *y2 + *ty, *y1 + *ty};
    for (std::size_t i = 0; i < 4; ++i) {
        const std::size_t j = (i + 1) % 4;
        L.edges[i] = make_edge(L.x[i], L.y[i], L.x[j], L.y[j], p.tie_rule);
    }
    const auto [xmin, xmax] = std::minmax_element(L.x.begin(), L.x.end());
    const auto [ymin, ymax] = std::minmax_element(L.y.begin(), L.y.end());
    if (!multisample_line_box(*xmin, *xmax, *ymin, *ymax, p, L)) return std::nullopt;
    return L;
}

namespace {

// What lp_setup_bin_triangle rasterizes of a multisampled primitive binned with box `b` (x0,
// y0 >= 0): the 64x64 tile of the box when it crosses no tile boundary (the multisample
// "contained" commands take the whole tile, measured), otherwise the tiles of the box
// trimmed to the draw region.
PixelRect binned_area(const PixelRect& b, const PixelRect& region) {
    constexpr int kTile = 1 << lp::kTileOrder;
    if (((b.x0 ^ b.x1) | (b.y0 ^ b.y1)) < kTile) {
        const int tx = b.x0 & ~(kTile - 1);
        const int ty = b.y0 & ~(kTile - 1);
        return {tx, ty, tx + kTile - 1, ty + kTile - 1};
    }
    const PixelRect t = intersect(b, region);
    return {t.x0 & ~(kTile - 1), t.y0 & ~(kTile - 1), (t.x1 & ~(kTile - 1)) + kTile - 1,
            (t.y1 & ~(kTile - 1)) + kTile - 1};
}

}  // namespace

// try_setup_line's box, rounded up at both ends ((v + 255) >> 8, the high end less one),
// decides which scissor planes the line gets and what the binner rasterizes
// (binned_area); the rectangle's samples may reach one pixel below the box's low ends, and
// there only the planes and the binned area limit them. A left (bottom) scissor plane, when
// the box crosses that side, keeps samples 1 and 3 (2 and 3) of the column (row) just outside
// (lp_setup_add_scissor_planes, +127 under multisampling); where the box does not cross it
// there is no plane, and the column just outside keeps every sample the rectangle covers.
// Right and top planes cut at the pixel. Measured: docs/precision.md, "Multisampling (4x)".
bool multisample_line_box(std::int32_t xmin, std::int32_t xmax, std::int32_t ymin,
                          std::int32_t ymax, const SetupParams& p, LineSetup& L) {
    const PixelRect& r = p.draw_region;
    const PixelRect box{ceil_shift(xmin, p.bits), ceil_shift(ymin, p.bits),
                        ceil_shift(xmax, p.bits) - 1, ceil_shift(ymax, p.bits) - 1};
    if (intersect(box, r).empty()) return false;
    const PixelRect pos{std::max(box.x0, 0), std::max(box.y0, 0), box.x1, box.y1};
    const bool left = pos.x0 < r.x0;
    const bool bottom = pos.y0 < r.y0;
    const PixelRect area = binned_area(pos, r);
    // Pixels holding a sample the rectangle may cover, within what is rasterized, the
    // framebuffer and the scissor planes.
    PixelRect b{std::max({xmin >> p.bits, area.x0, p.framebuffer.x0, r.x0 - 1}),
                std::max({ymin >> p.bits, area.y0, p.framebuffer.y0, r.y0 - 1}),
                std::min({(xmax - 1) >> p.bits, area.x1, r.x1}),
                std::min({(ymax - 1) >> p.bits, area.y1, r.y1})};
    if (b.empty()) return false;
    std::uint8_t leak = 0;
    if (b.x0 == r.x0 - 1 && left) leak |= kLeakLeft;
    if (b.y0 == r.y0 - 1 && bottom) leak |= kLeakBottom;
    L.bbox = b;
    L.scissor_leak = leak;
    return true;
}

void line_planes(const StageVertex& v1, const StageVertex& v2, const VertexStage& stage,
                 const Draw& draw, bool provoking_first, FragmentOptions options, SetupList& list,
                 SetupPrimitive& prim) {
    // setup_line_coefficients: C arithmetic (no fusion: baseline x86-64), under FTZ.
    const Fp fp{options.flush_denormals};
    const auto f = [fp](float v) { return fp.f(v); };
    const float* a = v1.window.data();
    const float* b = v2.window.data();
    const float dx = f(a[0] - b[0]);
    const float dy = f(a[1] - b[1]);
    const float area = f(f(dx * dx) + f(dy * dy));
    const float oneoverarea = f(1.0f / area);
    float info_dx = dx;
    float info_dy = dy;
    if (options.multisample) {
        // The rectangular branch leaves the gradient along the segment as it is (the wide-line
        // scaling below belongs to the other branch of try_setup_line).
    } else if (std::fabs(dx) >= std::fabs(dy)) {
        const float dydx = f(dy / dx);
        info_dx = f(info_dx * f(1.0f + f(dydx * dydx)));
        info_dy = 0.0f;
    } else {
        const float dxdy = f(dx / dy);
        info_dx = 0.0f;
        info_dy = f(info_dy * f(1.0f + f(dxdy * dxdy)));
    }
    // linear_coef: setup->pixel_offset, which stays 0.5 under multisampling (only the
    // snap drops it there, and the shader then evaluates at the pixel centre): measured,
    // docs/precision.md "Multisampling".
    const LinearTerms t{f(a[0] - 0.5f), f(a[1] - 0.5f), info_dx, info_dy, oneoverarea};
    PlaneWriter out(list, prim, options.flush_denormals);
    out.depth(linear_coef(fp, t, a[2], b[2]), linear_coef(fp, t, a[3], b[3]), 0.0f);
    const auto c1 = stage.attributes(v1);
    const auto c2 = stage.attributes(v2);
    for (std::size_t k = 0; k < c1.size(); ++k) {
        switch (draw.state.shade) {
            case ShadeModel::Flat:
                out.constant(provoking_first ? c1[k] : c2[k]);
                break;
            case ShadeModel::Smooth:
                out.attribute(linear_coef(fp, t, f(c1[k] * a[3]), f(c2[k] * b[3])));
                break;  // perspective_coef
            case ShadeModel::NoPerspective:
                out.attribute(linear_coef(fp, t, c1[k], c2[k]));
                break;
        }
    }
}

std::optional<PointSetup> setup_point(const StageVertex& v, float size, const SetupParams& p) {
    // try_setup_point, quad points: fixed_width = MAX2(FIXED_ONE, subpixel_snap(size)),
    // origin subpixel_snap(pos - pixel_offset) - fixed_width / 2.
    size = std::min(size, 255.0f);  // LP_MAX_POINT_WIDTH
    const auto fw_snapped = snap(size, p.bits);
    const auto xs = snap(v.window[0] - p.pixel_center_offset, p.bits);
    const auto ys = snap(v.window[1] - p.pixel_center_offset, p.bits);
    if (!fw_snapped || !xs || !ys) return std::nullopt;
    const std::int32_t fw = std::max(1 << p.bits, *fw_snapped);
    const std::int32_t x0 = *xs - fw / 2;
    const std::int32_t y0 = *ys - fw / 2;
    const std::int32_t x1 = x0 + fw;
    const std::int32_t y1 = y0 + fw;
    static constexpr PointSetup kInitial{};  // a block copy, as setup_line's
    PointSetup s = kInitial;
    s.bits = p.bits;
    s.fixed_width = fw;
    // Left, right, bottom, top, oriented like a set-up triangle (interior where E > 0): the
    // planes of try_setup_point, with the tie rule's +1 on the owned sides.
    s.edges = {make_edge(x0, y0, x0, y1, p.tie_rule), make_edge(x1, y1, x1, y0, p.tie_rule),
               make_edge(x1, y0, x0, y0, p.tie_rule), make_edge(x0, y1, x1, y1, p.tie_rule)};
    const int bx1 = owns_right_edges(p.tie_rule) ? (x1 >> p.bits) : ceil_shift(x1, p.bits) - 1;
    const int by1 = owns_top_edges(p.tie_rule) ? (y1 >> p.bits) : ceil_shift(y1, p.bits) - 1;
    s.bbox = intersect({x0 >> p.bits, y0 >> p.bits, bx1, by1}, p.draw_region);
    if (s.bbox.empty()) return std::nullopt;
    // Points are trimmed to the scissor by pixels even under multisampling: they show no
    // leak of the scissor planes (measured, docs/precision.md "Multisampling").
    return s;
}

void point_planes(const StageVertex& v, const PointSetup& setup, const SetupParams& params,
                  const VertexStage& stage, const Draw& draw, FragmentOptions options,
                  SetupList& list, SetupPrimitive& prim) {
    // setup_point_coefficients: every attribute constant; smooth ones premultiplied by 1/w
    // (point_persp_coeff) and divided again per pixel by the constant 1/w plane.
    const auto f = [fp = Fp{options.flush_denormals}](float x) { return fp.f(x); };
    PlaneWriter out(list, prim, options.flush_denormals);
    out.depth({v.window[2], 0.0f, 0.0f}, {v.window[3], 0.0f, 0.0f}, 0.0f);
    const auto c = stage.attributes(v);
    for (std::size_t k = 0; k < c.size(); ++k) {
        switch (draw.state.shade) {
            case ShadeModel::Flat:
                out.constant(c[k]);
                break;
            case ShadeModel::Smooth:
                out.attribute({f(c[k] * v.window[3]), 0.0f, 0.0f});
                break;
            case ShadeModel::NoPerspective:
                out.attribute({c[k], 0.0f, 0.0f});
                break;
        }
    }
    if (!draw.samples_point_coords()) return;
    // lp_setup_point.c, texcoord_coef: s rises by FIXED_ONE / fixed_width a pixel to the right,
    // t the same upwards or downwards, both 0.5 at the vertex; x0 and y0 are the position less
    // setup->pixel_offset, which is half_pixel_center's even on a multisampled point (whose
    // pixels are then evaluated at their centres: half a pixel further on). The sums are
    // float, the subtraction from 0.5 double (its literal), stored as float. gl_PointCoord is
    // a perspective input there (LP_INTERP_PERSPECTIVE): every term times the vertex's 1/w,
    // divided by the 1/w plane per pixel as smooth attributes are.
    const float one = static_cast<float>(std::int32_t{1} << setup.bits);
    const float step = one / static_cast<float>(setup.fixed_width);
    const float x0 = v.window[0] - params.half_pixel_center;
    const float y0 = v.window[1] - params.half_pixel_center;
    // In an FBO gallium's y is GL's, so GL's upper-left origin is gallium's lower left
    // (st_atom_rasterizer.c flips sprite_coord_mode for FBOs): t falls as y rises.
    const float t_step =
        draw.state.texture->point_coord_origin == PointCoordOrigin::UpperLeft ? -step : step;
    const auto a0 = [](float dadx, float x, float dady, float y) {
        return static_cast<float>(0.5 - static_cast<double>(dadx * x + dady * y));
    };
    const float w0 = v.window[3];
    const auto persp = [&](Plane q) { return Plane{f(q.a0 * w0), f(q.dadx * w0), f(q.dady * w0)}; };
    out.attribute(persp({a0(step, x0, 0.0f, y0), step, 0.0f}));
    out.attribute(persp({a0(0.0f, x0, t_step, y0), 0.0f, t_step}));
}

}  // namespace refraster::detail
