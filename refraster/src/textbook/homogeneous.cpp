#include "refraster/textbook/homogeneous.hpp"

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/big_int.hpp"
#include "snap.hpp"

namespace refraster::textbook {

namespace {

using detail::Int128;
using refraster::detail::BigInt;

constexpr double kMaxClip = 4096.0;  // |x|, |y|, |w| <= 2^12
constexpr int kMaxViewport = 1 << 12;

// A homogeneous window-space point scaled by 512: (512 X, 512 Y, 512 w), |.| < 2^35.
struct HVertex {
    std::int64_t x = 0;
    std::int64_t y = 0;
    std::int64_t w = 0;
};

std::int64_t snap_clip(double v) {
    REFRASTER_ASSERT(std::isfinite(v) && std::fabs(v) <= kMaxClip, "a clip coordinate within 2^12");
    return static_cast<std::int64_t>(std::llround(v * 256.0));
}

HVertex to_window(const ClipVertex& v, Viewport vp) {
    REFRASTER_ASSERT(std::abs(vp.x) <= kMaxViewport && std::abs(vp.y) <= kMaxViewport &&
                         vp.width >= 0 && vp.width <= kMaxViewport && vp.height >= 0 &&
                         vp.height <= kMaxViewport,
                     "a viewport within 2^12");
    const std::int64_t xs = snap_clip(v.x);
    const std::int64_t ys = snap_clip(v.y);
    const std::int64_t ws = snap_clip(v.w);
    // 512 (vx w + (x + w) width / 2) with x = xs / 256: 2 vx ws + (xs + ws) width.
    return {2 * vp.x * ws + (xs + ws) * vp.width, 2 * vp.y * ws + (ys + ws) * vp.height, 2 * ws};
}

struct Row3 {
    Int128 x = 0;
    Int128 y = 0;
    Int128 w = 0;
};

Row3 cross(const HVertex& a, const HVertex& b) {
    return {static_cast<Int128>(a.y) * b.w - static_cast<Int128>(a.w) * b.y,
            static_cast<Int128>(a.w) * b.x - static_cast<Int128>(a.x) * b.w,
            static_cast<Int128>(a.x) * b.y - static_cast<Int128>(a.y) * b.x};
}

// The pixel centre doubled: (2i + 1, 2j + 1, 2).
Int128 dot_centre(const Row3& r, int i, int j) {
    return r.x * (2 * static_cast<Int128>(i) + 1) + r.y * (2 * static_cast<Int128>(j) + 1) +
           r.w * 2;
}

int sign_of(Int128 v) {
    return v > 0 ? 1 : (v < 0 ? -1 : 0);
}

// The sign of an edge function at the nudged centre (+e, +e^2): its value, else its x slope,
// else its y slope.
int nudged_sign(Int128 value, Int128 slope_x, Int128 slope_y) {
    if (value != 0) return sign_of(value);
    if (slope_x != 0) return sign_of(slope_x);
    return sign_of(slope_y);
}

struct Setup {
    std::array<HVertex, 3> v{};
    std::array<Row3, 3> edge{};  // rows of the adjugate
    Int128 det = 0;
};

Setup setup(const ClipTriangle& t, Viewport vp) {
    Setup s;
    for (std::size_t i = 0; i < 3; ++i) s.v[i] = to_window(t[i], vp);
    for (std::size_t k = 0; k < 3; ++k) s.edge[k] = cross(s.v[(k + 1) % 3], s.v[(k + 2) % 3]);
    s.det = static_cast<Int128>(s.v[0].x) * s.edge[0].x +
            static_cast<Int128>(s.v[0].y) * s.edge[0].y +
            static_cast<Int128>(s.v[0].w) * s.edge[0].w;
    return s;
}

std::string format_int128(Int128 v) {
    // For traces: the value as a double is enough to read.
    return format_number(static_cast<double>(v));
}

void describe_input(Trace* trace, const ClipTriangle& t, Viewport vp, const char* name) {
    if (trace == nullptr) return;
    trace->algorithm = name;
    begin_part(trace, "triangle");
    // The projection of the vertices with w != 0, for orientation (w <= 0 ones are not drawn).
    for (std::size_t i = 0; i < 3; ++i) {
        const ClipVertex a = t[i];
        const ClipVertex b = t[(i + 1) % 3];
        if (a.w <= 0.0 || b.w <= 0.0) continue;
        trace->input.push_back({vp.x + (a.x / a.w + 1.0) * vp.width / 2.0,
                                vp.y + (a.y / a.w + 1.0) * vp.height / 2.0,
                                vp.x + (b.x / b.w + 1.0) * vp.width / 2.0,
                                vp.y + (b.y / b.w + 1.0) * vp.height / 2.0, "edge"});
    }
}

}  // namespace

Raster homogeneous_rasterize(const ClipTriangle& triangle, Viewport viewport, int width, int height,
                             bool w_positive_test, Trace* trace) {
    describe_input(trace, triangle, viewport,
                   w_positive_test ? "homogeneous rasterization"
                                   : "homogeneous rasterization without the w > 0 test");
    set_pseudo_code(trace, {"M = the clip-space vertices (x, y, w) as columns: the edge "
                            "functions are the rows of adj(M), det(M) gives their sign",
                            "for each row j, for each pixel centre (i, j):",
                            "    evaluate the three edge functions at the centre (x, y, 1)",
                            std::string("    covered when all three are > 0 (times the sign of "
                                        "det)") +
                                (w_positive_test ? "" : ", or all three < 0")});
    Raster out(width, height);
    const Setup s = setup(triangle, viewport);
    const int det_sign = sign_of(s.det);
    if (trace != nullptr) {
        Step& step = add_step(
            *trace, "the edge functions: rows of adj(M), det(M) " +
                        std::string(det_sign > 0 ? "> 0" : (det_sign < 0 ? "< 0" : "= 0")));
        step.line = 1;
        step.state.push_back({"det", format_int128(s.det)});
        for (std::size_t k = 0; k < 3; ++k) {
            step.state.push_back({"e" + std::to_string(k), format_int128(s.edge[k].x) + " x + " +
                                                               format_int128(s.edge[k].y) +
                                                               " y + " +
                                                               format_int128(s.edge[k].w)});
        }
    }
    if (det_sign == 0) return out;
    for (int j = 0; j < height; ++j) {
        Step* step = nullptr;
        if (trace != nullptr) {
            step = &add_step(*trace, "row " + std::to_string(j));
            step->line = 4;
        }
        for (int i = 0; i < width; ++i) {
            std::array<int, 3> sg{};
            Int128 sum = 0;
            for (std::size_t k = 0; k < 3; ++k) {
                const Int128 e = dot_centre(s.edge[k], i, j);
                sum += e;
                sg[k] = det_sign * nudged_sign(e, s.edge[k].x, s.edge[k].y);
            }
            const bool internal = sg[0] > 0 && sg[1] > 0 && sg[2] > 0;
            const bool external = sg[0] < 0 && sg[1] < 0 && sg[2] < 0;
            const bool covered = internal || (!w_positive_test && external);
            if (!covered) continue;
            out.set(i, j, 1.0);
            if (step != nullptr) {
                step->pixels.push_back({i, j, 1.0});
                if (step->state.empty()) {
                    // 1/w at the first covered centre: sum / det times 256.
                    step->state.push_back({"1/w at " + format_pixel(i, j),
                                           format_number(256.0 * static_cast<double>(sum) /
                                                         static_cast<double>(s.det))});
                    step->state.push_back({"part", internal ? "w > 0" : "external, w < 0"});
                }
            }
        }
        if (step != nullptr) {
            step->title += ": " + std::to_string(step->pixels.size()) + " pixels";
        }
    }
    return out;
}

Raster clip_then_rasterize(const ClipTriangle& triangle, Viewport viewport, double near_w,
                           int width, int height, Trace* trace) {
    describe_input(trace, triangle, viewport, "clip, then rasterize");
    set_pseudo_code(trace, {"clip the triangle against the plane w = near (Sutherland-Hodgman): "
                            "a polygon",
                            "for each row j, for each pixel centre: covered when inside every "
                            "edge of the projected polygon (GL's rule)"});
    Raster out(width, height);
    REFRASTER_ASSERT(near_w > 0.0, "a near plane at w > 0");
    const std::int64_t near = 2 * snap_clip(near_w);  // in the 512 w scale of HVertex
    std::array<HVertex, 3> v{};
    for (std::size_t i = 0; i < 3; ++i) v[i] = to_window(triangle[i], viewport);
    // Sutherland-Hodgman against w >= near. A crossing point a + t (b - a), t = da / (da - db),
    // is kept as the integer vector da b - db a (times da - db), negated when da - db < 0 so
    // that its w stays positive: |.| < 2^23 * 2^35 * 2 = 2^59.
    std::vector<HVertex> poly;
    for (std::size_t i = 0; i < 3; ++i) {
        const HVertex& a = v[i];
        const HVertex& b = v[(i + 1) % 3];
        const std::int64_t da = a.w - near;
        const std::int64_t db = b.w - near;
        if (da >= 0) poly.push_back(a);
        if ((da > 0 && db < 0) || (da < 0 && db > 0)) {
            const std::int64_t s = da - db > 0 ? 1 : -1;
            poly.push_back(
                {s * (da * b.x - db * a.x), s * (da * b.y - db * a.y), s * (da * b.w - db * a.w)});
        }
    }
    if (trace != nullptr) {
        Step& step = add_step(*trace, "clip against w = " + format_number(near_w) + ": " +
                                          std::to_string(poly.size()) + " vertices");
        step.line = 1;
        for (std::size_t k = 0; k < poly.size(); ++k) {
            const HVertex& p = poly[k];
            const HVertex& q = poly[(k + 1) % poly.size()];
            const auto px = static_cast<double>(p.x) / static_cast<double>(p.w);
            const auto py = static_cast<double>(p.y) / static_cast<double>(p.w);
            const auto qx = static_cast<double>(q.x) / static_cast<double>(q.w);
            const auto qy = static_cast<double>(q.y) / static_cast<double>(q.w);
            step.overlay.push_back({px, py, qx, qy, "clip"});
            step.state.push_back({"v" + std::to_string(k),
                                  "(" + format_number(px) + ", " + format_number(py) + ")"});
        }
    }
    if (poly.size() < 3) return out;
    // The edge rows P x Q of the clipped polygon, in 1024-bit integers (entries below 2^119).
    struct BigRow {
        BigInt x, y, w;
    };
    std::vector<BigRow> edges;
    for (std::size_t k = 0; k < poly.size(); ++k) {
        const HVertex& p = poly[k];
        const HVertex& q = poly[(k + 1) % poly.size()];
        const auto b = [](std::int64_t a) { return BigInt::from_int(a); };
        edges.push_back({b(p.y) * b(q.w) - b(p.w) * b(q.y), b(p.w) * b(q.x) - b(p.x) * b(q.w),
                         b(p.x) * b(q.y) - b(p.y) * b(q.x)});
    }
    // The orientation: every fan triangle of the convex polygon has the same sign (or 0), so
    // the sign of their sum. det[P0, Pk, Pk+1] = P0 . (Pk x Pk+1).
    BigInt orientation;
    const BigInt p0x = BigInt::from_int(poly[0].x);
    const BigInt p0y = BigInt::from_int(poly[0].y);
    const BigInt p0w = BigInt::from_int(poly[0].w);
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        orientation = orientation + p0x * edges[k].x + p0y * edges[k].y + p0w * edges[k].w;
    }
    const int orient_sign = orientation.sign();
    if (orient_sign == 0) return out;
    for (int j = 0; j < height; ++j) {
        Step* step = trace != nullptr ? &add_step(*trace, "row " + std::to_string(j)) : nullptr;
        if (step != nullptr) step->line = 2;
        const BigInt cy = BigInt::from_int(2 * std::int64_t{j} + 1);
        const BigInt two = BigInt::from_int(2);
        for (int i = 0; i < width; ++i) {
            const BigInt cx = BigInt::from_int(2 * std::int64_t{i} + 1);
            bool inside = true;
            for (const BigRow& e : edges) {
                const int value = (e.x * cx + e.y * cy + e.w * two).sign();
                const int sg = value != 0 ? value : (e.x.sign() != 0 ? e.x.sign() : e.y.sign());
                if (orient_sign * sg <= 0) {
                    inside = false;
                    break;
                }
            }
            if (!inside) continue;
            out.set(i, j, 1.0);
            if (step != nullptr) step->pixels.push_back({i, j, 1.0});
        }
        if (step != nullptr) step->title += ": " + std::to_string(step->pixels.size()) + " pixels";
    }
    return out;
}

HomogeneousDifference explain_difference(const ClipTriangle& triangle, Viewport viewport,
                                         double near_w, int x, int y) {
    const Setup s = setup(triangle, viewport);
    const int det_sign = sign_of(s.det);
    if (det_sign == 0) return HomogeneousDifference::Unexplained;
    // The categories by the nudged signs, as both rasterizers decide; OnEdge for a centre on
    // an edge line that neither category takes.
    std::array<int, 3> sg{};
    bool on_edge = false;
    Int128 sum = 0;
    for (std::size_t k = 0; k < 3; ++k) {
        const Int128 e = dot_centre(s.edge[k], x, y);
        sum += e;
        on_edge = on_edge || e == 0;
        sg[k] = det_sign * nudged_sign(e, s.edge[k].x, s.edge[k].y);
    }
    if (sg[0] < 0 && sg[1] < 0 && sg[2] < 0) return HomogeneousDifference::ExternalTriangle;
    if (sg[0] > 0 && sg[1] > 0 && sg[2] > 0) {
        // w at the centre is det / (256 sum) > 0 (doubled centre, 512-scaled vertices);
        // w <= near_w = near_s / 256 exactly when |det| <= |sum| near_s (below 2^108).
        const Int128 near_s = snap_clip(near_w);
        const Int128 abs_det = s.det < 0 ? -s.det : s.det;
        const Int128 abs_sum = sum < 0 ? -sum : sum;
        if (abs_det <= abs_sum * near_s) return HomogeneousDifference::BetweenEyeAndNearPlane;
    }
    if (on_edge) return HomogeneousDifference::OnEdge;
    return HomogeneousDifference::Unexplained;
}

const char* to_string(HomogeneousDifference d) {
    switch (d) {
        case HomogeneousDifference::ExternalTriangle:
            return "the external triangle (w < 0)";
        case HomogeneousDifference::BetweenEyeAndNearPlane:
            return "between the eye and the near plane (0 < w <= near)";
        case HomogeneousDifference::OnEdge:
            return "on an edge";
        case HomogeneousDifference::Unexplained:
            return "unexplained";
    }
    return "unexplained";
}

}  // namespace refraster::textbook
