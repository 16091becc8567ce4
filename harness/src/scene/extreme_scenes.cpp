#include "harness/extreme_scenes.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <ostream>
#include <random>
#include <stdexcept>

#include "harness/files.hpp"
#include "harness/scene_text.hpp"
#include "harness/scene_writer.hpp"

namespace harness {

namespace {

using refraster::BlendPreset;
using refraster::ColorFormat;
using refraster::CompareFunc;
using refraster::CullMode;
using refraster::DepthFormat;
using refraster::PrimitiveType;
using refraster::ShadeModel;

constexpr float kMax = std::numeric_limits<float>::max();
constexpr float kDenormMin = std::numeric_limits<float>::denorm_min();
constexpr float kNormMin = std::numeric_limits<float>::min();

class Rng {
  public:
    explicit Rng(std::uint64_t seed) : g_(seed) {}
    float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(g_); }
    int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(g_); }
    bool chance(float p) { return uniform(0.0f, 1.0f) < p; }
    float sign() { return chance(0.5f) ? 1.0f : -1.0f; }
    template <class T>
    T pick(std::initializer_list<T> v) {
        return *(v.begin() + integer(0, static_cast<int>(v.size()) - 1));
    }
    // A float of magnitude 10^e with e uniform in [lo, hi], either sign, capped at the largest.
    float magnitude(float lo, float hi) {
        const double v = std::pow(10.0, double{uniform(lo, hi)});
        return sign() * static_cast<float>(std::min(v, double{kMax}));
    }
    // A subnormal float of either sign.
    float subnormal() {
        const auto bits = static_cast<std::uint32_t>(integer(1, (1 << 23) - 1));
        return sign() * std::bit_cast<float>(bits);
    }
    std::array<float, 4> colour() {
        return {uniform(0, 1), uniform(0, 1), uniform(0, 1), uniform(0.25f, 1)};
    }

  private:
    std::mt19937_64 g_;
};

SceneFile base(const std::string& kind, std::string description, std::uint32_t w, std::uint32_t h,
               ColorFormat color = ColorFormat::Rgba8, DepthFormat depth = DepthFormat::None) {
    SceneFile s;
    s.name = "extreme." + kind;
    s.description = std::move(description);
    s.target = {w, h, color, depth, 1};
    s.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};
    s.clear.depth = 1.0f;
    return s;
}

SceneDraw draw_of(const SceneFile& s, PrimitiveType p, VertexSpace space) {
    SceneDraw d;
    d.primitive = p;
    d.space = space;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(s.target.width),
                        static_cast<std::int32_t>(s.target.height)};
    return d;
}

void clip_vertex(SceneDraw& d, std::array<float, 4> p, std::array<float, 4> c) {
    SceneVertex v;
    v.position = p;
    v.position_size = 4;
    v.color = c;
    d.vertices.push_back(v);
}

void window_vertex(SceneDraw& d, float x, float y, float z, std::array<float, 4> c) {
    SceneVertex v;
    v.position = {x, y, z, 1.0f};
    v.position_size = 3;
    v.color = c;
    d.vertices.push_back(v);
}

// A clip-space vertex inside the view volume at NDC (x, y, z) and the given w.
std::array<float, 4> inside(Rng& r, float w, float range = 0.9f) {
    return {r.uniform(-range, range) * w, r.uniform(-range, range) * w, r.uniform(-0.9f, 0.9f) * w,
            w};
}

CompareFunc any_compare(Rng& r) {
    return r.pick({CompareFunc::Less, CompareFunc::Lequal, CompareFunc::Greater,
                   CompareFunc::Gequal, CompareFunc::Equal, CompareFunc::NotEqual,
                   CompareFunc::Always});
}

// Triangles with one component of some vertices set by `extreme` (index 0..3 of the clip
// position), the others inside the view volume; smooth colours, depth tested.
SceneFile extreme_component(const std::string& kind, std::string description, Rng& r,
                            std::size_t component, const std::function<float(Rng&)>& extreme) {
    SceneFile s = base(kind, std::move(description), 64, 64, ColorFormat::Rgba8, DepthFormat::Z24);
    for (int t = 0; t < 12; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.depth_test = CompareFunc::Lequal;
        d.state.cull = r.pick({CullMode::None, CullMode::None, CullMode::Back});
        const int n_extreme = r.integer(1, 3);
        for (int k = 0; k < 3; ++k) {
            auto p = inside(r, r.uniform(0.5f, 2.0f));
            if (k < n_extreme) {
                p[component] = extreme(r);
                if (component == 3 && r.chance(0.5f)) {
                    // Keep the vertex's direction: x, y, z scaled with w.
                    const float w = p[3];
                    p = {r.uniform(-0.9f, 0.9f) * w, r.uniform(-0.9f, 0.9f) * w,
                         r.uniform(-0.9f, 0.9f) * w, w};
                    for (std::size_t c = 0; c < 3; ++c) {
                        if (!std::isfinite(p[c])) p[c] = std::copysign(kMax, p[c]);
                    }
                }
            }
            clip_vertex(d, p, r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

SceneFile huge(const std::string& axis, std::size_t component, Rng& r) {
    return extreme_component(
        "huge_coordinates_" + axis,
        "Triangles with one to three vertices whose clip " + axis +
            " is up to float's largest value (10^30 to 3.4*10^38, either sign), the rest "
            "inside the view volume: clipping distances near overflow and window "
            "coordinates that are infinite or NaN before the clipper removes them.",
        r, component,
        [](Rng& g) { return g.chance(0.2f) ? g.sign() * kMax : g.magnitude(30, 38.5f); });
}

SceneFile subnormal(const std::string& axis, std::size_t component, Rng& r) {
    return extreme_component(
        "subnormal_coordinates_" + axis,
        "Triangles with one to three vertices whose clip " + axis +
            " is subnormal (or the smallest normal float): llvmpipe flushes denormal "
            "inputs and results to zero, so such a w means w = 0.",
        r, component, [](Rng& g) {
            const int k = g.integer(0, 3);
            return k == 0 ? g.sign() * kDenormMin : k == 1 ? g.sign() * kNormMin : g.subnormal();
        });
}

SceneFile tiny_w(const std::string& kind, Rng& r, int signs) {
    SceneFile s = base(
        kind,
        signs == 0
            ? "Triangles whose vertices have a positive w between 10^-38 and 10^-6, x and y up "
              "to a few times w: 1/w near overflow, NDC far outside and inside."
        : signs == 1
            ? "Triangles with vertices of tiny negative w (-10^-38 to -10^-6): behind the eye, "
              "clipped away or clipped to a sliver."
            : "Triangles mixing tiny positive and tiny negative w in one triangle: the "
              "clipper's w = 0 crossing at the smallest scales.",
        64, 64, ColorFormat::Rgba8, DepthFormat::Z16);
    for (int t = 0; t < 12; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.depth_test = CompareFunc::Less;
        for (int k = 0; k < 3; ++k) {
            float w = std::fabs(r.magnitude(-38, -6));
            if (signs == 1 || (signs == 2 && k == 1) || (signs == 2 && k == 2 && r.chance(0.5f)))
                w = -w;
            if (k == 0 && signs != 1 && r.chance(0.5f)) w = r.uniform(0.5f, 2.0f);
            const float a = std::fabs(w);
            clip_vertex(d,
                        {r.uniform(-3, 3) * a, r.uniform(-3, 3) * a, r.uniform(-0.9f, 0.9f) * a, w},
                        r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

SceneFile guard_band(const std::string& kind, Rng& r, bool both) {
    SceneFile s = base(
        kind,
        both ? "Triangles with vertices at x/w and y/w from 10^4 to 10^30: far beyond any guard "
               "band in both directions, clipped back into the viewport."
             : "Triangles with vertices at x/w from 10^4 to 10^30, y inside: far beyond any guard "
               "band, clipped back into the viewport.",
        64, 64, ColorFormat::Rgba8, DepthFormat::Z24);
    for (int t = 0; t < 12; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.depth_test = CompareFunc::Less;
        for (int k = 0; k < 3; ++k) {
            auto p = inside(r, r.uniform(0.5f, 2.0f));
            if (k < 2) {
                p[0] = r.magnitude(4, 30) * p[3];
                if (both) p[1] = r.magnitude(4, 30) * p[3];
            }
            clip_vertex(d, p, r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

SceneFile viewport(const std::string& kind, Rng& r, int variant) {
    static const char* text[] = {
        "A 16384x16384 viewport at (-32768, -32768), the smallest origin: window coordinates near "
        "-32768, all "
        "off a 64x64 target; nothing may be drawn, and the snapped positions stay in range.",
        "A 16384x16384 viewport at (-16320, -16320) whose top right corner reaches into a 64x64 "
        "target: "
        "window coordinates up to 16384 away from the drawn pixels.",
        "A 16384x16384 viewport at the largest origin (32767, 32767), off the target: window "
        "coordinates near "
        "49151, the snapped bit budget's limit.",
        "A 16384-wide, 1-high viewport at x = -16320, y = 20, and a 1-wide, 16384-high one: "
        "extreme aspect ratios."};
    SceneFile s = base(kind, text[variant], 64, 64, ColorFormat::Rgba8, DepthFormat::Z24);
    const std::array<refraster::Rect, 4> vps{refraster::Rect{-32768, -32768, 16384, 16384},
                                             refraster::Rect{-16320, -16320, 16384, 16384},
                                             refraster::Rect{32767, 32767, 16384, 16384},
                                             refraster::Rect{-16320, 20, 16384, 1}};
    for (int t = 0; t < 16; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.viewport = vps[static_cast<std::size_t>(variant)];
        if (variant == 3 && t % 2 == 1) d.state.viewport = {30, -16320, 1, 16384};
        d.state.depth_test = CompareFunc::Less;
        for (int k = 0; k < 3; ++k) {
            auto p = inside(r, r.uniform(0.5f, 2.0f), variant == 1 ? 1.0f : 1.2f);
            // Most of the area near the corner that the target sees (NDC (1, 1) for variant 1).
            if (variant == 1 && r.chance(0.7f)) {
                p[0] = r.uniform(0.99f, 1.01f) * p[3];
                p[1] = r.uniform(0.99f, 1.01f) * p[3];
            }
            clip_vertex(d, p, r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

SceneFile largest_target(Rng& r) {
    SceneFile s = base(
        "largest_target",
        "The largest target the format allows, 16384x4096 = 67,108,864 pixels, with a few small "
        "triangles and points at its corners and centre (pixel coordinates near 16383 and 4095).",
        16384, 4096);
    s.clear.color = {0.25f, 0.5f, 0.75f, 1.0f};
    SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Window);
    const std::array<std::array<float, 2>, 5> at{
        {{2, 2}, {16370, 2}, {2, 4082}, {16370, 4082}, {8190, 2046}}};
    for (const auto& a : at) {
        const float x = a[0] + static_cast<float>(r.integer(0, 4)) * 0.125f;
        const float y = a[1] + static_cast<float>(r.integer(0, 4)) * 0.125f;
        window_vertex(d, x, y, 0, r.colour());
        window_vertex(d, x + 11.5f, y + 0.25f, 0, r.colour());
        window_vertex(d, x + 0.75f, y + 11.75f, 0, r.colour());
    }
    s.draws.push_back(std::move(d));
    SceneDraw p = draw_of(s, PrimitiveType::Points, VertexSpace::Window);
    p.state.point_size = 5;
    window_vertex(p, 16383.5f, 4095.5f, 0, r.colour());
    window_vertex(p, 0.5f, 0.5f, 0, r.colour());
    s.draws.push_back(std::move(p));
    return s;
}

SceneFile long_target(const std::string& kind, Rng& r, bool wide) {
    SceneFile s =
        base(kind,
             wide ? "A 16384x4 target with triangles and a line spanning its whole width."
                  : "A 4x16384 target with triangles and a line spanning its whole height.",
             wide ? 16384 : 4, wide ? 4 : 16384, ColorFormat::Rgba8, DepthFormat::Z16);
    const auto pos = [&](float along, float across) {
        return wide ? std::array<float, 2>{along, across} : std::array<float, 2>{across, along};
    };
    SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Window);
    d.state.depth_test = CompareFunc::Less;
    for (int t = 0; t < 4; ++t) {
        const float a0 = r.uniform(-100, 200), a1 = r.uniform(16200, 16500),
                    am = r.uniform(0, 16384);
        const auto p0 = pos(a0, r.uniform(-1, 5));
        const auto p1 = pos(a1, r.uniform(-1, 5));
        const auto p2 = pos(am, r.uniform(-1, 5));
        window_vertex(d, p0[0], p0[1], r.uniform(0, 1), r.colour());
        window_vertex(d, p1[0], p1[1], r.uniform(0, 1), r.colour());
        window_vertex(d, p2[0], p2[1], r.uniform(0, 1), r.colour());
    }
    s.draws.push_back(std::move(d));
    SceneDraw l = draw_of(s, PrimitiveType::Lines, VertexSpace::Window);
    const auto q0 = pos(0.25f, 1.75f);
    const auto q1 = pos(16383.75f, 2.25f);
    window_vertex(l, q0[0], q0[1], 0, r.colour());
    window_vertex(l, q1[0], q1[1], 0, r.colour());
    s.draws.push_back(std::move(l));
    return s;
}

// Slivers 16,000 pixels long, less than a pixel thick, through rows of pixel centres.
SceneFile sliver(const std::string& kind, Rng& r, int dir) {
    static const char* text[] = {
        "Horizontal slivers 16,000 pixels long and a few hundredths of a pixel thick, through and "
        "beside rows "
        "of pixel centres, on a 16384x8 target.",
        "Vertical slivers 16,000 pixels long and a few hundredths of a pixel thick, on an 8x16384 "
        "target.",
        "Slivers 16,000 pixels long rising 6 pixels, on a 16384x8 target: long shallow edges "
        "stepping across "
        "pixel centres."};
    const bool vertical = dir == 1;
    SceneFile s = base(kind, text[dir], vertical ? 8 : 16384, vertical ? 16384 : 8);
    for (int t = 0; t < 8; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Window);
        d.state.shade = r.chance(0.5f) ? ShadeModel::Flat : ShadeModel::Smooth;
        const float a0 = static_cast<float>(r.integer(0, 383)) + 0.5f +
                         static_cast<float>(r.integer(-4, 4)) / 64.0f;
        const float a1 = a0 + 16000.0f;
        const float c = static_cast<float>(r.integer(1, 6)) + 0.5f +
                        static_cast<float>(r.integer(-8, 8)) / 1024.0f;
        const float thick = static_cast<float>(r.integer(1, 40)) / 1024.0f;
        const float rise = dir == 2 ? 6.0f : 0.0f;
        const float c0 = dir == 2 ? 0.5f + static_cast<float>(r.integer(-8, 8)) / 1024.0f : c;
        std::array<std::array<float, 2>, 3> p{
            {{a0, c0}, {a1, c0 + rise}, {r.uniform(a0, a1), c0 + rise * 0.5f + thick}}};
        if (r.chance(0.5f)) p[2][1] = c0 + rise * 0.5f - thick;
        for (auto& q : p) {
            if (vertical) std::swap(q[0], q[1]);
            window_vertex(d, q[0], q[1], 0, r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

// Triangles collinear in float window coordinates but not after snapping: the three vertices lie
// on one line with exact float products, so setup's area is 0, 1/area infinite and every plane
// NaN, while the snapped triangle covers a row of pixel centres. Long lists of them, over
// ordinary triangles that give the depth buffer varied values.
SceneFile nan_planes(const std::string& kind, Rng& r, DepthFormat depth, ColorFormat color) {
    SceneFile s = base(
        kind,
        "Long triangle lists of triangles collinear in float window coordinates but not after "
        "snapping: setup's float area is 0, so every attribute plane (z, 1/w, colour) is NaN; "
        "llvmpipe's depth clamp turns the NaN depth into the far value. Random compare functions "
        "and shading, over ordinary triangles.",
        64, 64, color, depth);
    s.clear.depth = r.pick({1.0f, 0.5f, 0.0f});
    for (int dn = 0; dn < 6; ++dn) {
        SceneDraw under = draw_of(s, PrimitiveType::Triangles, VertexSpace::Window);
        under.state.depth_test = CompareFunc::Always;
        for (int k = 0; k < 3; ++k)
            window_vertex(under, r.uniform(-8, 72), r.uniform(-8, 72), r.uniform(0, 1), r.colour());
        s.draws.push_back(std::move(under));

        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Window);
        d.state.depth_test = any_compare(r);
        d.state.depth_write = r.chance(0.8f);
        d.state.shade = r.pick({ShadeModel::Smooth, ShadeModel::Flat, ShadeModel::NoPerspective});
        if (color == ColorFormat::Rgba32f)
            d.state.blend = r.pick({BlendPreset::None, BlendPreset::Alpha, BlendPreset::Add});
        if (r.chance(0.3f))
            d.state.polygon_offset = refraster::PolygonOffset{r.uniform(-2, 2), r.uniform(-4, 4)};
        for (int t = 0; t < 100; ++t) {
            // Points along a line of slope -2/1024 per L pixels: y offsets 3, 1, -1 (in 1/1024 px)
            // snap to 1, 0, 0 (in 1/256 px), so the snapped triangle has a horizontal bottom edge
            // on a row of centres.
            const float L = static_cast<float>(r.integer(1, 12));
            const float y = static_cast<float>(r.integer(0, 63)) + 0.5f;
            const float x =
                static_cast<float>(r.integer(0, 63)) + static_cast<float>(r.integer(0, 3)) * 0.25f;
            const float m =
                static_cast<float>(r.integer(-1, 1)) * 4.0f / 1024.0f;  // shift by whole subpixels
            std::array<std::array<float, 3>, 3> p{
                {{x - L, y + m + 3.0f / 1024.0f, r.uniform(0, 1)},
                 {x, y + m + 1.0f / 1024.0f, r.uniform(0, 1)},
                 {x + L, y + m - 1.0f / 1024.0f, r.uniform(0, 1)}}};
            if (r.chance(0.5f)) std::swap(p[0], p[2]);
            if (r.chance(0.5f)) std::swap(p[1], p[2]);
            for (const auto& q : p) window_vertex(d, q[0], q[1], q[2], r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

// Long draws (more than 4,095 vertices) of slivers with random orientation noise, so the
// draw module's float cull and llvmpipe's fixed-point cull disagree on some of them; vertices
// outside the view volume in some segments only, so that only those segments go through the
// draw pipeline's float cull.
// Indices 0 .. n-1: the same primitives as the unindexed draw, through glDrawElements.
std::vector<std::uint32_t> identity_indices(std::size_t n) {
    std::vector<std::uint32_t> v(n);
    for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint32_t>(i);
    return v;
}

SceneFile segments(const std::string& kind, Rng& r, PrimitiveType prim, bool first,
                   bool indexed = false) {
    const char* what = prim == PrimitiveType::Triangles       ? "a triangle list of 4,800 vertices"
                       : prim == PrimitiveType::TriangleStrip ? "a triangle strip of 9,000 vertices"
                                                              : "a triangle fan of 9,000 vertices";
    SceneFile s =
        base(kind,
             std::string("Culling on, ") + what +
                 " of slivers whose float and fixed-point orientation disagree now and then, and "
                 "vertices outside the view volume in some of the draw module's " +
                 (indexed ? std::string("segments only, drawn with 32-bit indices, which split at "
                                        "vsplit's 1,024-vertex segment size")
                          : std::string("4,096-vertex segments only")) +
                 ": the float cull of the draw pipeline applies to exactly those segments." +
                 (first ? " First-vertex convention." : ""),
             256, 64);
    SceneDraw d = draw_of(s, prim, VertexSpace::Window);
    d.state.cull = r.pick({CullMode::Back, CullMode::Front});
    d.state.front_face = r.chance(0.5f) ? refraster::FrontFace::Ccw : refraster::FrontFace::Cw;
    d.state.shade = ShadeModel::Flat;
    if (first) d.state.provoking_vertex = refraster::ProvokingVertex::First;
    const std::size_t n = prim == PrimitiveType::Triangles ? 4800 : 9000;
    // Which of the vertices are pushed out of the view volume (past the right edge).
    // Indexed: inside the second 1,024-vertex segment, so that only its triangles take the
    // float cull (one 4,096-vertex segment would put the whole start of the draw there).
    const std::size_t out_at = static_cast<std::size_t>(
        indexed ? r.integer(1100, 1900) : r.integer(4200, static_cast<int>(n) - 40));
    const auto colour_of = [](std::size_t i) {
        return std::array<float, 4>{static_cast<float>(i % 251) / 255.0f,
                                    static_cast<float>((i / 251) % 251) / 255.0f,
                                    static_cast<float>((i * 7) % 256) / 255.0f, 1.0f};
    };
    const auto jitter = [&] { return static_cast<float>(r.integer(-3, 3)) / 1024.0f; };
    if (prim == PrimitiveType::Triangles) {
        for (std::size_t t = 0; t < n / 3; ++t) {
            const float y = static_cast<float>(r.integer(0, 63)) + 0.5f;
            // Inside the viewport (x0 + L < 256): only the vertices chosen below leave it.
            const float x0 =
                static_cast<float>(r.integer(0, 230)) + static_cast<float>(r.integer(0, 7)) / 8.0f;
            const float L = static_cast<float>(r.integer(2, 16));
            std::array<std::array<float, 2>, 3> p{
                {{x0, y + jitter()},
                 {x0 + L, y + jitter()},
                 {x0 + static_cast<float>(r.integer(1, 7)) * L / 8.0f, y + jitter()}}};
            if (r.chance(0.5f)) {
                // A sliver whose orientation flips in snapping: ends 3/1024 px above and below the
                // row (snapped to +1 and -1 subpixel), the third vertex a quarter along, 2/1024 px
                // up: above the float line (1.5/1024 there) but snapped (2049.5 -> 2048, even)
                // below the snapped one.
                p = {{{x0, y + 3.0f / 1024.0f},
                      {x0 + L, y - 3.0f / 1024.0f},
                      {x0 + L / 4.0f, y + 2.0f / 1024.0f}}};
            }
            if (r.chance(0.5f)) std::swap(p[0], p[1]);
            for (std::size_t k = 0; k < 3; ++k) {
                float x = p[k][0];
                if (3 * t + k == out_at || (3 * t + k > out_at && 3 * t + k < out_at + 3))
                    x = 300.0f + x;
                window_vertex(d, x, p[k][1], 0, colour_of(t));
            }
        }
    } else if (prim == PrimitiveType::TriangleStrip) {
        // A strip snaking along the rows, 0.75 px per vertex.
        for (std::size_t k = 0; k < n; ++k) {
            const float along = static_cast<float>(k) * 0.75f;
            const int row = static_cast<int>(along / 240.0f);
            const float t = along - static_cast<float>(row) * 240.0f;
            float x = (row % 2 == 0) ? 8.0f + t : 248.0f - t;
            const float y = static_cast<float>(row) * 2.0f + 2.5f + jitter();
            if (k >= out_at && k < out_at + 2) x += 400.0f;
            window_vertex(d, x, y, 0, colour_of(k));
        }
    } else {
        // A fan from a vertex at the left of row 30, over points along that row.
        window_vertex(d, 2.0f, 30.5f, 0, colour_of(0));
        for (std::size_t k = 1; k < n; ++k) {
            const float x = 10.0f + static_cast<float>(k) * (240.0f / 9000.0f);
            float xr = std::round(x * 1024.0f) / 1024.0f;
            if (k >= out_at && k < out_at + 2) xr += 400.0f;
            window_vertex(d, xr, 30.5f + jitter() + static_cast<float>(r.integer(-2, 2)) / 256.0f,
                          0, colour_of(k));
        }
    }
    if (indexed) d.indices = identity_indices(n);
    s.draws.push_back(std::move(d));
    return s;
}

// A triangle fan whose split into the draw module's segments is visible: vertex 0 sits 3/1024 px
// above a row of pixel centres; rim vertices alternate between the end of a horizontal sliver
// (3/1024 px below the row) and its quarter point (2/1024 px above), so consecutive triangles are
// one sliver in both orientations, and the one llvmpipe's fixed-point setup keeps is back-facing
// by the float determinant. Such runs lie across the fan splits after triangles 1,022 (to the
// right of vertex 0) and 2,044 (to the left); every other triangle is degenerate. One rim vertex
// past the far plane, at vertex 0's window position, lies in the second segment only: its
// triangles take the draw pipeline's float cull, the others llvmpipe's fixed-point cull alone.
// A fan of more than 4,096 vertices is split; one of at most 4,096 is a single segment.
SceneFile segments_fan_split(const std::string& kind, Rng& r, bool first, std::size_t n,
                             bool indexed = false) {
    SceneFile s = base(
        kind,
        "Culling on, a triangle fan of " + std::to_string(n) + " vertices" +
            std::string(indexed
                            ? " drawn with 32-bit indices (which split a fan of more than 1,024)"
                            : "") +
            ", runs of slivers in both orientations "
            "across the draw module's fan splits after 1,022 and 2,044 triangles, and one vertex "
            "beyond the far plane in the second segment only: only its slivers take the draw "
            "pipeline's float cull, which drops the ones the fixed-point cull keeps (a fan of at "
            "most 4,096 vertices is one segment)." +
            std::string(first ? " First-vertex convention." : ""),
        256, 64);
    SceneDraw d = draw_of(s, PrimitiveType::TriangleFan, VertexSpace::Window);
    d.state.cull = r.pick({CullMode::Back, CullMode::Front});
    d.state.front_face = r.chance(0.5f) ? refraster::FrontFace::Ccw : refraster::FrontFace::Cw;
    d.state.shade = ShadeModel::Flat;
    if (first) d.state.provoking_vertex = refraster::ProvokingVertex::First;
    const auto colour_of = [](std::size_t i) {
        return std::array<float, 4>{static_cast<float>(i % 251) / 255.0f,
                                    static_cast<float>((i / 251) % 251) / 255.0f,
                                    static_cast<float>((i * 7) % 256) / 255.0f, 1.0f};
    };
    const float cx = static_cast<float>(r.integer(100, 155)) + 0.5f;
    const float cy = static_cast<float>(r.integer(8, 55)) + 0.5f;
    const float right = static_cast<float>(r.integer(24, 96));
    const float left = -static_cast<float>(r.integer(24, 96));
    const std::array<float, 3> centre{cx, cy + 3.0f / 1024.0f, 0.0f};
    const auto end_of = [&](float L) {
        return std::array<float, 3>{cx + L, cy - 3.0f / 1024.0f, 0.0f};
    };
    const auto quarter_of = [&](float L) {
        return std::array<float, 3>{cx + L / 4.0f, cy + 2.0f / 1024.0f, 0.0f};
    };
    constexpr std::size_t half_run = 12;  // sliver triangles on either side of a split
    // Triangle k of the fan is (0, k + 1, k + 2): rim vertex i belongs to triangles i - 2 and i
    // - 1.
    std::vector<std::array<float, 3>> rim(n);
    rim[0] = centre;
    for (std::size_t i = 1; i < n; ++i) {
        const bool second = i > 1500;  // after the far-plane vertex: the run at the second split
        const float L = second ? left : right;
        const std::size_t split = second ? 2044 : 1022;
        const std::size_t lo = split - half_run + 1;
        const std::size_t hi = split + half_run + 1;
        if (i >= lo && i <= hi) {
            rim[i] = (i - lo) % 2 == 0 ? end_of(L) : quarter_of(L);
        } else if (i < lo) {
            rim[i] = second ? centre : end_of(L);
        } else {
            rim[i] = rim[hi];
        }
    }
    // From the first run's last vertex to the second run through vertex 0's position, and the
    // vertex beyond the far plane there (all its triangles degenerate in window x and y).
    for (std::size_t i = 1022 + half_run + 2; i <= 1500; ++i)
        rim[i] = i < 1400 ? rim[1022 + half_run + 1] : centre;
    rim[1450 + 50] = {cx, cy + 3.0f / 1024.0f, 1.5f};
    for (std::size_t i = 0; i < n; ++i)
        window_vertex(d, rim[i][0], rim[i][1], rim[i][2], colour_of(i));
    if (indexed) d.indices = identity_indices(n);
    s.draws.push_back(std::move(d));
    return s;
}

SceneFile depth_limits(const std::string& kind, Rng& r, DepthFormat depth) {
    SceneFile s = base(
        kind,
        "Triangles at window depth exactly 0 and 1 (depth ranges [0, 1] and [1, 0]), with polygon "
        "offsets from tiny to 10^30 in factor and units, either sign, some steep enough that "
        "slope times factor overflows: the offset depth is clamped to [0, 1], infinities to the "
        "ends, NaN to the far value.",
        64, 64, ColorFormat::Rgba8, depth);
    s.clear.depth = r.pick({1.0f, 0.5f, 0.0f});
    for (int t = 0; t < 16; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.depth_test = any_compare(r);
        if (r.chance(0.4f)) {
            d.state.depth_near = 1.0f;
            d.state.depth_far = 0.0f;
        }
        const float f = r.chance(0.2f) ? 0.0f : r.magnitude(-3, 30);
        const float u = r.chance(0.2f) ? 0.0f : r.magnitude(-3, 30);
        d.state.polygon_offset = refraster::PolygonOffset{f, u};
        const int mode = r.integer(0, 3);
        for (int k = 0; k < 3; ++k) {
            auto p = inside(r, r.uniform(0.5f, 2.0f));
            if (mode == 0) p[2] = p[3];                            // z = 1 (far) everywhere
            if (mode == 1) p[2] = -p[3];                           // z = 0 (near)
            if (mode == 2) p[2] = (k == 0 ? -1.0f : 1.0f) * p[3];  // from near to far
            if (mode == 3 && k == 0) {  // a steep depth slope in a sliver
                p[2] = p[3];
            }
            clip_vertex(d, p, r.colour());
        }
        if (mode == 3) {
            d.vertices[1].position = d.vertices[0].position;
            d.vertices[1].position[0] += 0.001f * d.vertices[1].position[3];
            d.vertices[1].position[2] = -d.vertices[1].position[3];
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

// Colours far outside [0, 1]: vertex colours up to float's largest, subnormal ones, and w tiny
// enough that colour times 1/w overflows, so that interpolation gives infinities and NaN.
SceneFile colours(const std::string& kind, Rng& r, ColorFormat color, BlendPreset blend,
                  bool tiny_w) {
    SceneFile s = base(
        kind,
        std::string("Colours far out of range into ") +
            (color == ColorFormat::Rgba8 ? "rgba8" : "rgba32f") +
            (blend == BlendPreset::None    ? ""
             : blend == BlendPreset::Alpha ? " with alpha blending"
                                           : " with additive blending") +
            (tiny_w
                 ? ": vertex colours up to 10^38 with w small enough that colour/w overflows, so "
                   "interpolation yields infinities and NaN."
                 : ": vertex colours from subnormal to 3.4*10^38, both signs, smooth, flat and "
                   "noperspective."),
        32, 32, color, DepthFormat::None);
    s.clear.color = {r.uniform(-2, 2), r.uniform(0, 1), r.magnitude(-3, 3), r.uniform(0, 1)};
    if (color == ColorFormat::Rgba8)
        s.clear.color = {r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1)};
    const auto extreme_value = [&]() -> float {
        switch (r.integer(0, 6)) {
            case 0:
                return r.sign() * kMax;
            case 1:
                return r.magnitude(20, 38.5f);
            case 2:
                return r.subnormal();
            case 3:
                return r.magnitude(-3, 3);
            case 4:
                return r.uniform(-1, 2);
            case 5:
                return r.sign() * kNormMin;
            default:
                return r.uniform(0, 1);
        }
    };
    for (int t = 0; t < 16; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.blend = blend;
        d.state.shade = r.pick(
            {ShadeModel::Smooth, ShadeModel::Smooth, ShadeModel::Flat, ShadeModel::NoPerspective});
        for (int k = 0; k < 3; ++k) {
            const float w = tiny_w ? std::fabs(r.magnitude(-30, -8)) : r.uniform(0.5f, 2.0f);
            std::array<float, 4> c{};
            for (auto& ch : c) ch = extreme_value();
            clip_vertex(d, inside(r, w, 1.1f), c);
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

// Clipped triangles whose attribute planes have subnormal terms (vertex colours near the
// smallest normal float), in draws of different lengths: llvmpipe sets up the draw pipeline's
// triangles in batches of at most 128 vertices, the last batch of a draw after draw_vbo has
// restored the caller's floating-point state, so with denormals kept.
SceneFile subnormal_setup(const std::string& kind, Rng& r) {
    SceneFile s = base(
        kind,
        "Draws that start with one clipped triangle whose vertex colours lie near the smallest "
        "normal float (noperspective or smooth, into rgba32f), followed by none or by 70 to 100 "
        "ordinary triangles, clipped or not: the draw pipeline hands its triangles to llvmpipe's "
        "setup in "
        "batches of at most 128 vertices, and a draw's last batch is set up after draw_vbo has "
        "restored the floating-point state, so without flushing denormals.",
        32, 32, ColorFormat::Rgba32f, DepthFormat::None);
    const auto tiny = [&]() -> float {
        switch (r.integer(0, 2)) {
            case 0:
                return r.sign() * kNormMin;
            case 1:
                return r.subnormal();
            default:
                return r.uniform(-1, 1);
        }
    };
    for (int dn = 0; dn < 16; ++dn) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.shade = r.chance(0.5f) ? ShadeModel::NoPerspective : ShadeModel::Smooth;
        for (int k = 0; k < 3; ++k) {
            auto p = inside(r, r.uniform(0.5f, 2.0f), 1.4f);
            if (k == 0) p[0] = 1.2f * p[3];  // outside x = w: the draw goes through the pipeline
            clip_vertex(d, p, {tiny(), tiny(), tiny(), r.uniform(0, 1)});
        }
        // Followers, clipped ones (four vertices after clipping) or unclipped ones (three), in
        // the corner at NDC (-1, -1): none, so that the first triangle is in the draw's last
        // batch, or enough that it is not, whatever the vertex size (the owner pass of
        // docs/conformance.md adds an attribute, and so shrinks the batches).
        const bool clipped = r.chance(0.5f);
        const int n = r.pick({0, 0, 70, 100});
        for (int t = 0; t < n; ++t) {
            const std::array<float, 4> c{r.uniform(0, 1), r.uniform(0, 1), r.uniform(0, 1), 1.0f};
            clip_vertex(d, {clipped ? -1.5f : -0.8f, -1.0f, 0.0f, 1.0f}, c);
            clip_vertex(d, {clipped ? -0.9f : -0.7f, -1.0f, 0.0f, 1.0f}, c);
            clip_vertex(d, {clipped ? -0.9f : -0.7f, -0.9f, 0.0f, 1.0f}, c);
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

SceneFile wide_lines(const std::string& kind, Rng& r, PrimitiveType prim) {
    SceneFile s = base(
        kind,
        std::string("Width-255 ") + (prim == PrimitiveType::Lines ? "lines" : "line loops") +
            " crossing the view volume's planes (x, y, near, far) and w = 0, on a 128x128 target: "
            "the clipper's new ends, then parallelograms 255 pixels wide.",
        128, 128, ColorFormat::Rgba8, DepthFormat::Z24);
    for (int t = 0; t < 6; ++t) {
        SceneDraw d = draw_of(s, prim, VertexSpace::Clip);
        d.state.line_width = r.chance(0.7f) ? 255.0f : r.uniform(100, 255);
        d.state.depth_test = CompareFunc::Lequal;
        d.state.shade = r.pick({ShadeModel::Smooth, ShadeModel::Flat, ShadeModel::NoPerspective});
        const int n = prim == PrimitiveType::Lines ? 4 : 3;
        for (int k = 0; k < n; ++k) {
            auto p = inside(r, r.uniform(0.5f, 2.0f), 2.5f);
            if (r.chance(0.3f)) p[2] = r.uniform(-2, 2) * p[3];
            if (r.chance(0.15f)) p[3] = -r.uniform(0.1f, 1);
            clip_vertex(d, p, r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

SceneFile big_points(const std::string& kind, Rng& r, bool polygon_mode) {
    SceneFile s =
        base(kind,
             polygon_mode
                 ? "Triangles in polygon mode point with size-255 points, vertices across the "
                   "clip planes: the clipper's new vertices become points too."
                 : "Size-255 points with centres just inside and just outside every clip plane "
                   "(x, y, near, far): a point is dropped whole when its centre is outside, and "
                   "one inside lights pixels far beyond the viewport.",
             128, 128, ColorFormat::Rgba8, DepthFormat::Z24);
    SceneDraw d = draw_of(s, polygon_mode ? PrimitiveType::Triangles : PrimitiveType::Points,
                          VertexSpace::Clip);
    d.state.viewport = {32, 32, 64, 64};
    d.state.point_size = 255;
    d.state.depth_test = CompareFunc::Lequal;
    if (polygon_mode) d.state.polygon_mode = refraster::PolygonMode::Point;
    for (int k = 0; k < (polygon_mode ? 12 : 16); ++k) {
        auto p = inside(r, r.uniform(0.5f, 2.0f));
        const auto axis = static_cast<std::size_t>(r.integer(0, 2));
        const float e = r.pick({0.999f, 1.001f, 0.9999999f, 1.0000001f, 1.5f});
        p[axis] = r.sign() * e * p[3];
        clip_vertex(d, p, r.colour());
    }
    s.draws.push_back(std::move(d));
    return s;
}

SceneFile perspective(const std::string& kind, Rng& r, bool clipped) {
    SceneFile s = base(
        kind,
        clipped
            ? "Perspective triangles whose vertices' w differ by a factor of 10^8 (10^-4 to 10^4), "
              "crossing the view volume, smooth colours and depth: 1/w planes over eight "
              "decades, and the clipper's new vertices."
            : "Perspective triangles inside the view volume whose vertices' w differ by a factor "
              "of "
              "10^8 (10^-4 to 10^4): smooth colours divided by a 1/w plane spanning eight "
              "decades, and depth.",
        64, 64, ColorFormat::Rgba8, DepthFormat::Z32f);
    for (int t = 0; t < 10; ++t) {
        SceneDraw d = draw_of(s, PrimitiveType::Triangles, VertexSpace::Clip);
        d.state.depth_test = CompareFunc::Less;
        d.state.shade = r.chance(0.8f) ? ShadeModel::Smooth : ShadeModel::NoPerspective;
        const std::array<float, 3> ws{1e-4f, 1e4f, r.magnitude(-4, 4)};
        for (int k = 0; k < 3; ++k) {
            const float w = std::fabs(ws[static_cast<std::size_t>(k)]);
            clip_vertex(d, inside(r, w, clipped ? 1.5f : 0.9f), r.colour());
        }
        s.draws.push_back(std::move(d));
    }
    return s;
}

using Maker = std::function<SceneFile(Rng&)>;

const std::vector<std::pair<std::string, Maker>>& makers() {
    static const std::vector<std::pair<std::string, Maker>> m = [] {
        std::vector<std::pair<std::string, Maker>> v;
        const std::array<std::string, 4> axes{"x", "y", "z", "w"};
        for (std::size_t a = 0; a < 4; ++a) {
            v.emplace_back("huge_coordinates_" + axes[a],
                           [a, axes](Rng& r) { return huge(axes[a], a, r); });
        }
        for (std::size_t a = 0; a < 4; ++a) {
            v.emplace_back("subnormal_coordinates_" + axes[a],
                           [a, axes](Rng& r) { return subnormal(axes[a], a, r); });
        }
        v.emplace_back("tiny_w_positive", [](Rng& r) { return tiny_w("tiny_w_positive", r, 0); });
        v.emplace_back("tiny_w_negative", [](Rng& r) { return tiny_w("tiny_w_negative", r, 1); });
        v.emplace_back("tiny_w_both_signs",
                       [](Rng& r) { return tiny_w("tiny_w_both_signs", r, 2); });
        v.emplace_back("beyond_guard_band_x",
                       [](Rng& r) { return guard_band("beyond_guard_band_x", r, false); });
        v.emplace_back("beyond_guard_band_xy",
                       [](Rng& r) { return guard_band("beyond_guard_band_xy", r, true); });
        v.emplace_back("viewport_min_origin",
                       [](Rng& r) { return viewport("viewport_min_origin", r, 0); });
        v.emplace_back("viewport_reaching_target",
                       [](Rng& r) { return viewport("viewport_reaching_target", r, 1); });
        v.emplace_back("viewport_max_origin",
                       [](Rng& r) { return viewport("viewport_max_origin", r, 2); });
        v.emplace_back("viewport_extreme_aspect",
                       [](Rng& r) { return viewport("viewport_extreme_aspect", r, 3); });
        v.emplace_back("largest_target", [](Rng& r) { return largest_target(r); });
        v.emplace_back("widest_target",
                       [](Rng& r) { return long_target("widest_target", r, true); });
        v.emplace_back("tallest_target",
                       [](Rng& r) { return long_target("tallest_target", r, false); });
        v.emplace_back("sliver_16000_horizontal",
                       [](Rng& r) { return sliver("sliver_16000_horizontal", r, 0); });
        v.emplace_back("sliver_16000_vertical",
                       [](Rng& r) { return sliver("sliver_16000_vertical", r, 1); });
        v.emplace_back("sliver_16000_shallow",
                       [](Rng& r) { return sliver("sliver_16000_shallow", r, 2); });
        v.emplace_back("nan_planes_z16", [](Rng& r) {
            return nan_planes("nan_planes_z16", r, DepthFormat::Z16, ColorFormat::Rgba8);
        });
        v.emplace_back("nan_planes_z24", [](Rng& r) {
            return nan_planes("nan_planes_z24", r, DepthFormat::Z24, ColorFormat::Rgba8);
        });
        v.emplace_back("nan_planes_z32f", [](Rng& r) {
            return nan_planes("nan_planes_z32f", r, DepthFormat::Z32f, ColorFormat::Rgba8);
        });
        v.emplace_back("nan_planes_rgba32f_z24", [](Rng& r) {
            return nan_planes("nan_planes_rgba32f_z24", r, DepthFormat::Z24, ColorFormat::Rgba32f);
        });
        v.emplace_back("nan_planes_rgba32f_z32f", [](Rng& r) {
            return nan_planes("nan_planes_rgba32f_z32f", r, DepthFormat::Z32f,
                              ColorFormat::Rgba32f);
        });
        v.emplace_back("segments_list_clip_cull", [](Rng& r) {
            return segments("segments_list_clip_cull", r, PrimitiveType::Triangles, false);
        });
        v.emplace_back("segments_list_clip_cull_first", [](Rng& r) {
            return segments("segments_list_clip_cull_first", r, PrimitiveType::Triangles, true);
        });
        v.emplace_back("segments_strip_clip_cull", [](Rng& r) {
            return segments("segments_strip_clip_cull", r, PrimitiveType::TriangleStrip, false);
        });
        v.emplace_back("segments_strip_clip_cull_first", [](Rng& r) {
            return segments("segments_strip_clip_cull_first", r, PrimitiveType::TriangleStrip,
                            true);
        });
        v.emplace_back("segments_fan_clip_cull", [](Rng& r) {
            return segments("segments_fan_clip_cull", r, PrimitiveType::TriangleFan, false);
        });
        v.emplace_back("segments_list_indexed", [](Rng& r) {
            return segments("segments_list_indexed", r, PrimitiveType::Triangles, false, true);
        });
        v.emplace_back("segments_strip_indexed", [](Rng& r) {
            return segments("segments_strip_indexed", r, PrimitiveType::TriangleStrip, false, true);
        });
        v.emplace_back("segments_fan_indexed", [](Rng& r) {
            return segments_fan_split("segments_fan_indexed", r, false, 4096, true);
        });
        v.emplace_back("segments_fan_clip_cull_first", [](Rng& r) {
            return segments("segments_fan_clip_cull_first", r, PrimitiveType::TriangleFan, true);
        });
        v.emplace_back("depth_limits_offset_z16", [](Rng& r) {
            return depth_limits("depth_limits_offset_z16", r, DepthFormat::Z16);
        });
        v.emplace_back("depth_limits_offset_z24", [](Rng& r) {
            return depth_limits("depth_limits_offset_z24", r, DepthFormat::Z24);
        });
        v.emplace_back("depth_limits_offset_z32f", [](Rng& r) {
            return depth_limits("depth_limits_offset_z32f", r, DepthFormat::Z32f);
        });
        for (const bool tiny : {false, true}) {
            for (const auto fmt : {ColorFormat::Rgba8, ColorFormat::Rgba32f}) {
                for (const auto b : {BlendPreset::None, BlendPreset::Alpha, BlendPreset::Add}) {
                    const std::string name = std::string("colour_") +
                                             (tiny ? "overflow_" : "extreme_") +
                                             (fmt == ColorFormat::Rgba8 ? "rgba8" : "rgba32f") +
                                             (b == BlendPreset::None    ? ""
                                              : b == BlendPreset::Alpha ? "_alpha"
                                                                        : "_add");
                    v.emplace_back(name, [name, fmt, b, tiny](Rng& r) {
                        return colours(name, r, fmt, b, tiny);
                    });
                }
            }
        }
        v.emplace_back("subnormal_setup_batches",
                       [](Rng& r) { return subnormal_setup("subnormal_setup_batches", r); });
        v.emplace_back("lines_255_across_clip", [](Rng& r) {
            return wide_lines("lines_255_across_clip", r, PrimitiveType::Lines);
        });
        v.emplace_back("line_loops_255_across_clip", [](Rng& r) {
            return wide_lines("line_loops_255_across_clip", r, PrimitiveType::LineLoop);
        });
        v.emplace_back("points_255_across_clip",
                       [](Rng& r) { return big_points("points_255_across_clip", r, false); });
        v.emplace_back("polygon_points_255_across_clip", [](Rng& r) {
            return big_points("polygon_points_255_across_clip", r, true);
        });
        v.emplace_back("perspective_w_ratio_1e8",
                       [](Rng& r) { return perspective("perspective_w_ratio_1e8", r, false); });
        v.emplace_back("perspective_w_ratio_1e8_clipped", [](Rng& r) {
            return perspective("perspective_w_ratio_1e8_clipped", r, true);
        });
        v.emplace_back("segments_fan_split_visible", [](Rng& r) {
            return segments_fan_split("segments_fan_split_visible", r, false, 4200);
        });
        v.emplace_back("segments_fan_split_visible_first", [](Rng& r) {
            return segments_fan_split("segments_fan_split_visible_first", r, true, 4200);
        });
        return v;
    }();
    return m;
}

}  // namespace

std::vector<std::string> extreme_kinds() {
    std::vector<std::string> k;
    for (const auto& [name, make] : makers()) k.push_back(name);
    return k;
}

SceneFile extreme_scene(const std::string& kind, std::uint64_t seed) {
    for (std::size_t i = 0; i < makers().size(); ++i) {
        if (makers()[i].first == kind) {
            // Each kind draws from its own stream, so adding kinds changes no other scene.
            std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a of the kind's name
            for (const char c : kind) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
            Rng r(seed * 0x9e3779b97f4a7c15ull + h);
            return makers()[i].second(r);
        }
    }
    throw std::invalid_argument("unknown extreme scene kind: " + kind);
}

int write_extreme_scenes(std::uint64_t seed, const std::filesystem::path& dir, std::ostream& err) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        err << "refraster generate extreme: " << dir.string() << ": " << ec.message() << "\n";
        return 2;
    }
    for (const auto& kind : extreme_kinds()) {
        const auto path = dir / (kind + ".json");
        try {
            write_file_atomically(path, extreme_scene_json(extreme_scene(kind, seed)));
        } catch (const std::bad_alloc&) {
            throw;  // running out of memory: main reports it (exit 3)
        } catch (const std::exception& e) {
            err << "refraster generate extreme: " << e.what() << "\n";
            return 2;
        }
    }
    return 0;
}

std::string extreme_scene_json(const SceneFile& s) {
    using ojson = nlohmann::ordered_json;
    const ojson j = ojson::parse(scene_to_json(s));
    return lay_out_scene_json(j, [](std::string& out, std::size_t, const ojson& d) {
        bool first_field = true;
        for (auto f = d.begin(); f != d.end(); ++f) {
            open_draw_field(out, first_field);
            out += ojson(f.key()).dump() + ": ";
            if (f.key() == "vertices") {
                out += "[";
                for (std::size_t v = 0; v < f.value().size(); ++v) {
                    out += (v == 0 ? "\n    " : ",\n    ") + f.value()[v].dump();
                }
                out += "\n   ]";
            } else {
                out += f.value().dump();
            }
        }
    });
}

}  // namespace harness
