// fingerprint.cpp: probe scenes and the candidate search (fingerprint.hpp).
#include "harness/fingerprint.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <stdexcept>

#include "harness/profile_io.hpp"
#include "harness/rule_search.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

using refraster::Draw;
using refraster::Framebuffer;
using refraster::Profile;

// ---------------------------------------------------------------------------------------
// Probe scenes. Every position is a window coordinate on a dyadic grid, given in clip space
// with w = 1 under a viewport covering a power-of-two target, so that the viewport transform
// is exact whichever way it is computed (fused or not), unless the probe wants otherwise.

struct Probe {
    std::string name;
    Scene scene;
    // Which pixels count: coverage (lit or not against the clear colour), everything (colour
    // bits and depth), or depth alone.
    enum class Compare { Coverage, Exact, Depth } compare = Compare::Coverage;
};

Scene make_scene(const std::string& name, std::uint32_t w, std::uint32_t h,
                 refraster::ColorFormat color = refraster::ColorFormat::Rgba8,
                 refraster::DepthFormat depth = refraster::DepthFormat::None) {
    Scene s;
    s.path = "fingerprint/" + name;
    s.file.name = name;
    s.file.target = {w, h, color, depth, 1};
    s.file.clear.color = {0.0f, 0.0f, 0.0f, 0.0f};
    s.file.clear.depth = 1.0f;
    s.draw_list.target = s.file.target;
    s.draw_list.clear = s.file.clear;
    return s;
}

// A draw of window-space vertices (x, y, z) with colours, in a target of size (w, h) whose
// whole area is the viewport; w_clip scales each clip position (perspective) when given.
Draw window_draw(refraster::PrimitiveType p, const std::vector<std::array<float, 3>>& pos,
                 const std::vector<std::array<float, 4>>& colors, std::uint32_t w, std::uint32_t h,
                 const std::vector<float>& w_clip = {}) {
    Draw d;
    d.primitive = p;
    d.state.viewport = {0, 0, static_cast<std::int32_t>(w), static_cast<std::int32_t>(h)};
    d.vertices.attributes = {{"color", 4}};
    const float hw = 0.5f * static_cast<float>(w);
    const float hh = 0.5f * static_cast<float>(h);
    for (std::size_t i = 0; i < pos.size(); ++i) {
        const float cw = w_clip.empty() ? 1.0f : w_clip[i];
        const float x = (pos[i][0] - hw) / hw;
        const float y = (pos[i][1] - hh) / hh;
        const float z = pos[i][2] * 2.0f - 1.0f;
        d.vertices.data.insert(d.vertices.data.end(), {x * cw, y * cw, z * cw, cw});
        const auto& c = colors[std::min(i, colors.size() - 1)];
        d.vertices.data.insert(d.vertices.data.end(), c.begin(), c.end());
    }
    return d;
}

constexpr std::array<float, 4> kWhite{1.0f, 1.0f, 1.0f, 1.0f};

// A position on the 1/1024 grid in [lo, hi).
float grid(std::mt19937& rng, float lo, float hi, float step = 1.0f / 1024.0f) {
    std::uniform_real_distribution<float> u(lo, hi);
    return std::floor(u(rng) / step) * step;
}

// Triangles in 16x16 cells: random vertices on the 1/1024 grid (subpixel precision and
// rounding), vertices exactly half a subpixel step apart for every step from 1/2 to 1/256
// (the snapping's rounding), and edges through pixel centres in every direction (the tie
// rule). Above them, in a second viewport, a strip of near ties: edges passing 2^-14 to 2^-24
// px from a pixel centre, which exact predicates decide by the true side and float setups by
// their rounding (what tells softpipe's scanline walk from the exact model, which light the
// same pixels everywhere else).
Probe triangle_probe() {
    Probe p{"triangles", make_scene("triangles", 256, 320), Probe::Compare::Coverage};
    std::mt19937 rng(11);
    std::vector<std::array<float, 3>> v;
    for (int cell = 0; cell < 256; ++cell) {
        const float cx = static_cast<float>((cell % 16) * 16);
        const float cy = static_cast<float>((cell / 16) * 16);
        const int kind = cell % 4;
        std::array<std::array<float, 2>, 3> t{};
        if (kind == 0 || kind == 1) {
            for (auto& q : t) q = {cx + grid(rng, 1.0f, 15.0f), cy + grid(rng, 1.0f, 15.0f)};
        } else if (kind == 2) {
            // Half steps: k/2^b + 1/2^(b+1) for b = 1..8, around pixel centres.
            const int b = 1 + (cell / 4) % 8;
            const float half = std::ldexp(1.0f, -(b + 1));
            for (auto& q : t) {
                q = {cx + std::floor(grid(rng, 1.0f, 15.0f)) + 0.5f +
                         half * static_cast<float>(std::uniform_int_distribution<int>(-3, 3)(rng)),
                     cy + std::floor(grid(rng, 1.0f, 15.0f)) + 0.5f +
                         half * static_cast<float>(std::uniform_int_distribution<int>(-3, 3)(rng))};
            }
        } else {
            // Edges through pixel centres: a right triangle with its legs on centre lines and a
            // diagonal through centres, in one of four orientations.
            const float x0 = cx + 2.5f, y0 = cy + 2.5f, s = 10.0f;
            const int o = (cell / 4) % 4;
            const float sx = (o & 1) ? -1.0f : 1.0f;
            const float sy = (o & 2) ? -1.0f : 1.0f;
            const float bx = (o & 1) ? x0 + s : x0;
            const float by = (o & 2) ? y0 + s : y0;
            t = {{{bx, by}, {bx + sx * s, by}, {bx, by + sy * s}}};
        }
        for (const auto& q : t) v.push_back({q[0], q[1], 0.5f});
    }
    p.scene.draw_list.draws.push_back(
        window_draw(refraster::PrimitiveType::Triangles, v, {kWhite}, 256, 256));
    std::vector<std::array<float, 3>> near;
    for (int cell = 0; cell < 64; ++cell) {
        const float cx = static_cast<float>((cell % 16) * 16) + 8.5f;
        const float cy = static_cast<float>((cell / 16) * 16) + 8.5f;
        const float slope = grid(rng, 0.05f, 0.95f);
        const float offset =
            std::ldexp(cell % 2 == 0 ? 1.0f : -1.0f, -14 - (cell / 2) % 11);  // 2^-14 .. 2^-24
        const float sign = (cell / 4) % 2 == 0 ? 1.0f : -1.0f;  // interior above or below
        near.push_back({cx - 6.0f, cy - 6.0f * slope + offset, 0.5f});
        near.push_back({cx + 6.0f, cy + 6.0f * slope + offset, 0.5f});
        near.push_back({cx - 2.0f, cy + sign * 5.0f, 0.5f});
    }
    Draw strip = window_draw(refraster::PrimitiveType::Triangles, near, {kWhite}, 256, 64);
    strip.state.viewport.y = 256;
    p.scene.draw_list.draws.push_back(std::move(strip));
    return p;
}

// Width-1 lines in 32x32 cells, every octant, ends on the 1/256 grid and on integers.
Probe line_probe() {
    Probe p{"lines", make_scene("lines", 256, 256), Probe::Compare::Coverage};
    std::mt19937 rng(12);
    std::vector<std::array<float, 3>> v;
    for (int cell = 0; cell < 64; ++cell) {
        const float cx = static_cast<float>((cell % 8) * 32);
        const float cy = static_cast<float>((cell / 8) * 32);
        const float step = cell % 3 == 0 ? 1.0f : 1.0f / 256.0f;
        v.push_back({cx + grid(rng, 3.0f, 29.0f, step), cy + grid(rng, 3.0f, 29.0f, step), 0.5f});
        v.push_back({cx + grid(rng, 3.0f, 29.0f, step), cy + grid(rng, 3.0f, 29.0f, step), 0.5f});
    }
    p.scene.draw_list.draws.push_back(
        window_draw(refraster::PrimitiveType::Lines, v, {kWhite}, 256, 256));
    return p;
}

// Horizontal lines of widths 1.5 to 4.5 in half steps at rows with centre k + 0.5, and the
// rows each lights (the line width rounding).
Probe line_width_probe() {
    Probe p{"line_widths", make_scene("line_widths", 64, 64), Probe::Compare::Coverage};
    for (int i = 0; i < 7; ++i) {
        const float y = 4.5f + 8.0f * static_cast<float>(i);
        Draw d = window_draw(refraster::PrimitiveType::Lines, {{8.0f, y, 0.5f}, {56.0f, y, 0.5f}},
                             {kWhite}, 64, 64);
        d.state.line_width = 1.5f + 0.5f * static_cast<float>(i);
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// Points of sizes 1 to 5.5 in quarter and half steps at random positions on the 1/256 grid
// and on pixel centres and corners, one a 16x16 cell.
Probe point_probe() {
    Probe p{"points", make_scene("points", 256, 256), Probe::Compare::Coverage};
    std::mt19937 rng(13);
    for (int cell = 0; cell < 256; ++cell) {
        const float cx = static_cast<float>((cell % 16) * 16);
        const float cy = static_cast<float>((cell / 16) * 16);
        float x = cx + grid(rng, 5.0f, 11.0f, 1.0f / 256.0f);
        float y = cy + grid(rng, 5.0f, 11.0f, 1.0f / 256.0f);
        if (cell % 4 == 1) x = std::floor(x) + 0.5f, y = std::floor(y) + 0.5f;
        if (cell % 4 == 2) x = std::floor(x), y = std::floor(y);
        Draw d = window_draw(refraster::PrimitiveType::Points, {{x, y, 0.5f}}, {kWhite}, 256, 256);
        d.state.point_size = 1.0f + 0.25f * static_cast<float>(cell % 19);
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// A viewport inside the target: triangles crossing its sides, points and wide lines whose
// squares reach past them (the clipper leaves them whole, a guard band's viewport scissor cuts
// them).
Probe clipping_probe() {
    Probe p{"clipping", make_scene("clipping", 64, 64), Probe::Compare::Coverage};
    const auto in_viewport = [](Draw d) {
        d.state.viewport = {16, 16, 32, 32};
        return d;
    };
    // Positions in the viewport's own window space (0..32 before the offset of 16).
    const auto at = [](float x, float y) {
        return std::array<float, 3>{x + 16.0f, y + 16.0f, 0.5f};
    };
    auto make = [&](refraster::PrimitiveType t, std::vector<std::array<float, 3>> v) {
        // window_draw maps with the whole target; recompute for the 32x32 viewport at 16.
        Draw d = window_draw(t, {}, {kWhite}, 64, 64);
        d.vertices.data.clear();
        for (const auto& q : v) {
            const float x = (q[0] - 32.0f) / 16.0f;
            const float y = (q[1] - 32.0f) / 16.0f;
            d.vertices.data.insert(d.vertices.data.end(), {x, y, 0.0f, 1.0f});
            d.vertices.data.insert(d.vertices.data.end(), kWhite.begin(), kWhite.end());
        }
        return in_viewport(d);
    };
    p.scene.draw_list.draws.push_back(make(refraster::PrimitiveType::Triangles,
                                           {at(-9.3f, 3.1f), at(20.7f, -6.4f), at(11.2f, 40.9f)}));
    Draw pts = make(refraster::PrimitiveType::Points,
                    {at(0.75f, 10.5f), at(31.25f, 20.5f), at(15.5f, 0.75f), at(12.5f, 31.25f)});
    pts.state.point_size = 6.0f;
    p.scene.draw_list.draws.push_back(pts);
    Draw lines = make(refraster::PrimitiveType::Lines,
                      {at(4.0f, 1.0f), at(28.0f, 1.0f), at(31.0f, 6.0f), at(31.0f, 26.0f)});
    lines.state.line_width = 5.0f;
    p.scene.draw_list.draws.push_back(lines);
    return p;
}

// Triangles reaching past a viewport inside the target (within the guard band), with float
// colours: clipped at the view volume, their planes come from the clipper's new vertices;
// under the guard band from the original ones, the viewport then a scissor. The colours'
// low bits tell the two apart.
Probe triangle_clipping_probe() {
    Probe p{"triangle_clipping",
            make_scene("triangle_clipping", 64, 64, refraster::ColorFormat::Rgba32f),
            Probe::Compare::Exact};
    std::mt19937 rng(16);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 12; ++i) {
        Draw d;
        d.primitive = refraster::PrimitiveType::Triangles;
        d.state.viewport = {16, 16, 32, 32};
        d.vertices.attributes = {{"color", 4}};
        for (int k = 0; k < 3; ++k) {
            // Clip x, y in [-1.8, 1.8]: inside the guard band (2w), often past the viewport.
            const float x = -1.8f + 3.6f * u(rng);
            const float y = -1.8f + 3.6f * u(rng);
            d.vertices.data.insert(d.vertices.data.end(),
                                   {x, y, 0.0f, 1.0f, u(rng), u(rng), u(rng), 1.0f});
        }
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// Perspective-correct colours into rgba32f under a viewport whose scale and offset are not
// powers of two, so that a fused viewport transform and plane evaluation leave other bits.
Probe fusion_probe() {
    Probe p{"fusion", make_scene("fusion", 128, 128, refraster::ColorFormat::Rgba32f),
            Probe::Compare::Exact};
    std::mt19937 rng(14);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 24; ++i) {
        Draw d;
        d.primitive = refraster::PrimitiveType::Triangles;
        d.state.viewport = {3, 5, 119, 117};
        d.vertices.attributes = {{"color", 4}};
        for (int k = 0; k < 3; ++k) {
            const float w = 0.5f + 1.5f * u(rng);
            const float x = (u(rng) * 1.8f - 0.9f) * w;
            const float y = (u(rng) * 1.8f - 0.9f) * w;
            d.vertices.data.insert(d.vertices.data.end(),
                                   {x, y, 0.0f, w, u(rng), u(rng), u(rng), u(rng)});
        }
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// Depth of perspective triangles into z24, written always (the depth quantisation).
Probe depth_probe() {
    Probe p{
        "depth",
        make_scene("depth", 128, 128, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24),
        Probe::Compare::Depth};
    std::mt19937 rng(15);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 16; ++i) {
        std::vector<std::array<float, 3>> v;
        std::vector<float> w;
        for (int k = 0; k < 3; ++k) {
            v.push_back({u(rng) * 128.0f, u(rng) * 128.0f, 0.05f + 0.9f * u(rng)});
            w.push_back(0.5f + 1.5f * u(rng));
        }
        Draw d = window_draw(refraster::PrimitiveType::Triangles, v, {kWhite}, 128, 128, w);
        d.state.depth_test = refraster::CompareFunc::Always;
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// Polygon offset's units term (offset_units_scale): flat triangles on z24 and z16 with units
// 1, 3 and 7 and no slope term, written with depth test always, so the stored depth is
// z + units * r * scale and each power of two of the scale gives other depth values.
std::vector<Probe> offset_probes() {
    std::vector<Probe> out;
    for (auto f : {refraster::DepthFormat::Z24, refraster::DepthFormat::Z16}) {
        const std::string name = "offset_" + std::string(refraster::to_string(f));
        Probe p{name, make_scene(name, 48, 16, refraster::ColorFormat::Rgba8, f),
                Probe::Compare::Depth};
        const float units[] = {1.0f, 3.0f, 7.0f};
        for (int i = 0; i < 3; ++i) {
            const float x = 16.0f * static_cast<float>(i);
            Draw d = window_draw(refraster::PrimitiveType::Triangles,
                                 {{x, 0.0f, 0.25f}, {x + 16.0f, 0.0f, 0.25f}, {x, 16.0f, 0.25f}},
                                 {kWhite}, 48, 16);
            d.state.depth_test = refraster::CompareFunc::Always;
            d.state.polygon_offset = refraster::PolygonOffset{0.0f, units[i]};
            p.scene.draw_list.draws.push_back(d);
        }
        out.push_back(std::move(p));
    }
    return out;
}

// Clears of z16 and z24 targets to values whose quantisation in double and in float differ.
std::vector<Probe> clear_probes() {
    std::vector<Probe> out;
    for (auto f : {refraster::DepthFormat::Z24, refraster::DepthFormat::Z16}) {
        const double max = f == refraster::DepthFormat::Z24 ? 16777215.0 : 65535.0;
        int found = 0;
        for (int i = 1; i < 200000 && found < 4; ++i) {
            const float z = static_cast<float>(i) / 200000.0f;
            const auto d = static_cast<std::uint32_t>(std::nearbyint(static_cast<double>(z) * max));
            const auto fl = static_cast<std::uint32_t>(std::nearbyint(z * static_cast<float>(max)));
            if (d == fl) continue;
            const std::string name =
                "clear_" + std::string(refraster::to_string(f)) + "_" + std::to_string(found++);
            Probe p{name, make_scene(name, 4, 4, refraster::ColorFormat::Rgba8, f),
                    Probe::Compare::Depth};
            p.scene.file.clear.depth = z;
            p.scene.draw_list.clear.depth = z;
            out.push_back(std::move(p));
        }
    }
    return out;
}

// The i-th flat colour between two bytes: each channel (k + 0.7) / 255, which rounds up and
// truncates down.
std::array<float, 4> between_bytes(int i) {
    std::array<float, 4> c{};
    for (int k = 0; k < 4; ++k)
        c[static_cast<std::size_t>(k)] = (static_cast<float>(i * 13 + k * 47) + 0.7f) / 255.0f;
    return c;
}

// Flat colours between two bytes (between_bytes).
Probe color_probe() {
    Probe p{"colors", make_scene("colors", 64, 64), Probe::Compare::Exact};
    for (int i = 0; i < 16; ++i) {
        const float x = static_cast<float>((i % 4) * 16);
        const float y = static_cast<float>((i / 4) * 16);
        const std::array<float, 4> c = between_bytes(i);
        Draw d = window_draw(
            refraster::PrimitiveType::Triangles,
            {{x + 1.0f, y + 1.0f, 0.5f}, {x + 15.0f, y + 1.0f, 0.5f}, {x + 1.0f, y + 15.0f, 0.5f}},
            {c}, 64, 64);
        d.state.shade = refraster::ShadeModel::Flat;
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// One class of the clipping probe alone: its points or its wide lines (the triangle left out).
Probe clipping_class_probe(refraster::PrimitiveType t) {
    Probe p = clipping_probe();
    p.name = t == refraster::PrimitiveType::Points ? "clipping_points" : "clipping_lines";
    auto& draws = p.scene.draw_list.draws;
    draws.erase(
        std::remove_if(draws.begin(), draws.end(), [&](const Draw& d) { return d.primitive != t; }),
        draws.end());
    return p;
}

// Depth of perspective lines or points (size 3) into z24, written always: the depth
// quantisation of that class.
Probe class_depth_probe(refraster::PrimitiveType t) {
    const bool points = t == refraster::PrimitiveType::Points;
    const std::string name = points ? "point_depth" : "line_depth";
    Probe p{name,
            make_scene(name, 128, 128, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24),
            Probe::Compare::Depth};
    std::mt19937 rng(points ? 18 : 17);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 24; ++i) {
        std::vector<std::array<float, 3>> v;
        std::vector<float> w;
        for (int k = 0; k < (points ? 1 : 2); ++k) {
            v.push_back({4.0f + u(rng) * 120.0f, 4.0f + u(rng) * 120.0f, 0.05f + 0.9f * u(rng)});
            w.push_back(0.5f + 1.5f * u(rng));
        }
        Draw d = window_draw(t, v, {kWhite}, 128, 128, w);
        d.state.depth_test = refraster::CompareFunc::Always;
        d.state.point_size = 3.0f;
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// Flat colours between two bytes, (k + 0.7) / 255 as in the colour probe, on lines or points
// (size 6): the colour conversion of that class.
Probe class_color_probe(refraster::PrimitiveType t) {
    const bool points = t == refraster::PrimitiveType::Points;
    const std::string name = points ? "point_colors" : "line_colors";
    Probe p{name, make_scene(name, 64, 64), Probe::Compare::Exact};
    for (int i = 0; i < 16; ++i) {
        const float x = static_cast<float>((i % 4) * 16);
        const float y = static_cast<float>((i / 4) * 16);
        const std::array<float, 4> c = between_bytes(i);
        std::vector<std::array<float, 3>> v{{x + 8.0f, y + 8.0f, 0.5f}};
        if (!points) v = {{x + 2.0f, y + 3.5f, 0.5f}, {x + 14.0f, y + 12.5f, 0.5f}};
        Draw d = window_draw(t, v, {c}, 64, 64);
        d.state.shade = refraster::ShadeModel::Flat;
        d.state.point_size = 6.0f;
        p.scene.draw_list.draws.push_back(d);
    }
    return p;
}

// Texture coordinates (s, t, r, q) after each vertex's colour, the front end's layout for a
// textured draw; the last one given repeats.
void with_texcoords(Draw& d, const std::vector<std::array<float, 4>>& tc) {
    std::vector<float> data;
    const std::size_t stride = d.vertices.stride();
    for (std::size_t i = 0; i < d.vertices.size(); ++i) {
        data.insert(data.end(), d.vertices.data.begin() + static_cast<std::ptrdiff_t>(i * stride),
                    d.vertices.data.begin() + static_cast<std::ptrdiff_t>((i + 1) * stride));
        const auto& t = tc[std::min(i, tc.size() - 1)];
        data.insert(data.end(), t.begin(), t.end());
    }
    d.vertices.attributes.push_back({"texcoord", 4});
    d.vertices.data = std::move(data);
}

// Textures (texture_rho, texture_mip_blend, texture_filtering): a perspective floor of
// trilinear-filtered texels from a full chain of given levels (16x16 down to 1x1, random from
// a fixed seed, so that no level generation enters) and a magnified bilinear square, both
// modulating a colour.
Probe texture_probe() {
    Probe p{"textures", make_scene("textures", 64, 64), Probe::Compare::Exact};
    std::mt19937 rng(20261206u);
    refraster::Texture tex;
    for (std::uint32_t size = 16; size >= 1; size /= 2) {
        refraster::TextureImage img;
        img.width = size;
        img.height = size;
        for (std::uint32_t i = 0; i < size * size * 4; ++i)
            img.rgba.push_back(static_cast<std::uint8_t>(rng() & 0xffu));
        tex.levels.push_back(std::move(img));
    }
    p.scene.draw_list.textures.push_back(std::move(tex));
    refraster::TextureState t;
    t.min_filter = refraster::TextureFilter::LinearMipmapLinear;
    t.mag_filter = refraster::TextureFilter::Linear;
    // A quad (x, y, z, w) with texture coordinates (s, t), corners counter-clockwise from the
    // bottom left, as the two triangles 0 1 2 and 0 2 3.
    const auto quad = [&](const std::array<std::array<float, 4>, 4>& corners,
                          const std::array<std::array<float, 2>, 4>& st) {
        std::vector<std::array<float, 3>> pos;
        std::vector<float> w;
        std::vector<std::array<float, 4>> tc;
        for (const std::size_t k : {0u, 1u, 2u, 0u, 2u, 3u}) {
            pos.push_back({corners[k][0], corners[k][1], corners[k][2]});
            w.push_back(corners[k][3]);
            tc.push_back({st[k][0], st[k][1], 0.0f, 1.0f});
        }
        Draw d = window_draw(refraster::PrimitiveType::Triangles, pos, {{0.9f, 0.8f, 1.0f, 1.0f}},
                             64, 64, w);
        with_texcoords(d, tc);
        d.state.texture = t;
        p.scene.draw_list.draws.push_back(d);
    };
    // The floor: near edge at w = 1, far edge at w = 6, eight repeats deep.
    quad({{{1.3f, 1.1f, 0.2f, 1.0f},
           {62.6f, 1.1f, 0.2f, 1.0f},
           {50.4f, 40.7f, 0.8f, 6.0f},
           {13.2f, 40.7f, 0.8f, 6.0f}}},
         {{{0.0f, 0.0f}, {3.0f, 0.0f}, {3.0f, 8.0f}, {0.0f, 8.0f}}});
    // The square: 4x4 texels of level 0 over 20x20 pixels.
    quad({{{40.2f, 42.3f, 0.5f, 1.0f},
           {61.7f, 42.3f, 0.5f, 1.0f},
           {61.7f, 62.6f, 0.5f, 1.0f},
           {40.2f, 62.6f, 0.5f, 1.0f}}},
         {{{0.1f, 0.2f}, {0.35f, 0.2f}, {0.35f, 0.45f}, {0.1f, 0.45f}}});
    return p;
}

// ---------------------------------------------------------------------------------------
// Comparing a candidate's render with the backend's.

struct Difference {
    std::uint64_t pixels = 0;
    int x = -1, y = -1;  // the first differing pixel
};

bool lit(const Framebuffer& fb, std::size_t i, const refraster::ClearValues& clear) {
    for (std::size_t k = 0; k < 4; ++k) {
        if (fb.color_format == refraster::ColorFormat::Rgba8) {
            if (fb.color8[4 * i + k] != static_cast<std::uint8_t>(clear.color[k] * 255.0f))
                return true;
        } else if (std::bit_cast<std::uint32_t>(fb.color32f[4 * i + k]) !=
                   std::bit_cast<std::uint32_t>(clear.color[k])) {
            return true;
        }
    }
    return false;
}

Difference difference(const Probe& p, const Framebuffer& a, const Framebuffer& b) {
    Difference d;
    if (a.width != b.width || a.height != b.height) {
        d.pixels = 1;
        return d;
    }
    const auto& clear = p.scene.draw_list.clear;
    for (std::uint32_t y = 0; y < a.height; ++y) {
        for (std::uint32_t x = 0; x < a.width; ++x) {
            const std::size_t i = a.index(x, y);
            bool differs = false;
            switch (p.compare) {
                case Probe::Compare::Coverage:
                    differs = lit(a, i, clear) != lit(b, i, clear);
                    break;
                case Probe::Compare::Depth:
                    differs = a.depth[i] != b.depth[i];
                    break;
                case Probe::Compare::Exact:
                    for (std::size_t k = 0; k < 4 && !differs; ++k) {
                        differs = a.color_format == refraster::ColorFormat::Rgba8
                                      ? a.color8[4 * i + k] != b.color8[4 * i + k]
                                      : std::bit_cast<std::uint32_t>(a.color32f[4 * i + k]) !=
                                            std::bit_cast<std::uint32_t>(b.color32f[4 * i + k]);
                    }
                    differs = differs || (!a.depth.empty() && a.depth[i] != b.depth[i]);
                    break;
            }
            if (differs) {
                if (d.pixels++ == 0) {
                    d.x = static_cast<int>(x);
                    d.y = static_cast<int>(y);
                }
            }
        }
    }
    return d;
}

// What a render shows at a pixel, for evidence.
std::string pixel_text(const Probe& p, const Framebuffer& fb, int x, int y) {
    if (x < 0) return "?";
    const std::size_t i = fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    char buf[96];
    if (p.compare == Probe::Compare::Depth) {
        std::snprintf(buf, sizeof buf, "depth %u", fb.depth[i]);
    } else if (p.compare == Probe::Compare::Coverage) {
        return lit(fb, i, p.scene.draw_list.clear) ? "lit" : "unlit";
    } else if (fb.color_format == refraster::ColorFormat::Rgba8) {
        std::snprintf(buf, sizeof buf, "%u,%u,%u,%u", fb.color8[4 * i], fb.color8[4 * i + 1],
                      fb.color8[4 * i + 2], fb.color8[4 * i + 3]);
    } else {
        std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g,%.9g",
                      static_cast<double>(fb.color32f[4 * i]),
                      static_cast<double>(fb.color32f[4 * i + 1]),
                      static_cast<double>(fb.color32f[4 * i + 2]),
                      static_cast<double>(fb.color32f[4 * i + 3]));
    }
    return buf;
}

// ---------------------------------------------------------------------------------------
// The search.

using Assignment = std::map<std::string, std::string>;

class Search {
  public:
    Search(Backend& target, const FingerprintProgress& progress)
        : target_(target), progress_(progress) {}

    // The backend's render of a probe; nullopt when it does not support it.
    std::optional<Framebuffer> backend(const Probe& p) {
        say("probe " + p.name + " through " + target_.name());
        RenderResult r = target_.render(p.scene);
        if (r.status == RenderStatus::NotSupported) return std::nullopt;
        if (r.status != RenderStatus::Ok) {
            throw std::runtime_error(target_.name() + " failed on probe " + p.name + ": " +
                                     std::string(to_string(r.status)) + " " + r.message);
        }
        return std::move(r.image);
    }

    // The reference under `profile`; nullopt when it cannot draw the probe so.
    static std::optional<Framebuffer> reference(const Probe& p, const Profile& profile) {
        refraster::RenderOptions o;
        o.profile = profile;
        o.threads = 1;
        Framebuffer fb;
        if (refraster::render(p.scene.draw_list, o, fb).status != refraster::RenderStatus::Ok)
            return std::nullopt;
        return fb;
    }

    void say(const std::string& s) const {
        if (progress_) progress_(s);
    }

  private:
    Backend& target_;
    const FingerprintProgress& progress_;
};

Profile with(Profile p, const Assignment& a) {
    for (const auto& [k, v] : a) refraster::set_profile_parameter(p, k, v);
    return p;
}

std::string assignment_text(const Assignment& a) {
    std::string s;
    for (const auto& [k, v] : a) s += (s.empty() ? "" : " ") + k + "=" + v;
    return s;
}

// One stage: every combination in `candidates` applied to `base` and rendered through the
// reference for each probe; the combinations that reproduce every probe pixel decide the keys
// they agree on. Findings for `keys` are appended; the decided values go into `decided`.
struct StageResult {
    std::vector<Assignment> matching;
};

// Every candidate applied to `base` and rendered through the reference for each probe, against
// the backend's renders: per candidate the pixels that differ over all probes, and whether the
// reference could draw them.
struct Reproduction {
    std::vector<std::optional<Framebuffer>> want;  // the backend's, per probe
    bool any = false;                              // the backend drew some probe
    std::vector<std::uint64_t> total;
    std::vector<bool> drawable;
    bool reproduces(std::size_t c) const { return any && drawable[c] && total[c] == 0; }
    // The drawable candidate with the fewest differing pixels.
    std::size_t closest() const {
        std::size_t best = 0;
        for (std::size_t c = 1; c < total.size(); ++c)
            if (drawable[c] && (!drawable[best] || total[c] < total[best])) best = c;
        return best;
    }
};

Reproduction reproduce(Search& search, const std::vector<Probe>& probes, const Profile& base,
                       const std::vector<Assignment>& candidates) {
    Reproduction r;
    for (const auto& p : probes) {
        r.want.push_back(search.backend(p));
        r.any = r.any || r.want.back().has_value();
    }
    r.total.assign(candidates.size(), 0);
    r.drawable.assign(candidates.size(), true);
    for (std::size_t c = 0; c < candidates.size(); ++c) {
        const Profile prof = with(base, candidates[c]);
        for (std::size_t i = 0; i < probes.size(); ++i) {
            if (!r.want[i]) continue;
            const auto got = Search::reference(probes[i], prof);
            if (!got) {
                r.drawable[c] = false;
                break;
            }
            r.total[c] += difference(probes[i], *got, *r.want[i]).pixels;
        }
    }
    return r;
}

StageResult run_stage(Search& search, const std::vector<Probe>& probes, const Profile& base,
                      const std::vector<Assignment>& candidates,
                      const std::vector<std::string>& keys, std::vector<RuleFinding>& findings,
                      Assignment& decided) {
    StageResult out;
    const Reproduction rep = reproduce(search, probes, base, candidates);
    const auto& want = rep.want;
    const bool any = rep.any;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
        if (rep.reproduces(c)) out.matching.push_back(candidates[c]);
    }
    for (const auto& key : keys) {
        RuleFinding f;
        f.key = key;
        for (const auto& c : candidates) {
            const auto it = c.find(key);
            if (it != c.end() && std::find(f.candidates.begin(), f.candidates.end(), it->second) ==
                                     f.candidates.end())
                f.candidates.push_back(it->second);
        }
        for (const auto& m : out.matching) {
            const auto it = m.find(key);
            const std::string v = it == m.end() ? "n/a" : it->second;
            if (std::find(f.matching.begin(), f.matching.end(), v) == f.matching.end())
                f.matching.push_back(v);
        }
        if (!any) {
            f.value = "undecided";
            f.evidence = "the backend draws none of the probes (" + probes.front().name + ")";
        } else if (f.matching.size() == 1 && f.matching[0] != "n/a") {
            f.value = f.matching[0];
            f.decided = true;
            decided[key] = f.value;
        } else if (f.matching.size() == 1) {
            f.value = "n/a";
            f.decided = true;
            f.evidence = "does not apply to the matching model";
        } else if (f.matching.empty()) {
            f.value = "undecided";
            const std::size_t best = rep.closest();
            f.evidence = "no candidate reproduces the probes " + probes.front().name +
                         (probes.size() > 1 ? " and others" : "") + "; the closest (" +
                         assignment_text(candidates[best]) + ") differs in " +
                         std::to_string(rep.total[best]) + " pixels";
        } else {
            f.value = "undecided";
            std::string vs;
            for (const auto& v : f.matching) vs += (vs.empty() ? "" : ", ") + v;
            f.evidence = "the values " + vs + " all reproduce every probe pixel";
        }
        findings.push_back(f);
    }
    // Evidence for each decided key: a rival value (the match with only that key changed)
    // and a probe pixel where it differs from the backend.
    if (out.matching.size() == 1) {
        const Assignment& chosen = out.matching[0];
        for (auto& f : findings) {
            if (!f.decided || f.value == "n/a" || !f.evidence.empty()) continue;
            if (std::find(keys.begin(), keys.end(), f.key) == keys.end()) continue;
            for (const auto& alt : f.candidates) {
                if (alt == f.value) continue;
                Assignment rival = chosen;
                rival[f.key] = alt;
                for (std::size_t i = 0; i < probes.size() && f.evidence.empty(); ++i) {
                    if (!want[i]) continue;
                    const auto got = Search::reference(probes[i], with(base, rival));
                    if (!got) continue;
                    const Difference d = difference(probes[i], *got, *want[i]);
                    if (d.pixels == 0) continue;
                    f.evidence = "probe " + probes[i].name + " pixel (" + std::to_string(d.x) +
                                 ", " + std::to_string(d.y) + "): the backend gives " +
                                 pixel_text(probes[i], *want[i], d.x, d.y) + " as " + f.key + "=" +
                                 f.value + " does; " + f.key + "=" + alt + " gives " +
                                 pixel_text(probes[i], *got, d.x, d.y) + " (" +
                                 std::to_string(d.pixels) + " pixels differ)";
                }
                if (!f.evidence.empty()) break;
            }
            if (f.evidence.empty())
                f.evidence = "the only candidate that reproduces every probe pixel";
        }
    }
    return out;
}

// The built-in profile of a coverage family.
Profile family_base(const std::string& coverage) {
    if (coverage == "scanline") return refraster::softpipe_22_3_profile();
    if (coverage == "exact") return refraster::gl_exact_profile();
    return refraster::llvmpipe_22_3_profile();
}

// The rows a horizontal line of the width probe lights, as "w=1.5: 2 rows" items, and what
// they say about the width rounding.
RuleFinding line_width_finding(const Probe& p, const std::optional<Framebuffer>& fb) {
    RuleFinding f;
    f.key = "line_width_rounding";
    f.candidates = {"half-away", "unrounded"};
    if (!fb) {
        f.value = "undecided";
        f.evidence = "the backend does not draw the probe line_widths";
        return f;
    }
    std::string rows_text;
    bool half_away = true;
    for (std::size_t i = 0; i < p.scene.draw_list.draws.size(); ++i) {
        const float width = p.scene.draw_list.draws[i].state.line_width;
        const int y0 = 4 + 8 * static_cast<int>(i);
        int rows = 0;
        for (int y = y0 - 4; y <= y0 + 4; ++y) {
            if (y < 0 || y >= 64) continue;
            if (lit(*fb, fb->index(32, static_cast<std::uint32_t>(y)), p.scene.draw_list.clear))
                ++rows;
        }
        rows_text += (rows_text.empty() ? "" : ", ") + std::string("width ") +
                     std::to_string(width).substr(0, 3) + ": " + std::to_string(rows) + " rows";
        if (rows != static_cast<int>(std::round(width))) half_away = false;
    }
    f.decided = true;
    f.value = half_away ? "half-away" : "unrounded";
    f.matching = {f.value};
    f.evidence = "probe line_widths column 32: " + rows_text +
                 (half_away ? " (round(width) rows each)" : " (not round(width) rows)");
    return f;
}

// The order in which the attribute planes are set up: the coverage family's (llvmpipe's
// orientation swap and calc_coef4, lp_state_setup.c; softpipe's vertices sorted by y,
// tri_linear_coeff, sp_setup.c), decided with the coverage; the fusion probe's colours, which
// the other family's setup moves, are its evidence.
RuleFinding setup_order_finding(Search& search, const Probe& fusion, const Profile& base,
                                const std::string& family) {
    RuleFinding f;
    f.key = "attribute_setup_order";
    f.candidates = {"snapped", "scanline"};
    if (family != "snapped" && family != "scanline") {
        f.value = "n/a";
        f.decided = true;
        f.evidence = "the exact model has no setup order";
        return f;
    }
    const auto want = search.backend(fusion);
    const auto mine = Search::reference(fusion, base);
    Profile other = family_base(family == "snapped" ? "scanline" : "snapped");
    other.gl.viewport_fma = base.gl.viewport_fma;
    const auto theirs = Search::reference(fusion, other);
    if (!want || !mine || !theirs) {
        f.value = "undecided";
        f.evidence = "the backend does not draw the probe fusion";
        return f;
    }
    const Difference d_mine = difference(fusion, *mine, *want);
    const Difference d_theirs = difference(fusion, *theirs, *want);
    if (d_mine.pixels != 0 || d_theirs.pixels == 0) {
        f.value = "undecided";
        f.evidence = "probe fusion: " + std::to_string(d_mine.pixels) +
                     " pixels differ under the " + family + " setup, " +
                     std::to_string(d_theirs.pixels) + " under the other";
        return f;
    }
    f.value = family;
    f.decided = true;
    f.matching = {family};
    f.evidence = "probe fusion pixel (" + std::to_string(d_theirs.x) + ", " +
                 std::to_string(d_theirs.y) + "): the backend gives " +
                 pixel_text(fusion, *want, d_theirs.x, d_theirs.y) + " as the " + family +
                 " setup does; the other gives " +
                 pixel_text(fusion, *theirs, d_theirs.x, d_theirs.y) + " (" +
                 std::to_string(d_theirs.pixels) + " pixels differ)";
    return f;
}

// Draw state GL requires an implementation to honour, probed as GL draws it and as it is drawn
// with the state ignored: GL_MULTISAMPLE disabled on a 4x target (14.3.1) and a GL_POLYGON's
// edge flags in polygon mode line (14.6.4). A finding, never a profile rule: "honoured",
// "ignored" (which breaks GL), or "n/a" where the backend or the family cannot draw the probe.
struct StateProbe {
    Probe as_gl;          // the state as set
    Scene state_ignored;  // the same scene with the state ignored
};

StateProbe multisample_off_probe() {
    StateProbe p{{"multisample_off", make_scene("multisample_off", 32, 32), Probe::Compare::Exact},
                 {}};
    p.as_gl.scene.file.target.samples = 4;
    p.as_gl.scene.draw_list.target.samples = 4;
    for (int i = 0; i < 4; ++i) {
        const float x = 2.0f + 7.5f * static_cast<float>(i);
        Draw d = window_draw(refraster::PrimitiveType::Triangles,
                             {{x, 1.3f, 0.5f}, {x + 6.7f, 9.1f, 0.5f}, {x + 1.1f, 30.2f, 0.5f}},
                             {kWhite}, 32, 32);
        d.state.multisample = false;
        p.as_gl.scene.draw_list.draws.push_back(d);
    }
    p.state_ignored = *multisample_enable_ignored(p.as_gl.scene);  // rule_search.hpp
    return p;
}

StateProbe edge_flags_probe() {
    StateProbe p{{"edge_flags", make_scene("edge_flags", 32, 32), Probe::Compare::Coverage}, {}};
    Draw d = window_draw(refraster::PrimitiveType::Polygon,
                         {{4.3f, 3.2f, 0.5f},
                          {27.6f, 4.1f, 0.5f},
                          {29.2f, 18.7f, 0.5f},
                          {16.4f, 28.9f, 0.5f},
                          {3.1f, 20.6f, 0.5f}},
                         {kWhite}, 32, 32);
    d.state.polygon_mode = refraster::PolygonMode::Line;
    p.as_gl.scene.draw_list.draws.push_back(d);
    p.state_ignored = *edge_flags_ignored(p.as_gl.scene);  // rule_search.hpp
    return p;
}

RuleFinding state_finding(Search& search, const std::string& key, const StateProbe& p,
                          const Profile& base) {
    RuleFinding f;
    f.key = key;
    f.candidates = {"honoured", "ignored"};
    const auto resolved = [](std::optional<Framebuffer> fb) {
        if (fb && fb->samples > 1) fb = refraster::resolve_samples(*fb);
        return fb;
    };
    const auto want = search.backend(p.as_gl);
    const auto gl = resolved(Search::reference(p.as_gl, base));
    Probe ignored_probe = p.as_gl;
    ignored_probe.scene = p.state_ignored;
    const auto ignored = resolved(Search::reference(ignored_probe, base));
    if (!want || !gl || !ignored) {
        f.value = "n/a";
        f.decided = true;
        f.evidence = std::string(!want ? "the backend" : "the reference under this profile") +
                     " does not draw the probe " + p.as_gl.name;
        return f;
    }
    const Difference d_gl = difference(p.as_gl, *gl, *want);
    const Difference d_ignored = difference(p.as_gl, *ignored, *want);
    if ((d_gl.pixels == 0) == (d_ignored.pixels == 0)) {
        f.value = "undecided";
        f.evidence = "probe " + p.as_gl.name + ": " + std::to_string(d_gl.pixels) +
                     " pixels differ from the state honoured, " + std::to_string(d_ignored.pixels) +
                     " from it ignored";
        return f;
    }
    const bool honoured = d_gl.pixels == 0;
    const Difference& rival = honoured ? d_ignored : d_gl;
    f.value = honoured ? "honoured" : "ignored";
    f.decided = true;
    f.matching = {f.value};
    f.evidence = "probe " + p.as_gl.name + " pixel (" + std::to_string(rival.x) + ", " +
                 std::to_string(rival.y) + "): the backend gives " +
                 pixel_text(p.as_gl, *want, rival.x, rival.y) + " as the state " + f.value +
                 " does; " + (honoured ? "ignored" : "honoured") + " gives " +
                 pixel_text(p.as_gl, honoured ? *ignored : *gl, rival.x, rival.y) + " (" +
                 std::to_string(rival.pixels) + " pixels differ)" +
                 (honoured                      ? ""
                  : key == "multisample_enable" ? "; GL 14.3.1 requires it"
                                                : "; GL 14.6.4 requires them");
    return f;
}

// The probe textures against the profile decided.
RuleFinding texture_finding(Search& search, const Profile& base) {
    RuleFinding f;
    f.key = "texture_sampling";
    f.candidates = {"as the profile", "unmodelled"};
    const Probe p = texture_probe();
    const auto want = search.backend(p);
    const auto ref = Search::reference(p, base);
    if (!want || !ref) {
        f.value = "n/a";
        f.decided = true;
        f.evidence = std::string(!want ? "the backend" : "the reference under this profile") +
                     " does not draw the probe textures";
        return f;
    }
    const Difference d = difference(p, *ref, *want);
    if (d.pixels == 0) {
        f.value = "as the profile";
        f.decided = true;
        f.matching = {f.value};
        f.evidence =
            "probe textures: every pixel of trilinear minification and bilinear "
            "magnification as the profile's sampler gives it";
        return f;
    }
    // The profile has no texture rule to change: a difference is reported, never guessed.
    f.value = "undecided";
    f.evidence = "probe textures pixel (" + std::to_string(d.x) + ", " + std::to_string(d.y) +
                 "): the backend gives " + pixel_text(p, *want, d.x, d.y) +
                 ", the profile's sampler " + pixel_text(p, *ref, d.x, d.y) + " (" +
                 std::to_string(d.pixels) +
                 " pixels differ); no texture rule of the profile reproduces it (LOD and "
                 "filtering arithmetic are modelled only as the two drivers and llvmpipe's "
                 "GALLIVM_PERF options compute them)";
    return f;
}

// GL_POINT_SPRITE_COORD_ORIGIN (OpenGL 4.6, 14.4): two textured point sprites whose texture
// is red at its top row and green at its bottom, drawn with the origin upper-left, then
// lower-left twice, then upper-left again, all through one worker. "honoured" when each render
// is the reference's for its origin; "ignored" when one origin is always drawn as the other;
// "order-dependent" when one origin gives both pictures (a state change the implementation
// misses). A finding, never a profile rule.
Probe sprite_origin_probe(refraster::PointCoordOrigin origin) {
    const bool upper = origin == refraster::PointCoordOrigin::UpperLeft;
    Probe p{upper ? "sprite_origin_upper_left" : "sprite_origin_lower_left",
            make_scene(upper ? "sprite_origin_upper_left" : "sprite_origin_lower_left", 32, 32),
            Probe::Compare::Exact};
    refraster::Texture tex;
    refraster::TextureImage img;
    img.width = 2;
    img.height = 2;
    // Rows bottom to top: green below, red above.
    img.rgba = {0, 255, 0, 255, 0, 255, 0, 255, 255, 0, 0, 255, 255, 0, 0, 255};
    tex.levels.push_back(img);
    p.scene.draw_list.textures.push_back(tex);
    Draw d = window_draw(refraster::PrimitiveType::Points,
                         {{8.0f, 8.0f, 0.5f}, {24.0f, 24.0f, 0.5f}}, {kWhite}, 32, 32);
    d.state.point_size = 12.0f;
    // A textured draw's vertices carry texture coordinates after the colour (the front end's
    // layout); the sprite replaces them.
    with_texcoords(d, {{0.0f, 0.0f, 0.0f, 1.0f}});
    refraster::TextureState t;
    t.min_filter = refraster::TextureFilter::Nearest;
    t.mag_filter = refraster::TextureFilter::Nearest;
    t.wrap_s = refraster::TextureWrap::ClampToEdge;
    t.wrap_t = refraster::TextureWrap::ClampToEdge;
    t.env = refraster::TextureEnv::Replace;
    t.coord_replace = true;
    t.point_coord_origin = origin;
    d.state.texture = t;
    p.scene.draw_list.draws.push_back(d);
    return p;
}

RuleFinding sprite_origin_finding(Search& search, const Profile& base, const FreshBackend& fresh,
                                  const FingerprintProgress& progress) {
    RuleFinding f;
    f.key = "point_sprite_origin";
    f.candidates = {"honoured", "ignored", "order-dependent"};
    const Probe upper = sprite_origin_probe(refraster::PointCoordOrigin::UpperLeft);
    const Probe lower = sprite_origin_probe(refraster::PointCoordOrigin::LowerLeft);
    const auto ref_upper = Search::reference(upper, base);
    const auto ref_lower = Search::reference(lower, base);
    // In this order, through one worker: each origin drawn once after the other origin and
    // once after itself; then, in a fresh worker when one can be had, the same with the
    // origins swapped, so that a worker whose first origin sticks shows both pictures for one
    // origin.
    std::vector<const Probe*> order{&upper, &lower, &lower, &upper};
    std::vector<std::optional<Framebuffer>> got;
    for (const Probe* p : order) got.push_back(search.backend(*p));
    std::unique_ptr<Backend> second = fresh ? fresh() : nullptr;
    if (second) {
        Search again(*second, progress);
        for (const Probe* p : {&lower, &upper, &upper, &lower}) {
            order.push_back(p);
            got.push_back(again.backend(*p));
        }
    }
    if (!ref_upper || !ref_lower ||
        std::any_of(got.begin(), got.end(), [](const auto& g) { return !g.has_value(); })) {
        f.value = "n/a";
        f.decided = true;
        f.evidence = std::string(!ref_upper || !ref_lower ? "the reference under this profile"
                                                          : "the backend") +
                     " does not draw the point sprite probes";
        return f;
    }
    std::vector<bool> own, other;  // each render is its origin's picture, or the other's
    for (std::size_t k = 0; k < order.size(); ++k) {
        const bool is_upper = order[k] == &upper;
        own.push_back(difference(*order[k], is_upper ? *ref_upper : *ref_lower, *got[k]).pixels ==
                      0);
        other.push_back(difference(*order[k], is_upper ? *ref_lower : *ref_upper, *got[k]).pixels ==
                        0);
    }
    const auto text = [&](std::size_t k) {
        const Difference d =
            difference(*order[k], order[k] == &upper ? *ref_upper : *ref_lower, *got[k]);
        return "render " + std::to_string(k + 1) + " (" + order[k]->name + ") " +
               (own[k] ? "matches its origin"
                       : std::string(other[k] ? "shows the other origin" : "matches neither") +
                             " at (" + std::to_string(d.x) + ", " + std::to_string(d.y) +
                             "): " + pixel_text(*order[k], *got[k], d.x, d.y) +
                             " where the reference gives " +
                             pixel_text(*order[k], order[k] == &upper ? *ref_upper : *ref_lower,
                                        d.x, d.y));
    };
    std::string evidence =
        std::string("probes sprite_origin_upper_left, _lower_left twice, _upper_left in turn") +
        (second ? ", then in a fresh worker _lower_left, _upper_left twice, _lower_left: "
                : " (no fresh worker to swap them in): ");
    std::string wrong;
    for (std::size_t k = 0; k < order.size(); ++k)
        if (!own[k]) wrong += (wrong.empty() ? "" : "; ") + text(k);
    f.evidence = evidence + (wrong.empty() ? "each of the " + std::to_string(order.size()) +
                                                 " renders matches its origin"
                                           : wrong);
    // Per origin: whether every render of it shows its own picture, or every one the other's.
    const auto every = [&](bool of_upper, const std::vector<bool>& v) {
        for (std::size_t k = 0; k < order.size(); ++k)
            if ((order[k] == &upper) == of_upper && !v[k]) return false;
        return true;
    };
    const auto some = [&](bool of_upper, const std::vector<bool>& v) {
        for (std::size_t k = 0; k < order.size(); ++k)
            if ((order[k] == &upper) == of_upper && v[k]) return true;
        return false;
    };
    if (every(true, own) && every(false, own)) {
        f.value = "honoured";
    } else if ((some(true, own) && some(true, other)) || (some(false, own) && some(false, other))) {
        f.value = "order-dependent";
        f.evidence +=
            "; the same origin gives either picture, as the render before it set "
            "(GL 14.4 requires the origin set)";
    } else if ((every(true, own) && every(false, other)) ||
               (every(false, own) && every(true, other))) {
        f.value = "ignored";
        f.evidence += "; one origin is always drawn as the other (GL 14.4 requires it)";
        if (!second) f.evidence += ", or the worker's first origin sticks";
    } else {
        f.value = "undecided";
        return f;
    }
    f.decided = true;
    f.matching = {f.value};
    return f;
}

// A rule left at `base`'s value without a probe, and why.
RuleFinding not_probed(const Profile& base, const std::string& key, const std::string& why) {
    RuleFinding f;
    f.key = key;
    f.probed = false;
    for (const auto& [k, v] : refraster::profile_parameters(base))
        if (k == key) f.value = v;
    f.evidence = "not probed: " + why;
    return f;
}

// Every combination of `keys`' searched values (rule_search.hpp), each added to every
// assignment of `with`.
std::vector<Assignment> product(std::vector<Assignment> with,
                                const std::vector<std::string>& keys) {
    for (const auto& key : keys) {
        std::vector<Assignment> wider;
        for (const auto& partial : with) {
            for (const auto& v : search_values(key)) {
                wider.push_back(partial);
                wider.back()[key] = v;
            }
        }
        with = std::move(wider);
    }
    return with;
}

// The snapped model's snapping: every subpixel precision, rounding, pixel centre and tie rule.
std::vector<Assignment> snapping_grid() {
    std::vector<Assignment> grid;
    for (int bits = 1; bits <= 8; ++bits)
        for (const char* rounding : {"nearest-even", "half-away", "truncate"})
            for (const char* offset : {"0.5", "0"})
                for (const char* tie : {"left-bottom", "left-top", "right-bottom", "right-top"})
                    grid.push_back({{"subpixel_bits", std::to_string(bits)},
                                    {"snap_rounding", rounding},
                                    {"pixel_center_offset", offset},
                                    {"tie_rule", tie}});
    return grid;
}

// One class of primitive against rules the profile holds for every class but decided from
// another (`source`): `candidates` tried on the class's own probes. "as <source>" (decided)
// when the profile's own values reproduce them; "differs" (undecided) when only other values
// do, named with a pixel: one profile holds one value of these rules for every class, so the
// class keeps <source>'s and its cases may differ; "undecided" when no candidate does.
RuleFinding class_finding(Search& search, const std::string& key, const std::vector<Probe>& probes,
                          const Profile& base, const std::vector<Assignment>& candidates,
                          const std::string& source) {
    RuleFinding f;
    f.key = key;
    f.candidates = {"as " + source, "differs"};
    const Reproduction rep = reproduce(search, probes, base, candidates);
    std::size_t own = candidates.size();
    std::size_t count = 0;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
        if (own == candidates.size() && with(base, candidates[c]) == base) own = c;
        if (rep.reproduces(c)) ++count;
    }
    std::string names;
    for (const auto& p : probes) names += (names.empty() ? "" : ", ") + p.name;
    const std::string of = std::to_string(count) + " of " + std::to_string(candidates.size());
    if (!rep.any) {
        f.value = "n/a";
        f.decided = true;
        f.evidence = "the backend draws none of the probes " + names;
        return f;
    }
    if (own == candidates.size()) {
        // A value outside the searched ones (a hand-written family default): nothing to compare.
        f.value = "undecided";
        f.evidence = "the profile's values are none of the " + of + " candidates tried";
        return f;
    }
    if (rep.reproduces(own)) {
        f.value = "as " + source;
        f.decided = true;
        f.matching = {f.value};
        f.evidence = (probes.size() > 1 ? "probes " : "probe ") + names +
                     ": every pixel as the profile's " + assignment_text(candidates[own]) +
                     " gives it (" + of + " candidates reproduce them" +
                     (count == candidates.size() ? ": this class does not show these rules)" : ")");
        return f;
    }
    // The first probe pixel where the profile's own values differ from the backend.
    std::string where;
    const Profile mine = with(base, candidates[own]);
    for (std::size_t i = 0; i < probes.size() && where.empty(); ++i) {
        if (!rep.want[i]) continue;
        const auto got = Search::reference(probes[i], mine);
        if (!got) continue;
        const Difference d = difference(probes[i], *got, *rep.want[i]);
        if (d.pixels == 0) continue;
        where = "probe " + probes[i].name + " pixel (" + std::to_string(d.x) + ", " +
                std::to_string(d.y) + "): the backend gives " +
                pixel_text(probes[i], *rep.want[i], d.x, d.y) + ", the profile's " +
                assignment_text(candidates[own]) + " " + pixel_text(probes[i], *got, d.x, d.y) +
                " (" + std::to_string(d.pixels) + " pixels differ)";
    }
    if (count > 0) {
        std::size_t first = 0;
        while (!rep.reproduces(first)) ++first;
        f.value = "differs";
        f.matching = {"differs"};
        f.evidence = where + "; " + assignment_text(candidates[first]) +
                     (count > 1 ? " and " + std::to_string(count - 1) + " other candidates" : "") +
                     " reproduce every pixel. One profile holds one value for every class: "
                     "this class keeps " +
                     source + "'s, and its cases may differ";
        return f;
    }
    const std::size_t best = rep.closest();
    f.value = "undecided";
    f.evidence = where + "; no candidate reproduces the probes (the closest, " +
                 assignment_text(candidates[best]) + ", differs in " +
                 std::to_string(rep.total[best]) + " pixels)";
    return f;
}

}  // namespace

bool FingerprintResult::complete() const {
    return std::all_of(rules.begin(), rules.end(),
                       [](const RuleFinding& f) { return !f.probed || f.decided; });
}

FingerprintResult fingerprint(Backend& target, const FingerprintProgress& progress,
                              const FreshBackend& fresh) {
    Search search(target, progress);
    FingerprintResult r;
    r.backend = target.name();
    Assignment decided;

    // 1. Coverage: the model and, for the snapped one, its four parameters, jointly.
    std::vector<Assignment> coverage = snapping_grid();
    for (auto& a : coverage) a["coverage"] = "snapped";
    coverage.push_back({{"coverage", "scanline"}});
    for (const char* tie : {"left-bottom", "left-top", "right-bottom", "right-top"})
        coverage.push_back({{"coverage", "exact"}, {"tie_rule", tie}});
    search.say("coverage: " + std::to_string(coverage.size()) + " candidates");
    run_stage(search, {triangle_probe()}, refraster::llvmpipe_22_3_profile(), coverage,
              {"coverage", "subpixel_bits", "snap_rounding", "pixel_center_offset", "tie_rule"},
              r.rules, decided);
    const std::string family = decided.count("coverage") ? decided["coverage"] : "snapped";
    Profile base = family_base(family);
    for (const auto& [k, v] : decided) refraster::set_profile_parameter(base, k, v);
    // Each rule's values are the ones explain and the GL verdict search (rule_search.hpp); the
    // rules of one stage are decided jointly, over every combination of their values.
    const auto stage = [&](const std::vector<Probe>& probes, const std::vector<std::string>& keys) {
        // A rule the family's model does not read cannot be seen in any probe; nor can a
        // texture rule in the texture probe's triangles unless they are snapped (the scanline
        // model samples them by softpipe's rules).
        auto why = refraster::unread_parameter(base, keys.front());
        if (!why && keys.front().rfind("texture_", 0) == 0 &&
            base.model != refraster::CoverageModel::Snapped)
            why = "the texture probe's triangles sample by softpipe's rules under this model";
        if (why) {
            for (const auto& key : keys) r.rules.push_back(not_probed(base, key, *why));
            return;
        }
        run_stage(search, probes, base, product({{}}, keys), keys, r.rules, decided);
        for (const auto& key : keys)
            if (decided.count(key)) refraster::set_profile_parameter(base, key, decided[key]);
    };

    // 2. Lines and points, then the clipper (whose probe has both).
    const Probe widths = line_width_probe();
    stage({line_probe()}, {"line_rule"});
    r.rules.push_back(line_width_finding(widths, search.backend(widths)));
    stage({point_probe()}, {"point_rule"});
    // Clipping per primitive class: points and wide lines here (their coverage), triangles
    // below, once the arithmetic their float colours show is decided.
    stage({clipping_probe()}, {"point_line_clipping"});
    // 3. Arithmetic: fusion, depth, clears, colours.
    const Probe fusion = fusion_probe();
    stage({fusion}, {"viewport_fma"});
    r.rules.push_back(setup_order_finding(search, fusion, base, family));
    stage({triangle_clipping_probe()}, {"clipping"});
    // The guard band for triangles implies it for points and lines: point_line_clipping then
    // keeps its default, "as clipping says".
    if (decided.count("clipping") && decided["clipping"] == "guard-band" &&
        base.gl.point_line_clipping == refraster::PointLineClipping::Pixels) {
        refraster::set_profile_parameter(base, "point_line_clipping", "vertices");
        for (auto& f : r.rules) {
            if (f.key == "point_line_clipping") {
                f.value = "vertices";
                f.evidence += " (implied by clipping=guard-band, which the profile keeps)";
            }
        }
    }
    stage({depth_probe()}, {"depth_rounding"});
    stage(offset_probes(), {"offset_units_scale"});
    stage(clear_probes(), {"depth_clear"});
    stage({color_probe()}, {"color_rounding"});

    // 3b. Each primitive class against the rules one profile holds for all of them but that
    // were decided from one class or from the classes together: the triangles' snapping on
    // lines and on points (with each class's own rule), point_line_clipping on points alone
    // and on wide lines alone, and the triangles' depth and colour conversions on each.
    const auto lines = refraster::PrimitiveType::Lines;
    const auto points = refraster::PrimitiveType::Points;
    // A finding whose rules the family's model does not read is not probed (`read_key` one of
    // them).
    const auto per_class = [&](const std::string& key, const std::vector<Probe>& probes,
                               const std::vector<Assignment>& candidates,
                               const std::string& read_key, const std::string& source) {
        if (const auto why = refraster::unread_parameter(base, read_key)) {
            r.rules.push_back(not_probed(base, key, *why));
            r.rules.back().value = "n/a";
            return;
        }
        r.rules.push_back(class_finding(search, key, probes, base, candidates, source));
    };
    per_class("line_snapping", {line_probe()}, product(snapping_grid(), {"line_rule"}),
              "subpixel_bits", "the profile's snapping");
    per_class("point_snapping", {point_probe()}, product(snapping_grid(), {"point_rule"}),
              "subpixel_bits", "the profile's snapping");
    per_class("point_clipping", {clipping_class_probe(points)},
              product({{}}, {"point_line_clipping"}), "point_line_clipping",
              "points and lines together");
    per_class("line_clipping", {clipping_class_probe(lines)},
              product({{}}, {"point_line_clipping"}), "point_line_clipping",
              "points and lines together");
    for (const auto t : {lines, points}) {
        per_class(t == lines ? "line_precision" : "point_precision",
                  {class_depth_probe(t), class_color_probe(t)},
                  product({{}}, {"depth_rounding", "color_rounding"}), "depth_rounding",
                  "triangles");
    }

    // viewport_fma: the family's "auto" where the observation is what auto gives on this CPU.
    for (auto& f : r.rules) {
        if (f.key == "viewport_fma" && f.decided &&
            family_base(family).gl.viewport_fma == refraster::FmaMode::Auto &&
            (f.value == "on") == refraster::host_has_fma()) {
            f.evidence += " (what auto gives on this CPU)";
            f.value = "auto";
            refraster::set_profile_parameter(base, "viewport_fma", "auto");
        }
    }
    // 4. Draw state GL requires honoured (findings only).
    r.rules.push_back(state_finding(search, "multisample_enable", multisample_off_probe(), base));
    r.rules.push_back(state_finding(search, "edge_flags", edge_flags_probe(), base));
    r.rules.push_back(sprite_origin_finding(search, base, fresh, progress));
    // 5. Textures: the LOD's rho, the mip blend and the filtering arithmetic, jointly (llvmpipe
    // takes another brilinear path when rho is not squared, and the mip fraction is quantised
    // on the fixed-point path only, so none can be decided alone); then the probe compared
    // with the profile decided (a finding).
    stage({texture_probe()}, {"texture_rho", "texture_mip_blend", "texture_filtering"});
    r.rules.push_back(texture_finding(search, base));

    for (const char* key :
         {"flush_denormals", "draw_pipeline_cull", "draw_segment_vertices", "nine_vertex_quirk",
          "wrapping_arithmetic", "draw_offset_nan_to_zero", "fill_clear_writes_tiles"}) {
        r.rules.push_back(not_probed(base, key, "the " + family + " family's default"));
    }
    // The name: the family's built-in, followed by the rules that differ from it
    // ("llvmpipe-22.3+tie_rule=right-top").
    base.name = family_base(family).name;
    name_by_rules(base);
    r.profile = base;
    return r;
}

std::string fingerprint_text(const FingerprintResult& r) {
    std::string s;
    for (const auto& f : r.rules) {
        std::string line = f.key + " = " + f.value;
        if (line.size() < 34) line.resize(34, ' ');
        s += line + "  " + f.evidence + "\n";
    }
    s += "profile: " + r.profile.name + (r.complete() ? "" : " (some rules undecided)") + "\n";
    return s;
}

std::string fingerprint_json(const FingerprintResult& r) {
    nlohmann::ordered_json j;
    j["backend"] = r.backend;
    j["complete"] = r.complete();
    nlohmann::ordered_json prof;
    for (const auto& [k, v] : refraster::profile_parameters(r.profile)) prof[k] = v;
    j["profile"] = prof;
    j["rules"] = nlohmann::json::array();
    for (const auto& f : r.rules) {
        j["rules"].push_back({{"key", f.key},
                              {"value", f.value},
                              {"decided", f.decided},
                              {"probed", f.probed},
                              {"candidates", f.candidates},
                              {"matching", f.matching},
                              {"evidence", f.evidence},
                              {"gl", f.decided ? gl_standing(f.key, f.value) : ""}});
    }
    return j.dump(2);
}

}  // namespace harness
