#include "variants.hpp"

#include <glm/vec2.hpp>

namespace harness::study {

std::string Variant::coverage_name() const {
    switch (coverage) {
        case CoverageRule::Snapped:
            return "snap-" + std::to_string(subpixel_bits);
        case CoverageRule::Float32:
            return "float32";
        case CoverageRule::Float64:
            return "float64";
        case CoverageRule::Exact:
            return "exact";
    }
    return "?";
}

std::string Variant::interpolation_name() const {
    if (coverage == CoverageRule::Exact) return "exact";
    return fused ? "fused" : "unfused";
}

std::string Variant::depth_name() const {
    switch (depth) {
        case DepthFormat::Z16:
            return "z16";
        case DepthFormat::Z24:
            return "z24";
        case DepthFormat::Z32F:
            return "z32f";
    }
    return "?";
}

std::string Variant::name() const {
    return coverage_name() + "/" + interpolation_name() + "/" + depth_name();
}

std::vector<Variant> all_variants() {
    std::vector<Variant> out;
    std::vector<Variant> rules;
    for (int b : kSubpixelBits) rules.push_back({CoverageRule::Snapped, b, true, DepthFormat::Z24});
    rules.push_back({CoverageRule::Float32, 0, true, DepthFormat::Z24});
    rules.push_back({CoverageRule::Float64, 0, true, DepthFormat::Z24});
    for (Variant r : rules) {
        for (bool fused : {true, false}) {
            for (DepthFormat d : {DepthFormat::Z16, DepthFormat::Z24, DepthFormat::Z32F}) {
                r.fused = fused;
                r.depth = d;
                out.push_back(r);
            }
        }
    }
    for (DepthFormat d : {DepthFormat::Z16, DepthFormat::Z24, DepthFormat::Z32F})
        out.push_back({CoverageRule::Exact, 0, false, d});
    return out;
}

namespace {

refraster::DrawState draw_state(const Viewport& vp) {
    refraster::DrawState s;
    s.viewport = {0, 0, vp.width, vp.height};
    return s;
}

refraster::detail::PixelRect viewport_rect(const Viewport& vp) {
    return {0, 0, vp.width - 1, vp.height - 1};
}

// The oracle's float32 inputs: the workload's values, which are float32 by construction.
std::array<std::array<float, 4>, 3> positions(const ClipTriangle& t) {
    std::array<std::array<float, 4>, 3> p{};
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t c = 0; c < 4; ++c) {
            p[i][c] = static_cast<float>(t[i].position[c]);
            REFRASTER_ASSERT(static_cast<double>(p[i][c]) == t[i].position[c],
                             "the oracle's inputs are float32 values");
        }
    return p;
}

// GL's conversion of a normalised depth to an n-bit integer: round to nearest of z * (2^n - 1),
// the product in the variant's arithmetic (docs/precision.md, "Depth").
template <typename T>
double quantise(DepthFormat f, T z) {
    z = std::clamp(z, T{0}, T{1});
    switch (f) {
        case DepthFormat::Z16:
            return std::nearbyint(static_cast<double>(z * T{65535}));
        case DepthFormat::Z24:
            return std::nearbyint(static_cast<double>(z * T{16777215}));
        case DepthFormat::Z32F:
            return static_cast<double>(static_cast<float>(z));
    }
    return 0.0;
}

// A plane q(x, y) = q0 + dqdx (x - x0) + dqdy (y - y0) over window space.
template <typename T>
struct Plane {
    T q0{}, dqdx{}, dqdy{};
};

// The setup every unsnapped-arithmetic path shares: window positions, the doubled signed area,
// and the planes of 1/w, a/w and z.
template <typename T>
struct FloatSetup {
    std::array<glm::vec<2, T>, 3> p{};  // window positions
    T area{};                           // (p1 - p0) x (p2 - p0)
    Plane<T> oow, aow, z;

    // Window coordinates as Mesa's draw module computes them: x * (1/w), then scale and offset
    // (draw_cliptest_tmp.h, the viewport transform); in T.
    FloatSetup(const ClipTriangle& t, const Viewport& vp) {
        const T sx = T(vp.width) / T{2}, sy = T(vp.height) / T{2};
        std::array<T, 3> oows{}, aows{}, zs{};
        for (std::size_t i = 0; i < 3; ++i) {
            const auto& c = t[i].position;
            const T rw = T{1} / static_cast<T>(c[3]);
            p[i] = {static_cast<T>(c[0]) * rw * sx + sx, static_cast<T>(c[1]) * rw * sy + sy};
            oows[i] = rw;
            aows[i] = static_cast<T>(t[i].attribute) * rw;
            // Window depth for near 0 and far 1: z/w * 1/2 + 1/2.
            zs[i] = static_cast<T>(c[2]) * rw * T{0.5} + T{0.5};
        }
        const T dx1 = p[1].x - p[0].x, dy1 = p[1].y - p[0].y;
        const T dx2 = p[2].x - p[0].x, dy2 = p[2].y - p[0].y;
        area = dx1 * dy2 - dx2 * dy1;
        const auto plane = [&](const std::array<T, 3>& q) {
            const T dq1 = q[1] - q[0], dq2 = q[2] - q[0];
            Plane<T> r;
            r.q0 = q[0];
            r.dqdx = (dq1 * dy2 - dq2 * dy1) / area;
            r.dqdy = (dq2 * dx1 - dq1 * dx2) / area;
            return r;
        };
        if (area != T{0}) {
            oow = plane(oows);
            aow = plane(aows);
            z = plane(zs);
        }
    }

    T eval(const Plane<T>& q, T cx, T cy, bool fused) const {
        const T dx = cx - p[0].x, dy = cy - p[0].y;
        if (fused) return std::fma(q.dqdy, dy, std::fma(q.dqdx, dx, q.q0));
        return q.q0 + q.dqdx * dx + q.dqdy * dy;
    }

    PlaneValues values(int x, int y, bool fused, DepthFormat f) const {
        const T cx = static_cast<T>(x) + T{0.5}, cy = static_cast<T>(y) + T{0.5};
        const T a = eval(aow, cx, cy, fused) / eval(oow, cx, cy, fused);
        return {static_cast<double>(a), quantise<T>(f, eval(z, cx, cy, fused))};
    }
};

// Whether an edge (i -> j) of a counter-clockwise triangle owns the centres on it: left edges
// (the interior to the right: the edge runs down) and bottom edges (horizontal, the interior
// above: the edge runs right). GL 4.6, 14.6.1 asks for exactly one owner; this is the
// `left-bottom` rule of the llvmpipe-22.3 and gl-exact profiles.
template <typename T>
bool owns_edge(T dx, T dy) {
    return dy < T{0} || (dy == T{0} && dx > T{0});
}

struct Box {
    int x0, y0, x1, y1;
};

template <typename T>
Box bounding_box(const std::array<glm::vec<2, T>, 3>& p, const Viewport& vp) {
    T lx = p[0].x, hx = lx, ly = p[0].y, hy = ly;
    for (const auto& q : p) {
        lx = std::min(lx, q.x);
        hx = std::max(hx, q.x);
        ly = std::min(ly, q.y);
        hy = std::max(hy, q.y);
    }
    const auto lo = [](T v, int limit) {
        return static_cast<int>(
            std::clamp<double>(std::floor(static_cast<double>(v)) - 1, 0, limit - 1));
    };
    return {lo(lx, vp.width), lo(ly, vp.height), lo(hx + T{1}, vp.width), lo(hy + T{1}, vp.height)};
}

// Unsnapped coverage: edge functions in T at each centre.
template <typename T>
void rasterize_float(const Variant& v, const ClipTriangle& t, const Viewport& vp,
                     std::vector<Fragment>& out) {
    const FloatSetup<T> s(t, vp);
    if (!(s.area != T{0}) || !std::isfinite(static_cast<double>(s.area))) return;
    std::array<glm::vec<2, T>, 3> p = s.p;
    if (s.area < T{0}) std::swap(p[1], p[2]);
    std::array<bool, 3> owns{};
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& a = p[k];
        const auto& b = p[(k + 1) % 3];
        owns[k] = owns_edge(b.x - a.x, b.y - a.y);
    }
    const Box box = bounding_box(p, vp);
    for (int y = box.y0; y <= box.y1; ++y) {
        const T cy = static_cast<T>(y) + T{0.5};
        for (int x = box.x0; x <= box.x1; ++x) {
            const T cx = static_cast<T>(x) + T{0.5};
            bool in = true;
            for (std::size_t k = 0; k < 3 && in; ++k) {
                const auto& a = p[k];
                const auto& b = p[(k + 1) % 3];
                const T e = (b.x - a.x) * (cy - a.y) - (b.y - a.y) * (cx - a.x);
                in = e > T{0} || (e == T{0} && owns[k]);
            }
            if (!in) continue;
            const PlaneValues pv = s.values(x, y, v.fused, v.depth);
            out.push_back({x, y, pv.attribute, pv.depth});
        }
    }
}

// Snapped coverage: float32 window coordinates rounded to 2^-b pixel, edge functions exact in
// 128-bit integers; attributes and depth from the unsnapped float32 planes.
void rasterize_snapped(const Variant& v, const ClipTriangle& t, const Viewport& vp,
                       std::vector<Fragment>& out) {
    const FloatSetup<float> s(t, vp);
    const int b = v.subpixel_bits;
    REFRASTER_ASSERT(b >= 1 && b <= 16, "sub-pixel bits within the study's budget");
    const double one = std::ldexp(1.0, b);
    std::array<std::array<std::int64_t, 2>, 3> q{};
    for (std::size_t i = 0; i < 3; ++i) {
        for (int c = 0; c < 2; ++c) {
            const double w = static_cast<double>(s.p[i][c]);
            // Outside the budget (not finite, or beyond twice the largest viewport): refused,
            // as a snapped rasterizer must refuse what its integers cannot hold.
            if (!std::isfinite(w) || std::fabs(w) > std::ldexp(1.0, kMaxViewportBits + 1)) return;
            q[i][static_cast<std::size_t>(c)] = static_cast<std::int64_t>(std::nearbyint(w * one));
        }
    }
    __extension__ using I = __int128;
    const auto cross = [&](std::size_t i, std::size_t j, std::size_t k) {
        return I{q[j][0] - q[i][0]} * I{q[k][1] - q[i][1]} -
               I{q[j][1] - q[i][1]} * I{q[k][0] - q[i][0]};
    };
    const I area = cross(0, 1, 2);
    if (area == 0) return;
    if (area < 0) std::swap(q[1], q[2]);
    std::array<bool, 3> owns{};
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& a = q[k];
        const auto& c = q[(k + 1) % 3];
        owns[k] = owns_edge(c[0] - a[0], c[1] - a[1]);
    }
    std::int64_t lx = q[0][0], hx = lx, ly = q[0][1], hy = ly;
    for (const auto& p : q) {
        lx = std::min(lx, p[0]);
        hx = std::max(hx, p[0]);
        ly = std::min(ly, p[1]);
        hy = std::max(hy, p[1]);
    }
    const auto px = [&](std::int64_t f, int limit) {
        return static_cast<int>(std::clamp<std::int64_t>((f >> b) - 1, 0, limit - 1));
    };
    const Box box{px(lx, vp.width), px(ly, vp.height),
                  px(hx + 2 * (std::int64_t{1} << b), vp.width),
                  px(hy + 2 * (std::int64_t{1} << b), vp.height)};
    const std::int64_t half = std::int64_t{1} << (b - 1);
    for (int y = box.y0; y <= box.y1; ++y) {
        const std::int64_t cy = (std::int64_t{y} << b) + half;
        for (int x = box.x0; x <= box.x1; ++x) {
            const std::int64_t cx = (std::int64_t{x} << b) + half;
            bool in = true;
            for (std::size_t k = 0; k < 3 && in; ++k) {
                const auto& a = q[k];
                const auto& c = q[(k + 1) % 3];
                const I e = I{c[0] - a[0]} * I{cy - a[1]} - I{c[1] - a[1]} * I{cx - a[0]};
                in = e > 0 || (e == 0 && owns[k]);
            }
            if (!in) continue;
            PlaneValues pv{};
            if (s.area != 0.0f) pv = s.values(x, y, v.fused, v.depth);
            out.push_back({x, y, pv.attribute, pv.depth});
        }
    }
}

ExactFragment exact_at(const refraster::detail::ExactCoverage& e, const ClipTriangle& t, int x,
                       int y) {
    // The centre's homogeneous weights (sum b_i w_i = 1): the triangle's point there has the
    // clip-space barycentric weights b / sum b, and NDC depth sum b_i z_i.
    const auto b = e.weights(x, y);
    double a = 0.0, z = 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
        a += b[i] * t[i].attribute;
        z += b[i] * t[i].position[2];
    }
    return {x, y, a / (b[0] + b[1] + b[2]), z * 0.5 + 0.5};
}

template <typename T>
std::vector<ClipTriangle> clip_in(const ClipTriangle& t, double g, bool from_outside) {
    struct V {
        std::array<T, 4> p;
        T a;
    };
    std::vector<V> poly;
    for (const ClipVertex& c : t)
        poly.push_back({{static_cast<T>(c.position[0]), static_cast<T>(c.position[1]),
                         static_cast<T>(c.position[2]), static_cast<T>(c.position[3])},
                        static_cast<T>(c.attribute)});
    const T gt = static_cast<T>(g);
    // Planes as distances d(v) >= 0 inside: g w - x, g w + x, g w - y, g w + y.
    for (int plane = 0; plane < 4 && !poly.empty(); ++plane) {
        const std::size_t axis = plane < 2 ? 0 : 1;
        const T sign = plane % 2 == 0 ? T{-1} : T{1};
        const auto dist = [&](const V& v) { return gt * v.p[3] + sign * v.p[axis]; };
        std::vector<V> next;
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const V& a = poly[i];
            const V& b = poly[(i + 1) % poly.size()];
            const T da = dist(a), db = dist(b);
            if (da >= T{0}) next.push_back(a);
            if ((da >= T{0}) != (db >= T{0})) {
                // As Mesa's clipper (draw_pipe_clip.c, do_clip_tri and interp): the new vertex
                // is interpolated from the outside vertex towards the inside one,
                // f = d_out / (d_out - d_in), v = v_out + f (v_in - v_out), whichever way the
                // edge runs, so that both triangles sharing an edge get the same vertex.
                const bool a_out = from_outside ? da < T{0} : true;
                const V& out_v = a_out ? a : b;
                const V& in_v = a_out ? b : a;
                const T d_out = a_out ? da : db, d_in = a_out ? db : da;
                const T f = d_out / (d_out - d_in);
                V m;
                for (std::size_t c = 0; c < 4; ++c)
                    m.p[c] = out_v.p[c] + f * (in_v.p[c] - out_v.p[c]);
                m.a = out_v.a + f * (in_v.a - out_v.a);
                next.push_back(m);
            }
        }
        poly = std::move(next);
    }
    std::vector<ClipTriangle> out;
    const auto vertex = [](const V& v) {
        ClipVertex c;
        for (std::size_t k = 0; k < 4; ++k) c.position[k] = static_cast<double>(v.p[k]);
        c.attribute = static_cast<double>(v.a);
        return c;
    };
    for (std::size_t i = 1; i + 1 < poly.size(); ++i)
        out.push_back({vertex(poly[0]), vertex(poly[i]), vertex(poly[i + 1])});
    return out;
}

}  // namespace

std::vector<ClipTriangle> clip_triangle(const Variant& v, const ClipTriangle& t, double g,
                                        bool from_outside) {
    switch (v.coverage) {
        case CoverageRule::Snapped:
        case CoverageRule::Float32:
            return clip_in<float>(t, g, from_outside);
        case CoverageRule::Float64:
            return clip_in<double>(t, g, from_outside);
        case CoverageRule::Exact:
            return {t};
    }
    return {};
}

double quantise_depth(DepthFormat f, double z) {
    return quantise<double>(f, z);
}

double float32_ulps(double value, double exact) {
    // Below 2^-8 (an 8-bit channel's step) a relative measure means nothing for an attribute
    // in [0, 1]: errors there are counted in the ulps of 2^-8.
    const float e = static_cast<float>(std::max(std::fabs(exact), 0x1p-8));
    const float up = std::nextafter(std::fabs(e), std::numeric_limits<float>::infinity());
    const double ulp = static_cast<double>(up) - static_cast<double>(std::fabs(e));
    return std::fabs(value - exact) / ulp;
}

std::vector<ExactFragment> exact_fragments(const ClipTriangle& t, const Viewport& vp) {
    std::vector<ExactFragment> out;
    const refraster::detail::ExactCoverage e(positions(t), draw_state(vp), viewport_rect(vp),
                                             refraster::TieRule::LeftBottom);
    if (e.degenerate()) return out;
    const auto c = e.candidates();
    for (int y = c.y0; y <= c.y1; ++y)
        for (int x = c.x0; x <= c.x1; ++x)
            if (e.covers(x, y)) out.push_back(exact_at(e, t, x, y));
    return out;
}

void rasterize(const Variant& v, const ClipTriangle& t, const Viewport& vp,
               std::vector<Fragment>& out) {
    out.clear();
    switch (v.coverage) {
        case CoverageRule::Snapped:
            rasterize_snapped(v, t, vp, out);
            return;
        case CoverageRule::Float32:
            rasterize_float<float>(v, t, vp, out);
            return;
        case CoverageRule::Float64:
            rasterize_float<double>(v, t, vp, out);
            return;
        case CoverageRule::Exact:
            for (const ExactFragment& f : exact_fragments(t, vp))
                out.push_back({f.x, f.y, f.attribute, quantise_depth(v.depth, f.depth)});
            return;
    }
}

std::vector<std::optional<PlaneValues>> evaluate_at(const Variant& v, const ClipTriangle& t,
                                                    const Viewport& vp,
                                                    const std::vector<ExactFragment>& at) {
    std::vector<std::optional<PlaneValues>> out(at.size());
    const auto fill = [&](const auto& s) {
        if (s.area == 0) return;
        for (std::size_t i = 0; i < at.size(); ++i)
            out[i] = s.values(at[i].x, at[i].y, v.fused, v.depth);
    };
    switch (v.coverage) {
        case CoverageRule::Snapped:
        case CoverageRule::Float32:
            fill(FloatSetup<float>(t, vp));
            break;
        case CoverageRule::Float64:
            fill(FloatSetup<double>(t, vp));
            break;
        case CoverageRule::Exact:
            for (std::size_t i = 0; i < at.size(); ++i)
                out[i] = PlaneValues{at[i].attribute, quantise_depth(v.depth, at[i].depth)};
            break;
    }
    return out;
}

}  // namespace harness::study
