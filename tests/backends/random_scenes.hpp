// Random triangle scenes for the backend comparison tests: a 256x256 target of 16 cells, one
// triangle per cell with the cell as viewport and scissor.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "harness/scene.hpp"

namespace testscenes {

// The third seed of every random backend test: REFRASTER_TEST_SEED, 3 without it (.ci/run keeps
// 3, so that CI's verdict does not depend on the day; other seeds are swept by setting it).
inline std::uint64_t ci_seed() {
    const char* s = std::getenv("REFRASTER_TEST_SEED");
    return s != nullptr && *s != '\0' ? std::strtoull(s, nullptr, 10) : 3;
}

constexpr int kGrid = 4;
constexpr int kCell = 64;
constexpr int kCells = kGrid * kGrid;
constexpr int kSize = kGrid * kCell;

struct CellTriangle {
    std::array<std::array<float, 4>, 3> clip{};
    refraster::CullMode cull = refraster::CullMode::None;
    refraster::FrontFace front_face = refraster::FrontFace::Ccw;
    refraster::ProvokingVertex provoking = refraster::ProvokingVertex::Last;
    std::array<float, 4> color{};
};

struct CategoryCounts {
    int total = 0;
    int crossing = 0;       // some vertex outside the viewport in x or y
    int centre_edges = 0;   // an edge passes exactly through a pixel centre
    int w_nonpositive = 0;  // some vertex has w <= 0
};

class CoverageGenerator {
  public:
    explicit CoverageGenerator(std::uint64_t seed) : rng_(seed) {}

    std::vector<CellTriangle> next_batch(CategoryCounts& counts) {
        std::vector<CellTriangle> cells(kCells);
        for (int i = 0; i < kCells; ++i) {
            CellTriangle& t = cells[static_cast<std::size_t>(i)];
            const float r = uniform(0, 1);
            bool centre = false;
            if (r < 0.28f) {
                for (auto& v : t.clip) v = random_vertex(0.95f, 0.25f, 4.0f);
            } else if (r < 0.56f) {
                for (auto& v : t.clip) v = random_vertex(2.5f, 0.25f, 4.0f);
            } else if (r < 0.90f) {
                centre = true;
                centre_triangle(t);
            } else {
                for (auto& v : t.clip) v = random_vertex(1.5f, 0.25f, 4.0f);
                const int behind = 1 + static_cast<int>(uniform(0, 2) >= 1.0f);
                for (int k = 0; k < behind; ++k) {
                    auto& v = t.clip[static_cast<std::size_t>(k)];
                    v[3] = uniform(0, 1) < 0.2f ? 0.0f : -uniform(0.1f, 2.0f);
                    v[0] = uniform(-2, 2);
                    v[1] = uniform(-2, 2);
                }
            }
            const float c = uniform(0, 1);
            t.cull = c < 0.5f   ? refraster::CullMode::None
                     : c < 0.7f ? refraster::CullMode::Back
                     : c < 0.9f ? refraster::CullMode::Front
                                : refraster::CullMode::FrontAndBack;
            if (t.cull == refraster::CullMode::FrontAndBack && uniform(0, 1) < 0.7f)
                t.cull = refraster::CullMode::None;
            t.front_face =
                uniform(0, 1) < 0.5f ? refraster::FrontFace::Ccw : refraster::FrontFace::Cw;
            t.provoking = uniform(0, 1) < 0.5f ? refraster::ProvokingVertex::Last
                                               : refraster::ProvokingVertex::First;
            t.color = {static_cast<float>(16 * i + 15) / 255.0f, 1.0f,
                       static_cast<float>(counts.total % 255) / 255.0f, 1.0f};
            ++counts.total;
            bool crossing = false;
            bool behind = false;
            for (const auto& v : t.clip) {
                crossing = crossing || v[0] > v[3] || v[0] < -v[3] || v[1] > v[3] || v[1] < -v[3];
                behind = behind || v[3] <= 0.0f;
            }
            counts.crossing += crossing;
            counts.centre_edges += centre;
            counts.w_nonpositive += behind;
        }
        return cells;
    }

  private:
    float uniform(float lo, float hi) {
        return std::uniform_real_distribution<float>(lo, hi)(rng_);
    }
    int uniform_int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

    // NDC in [-range, range], random w: clip = ndc * w, so every mantissa bit is used.
    std::array<float, 4> random_vertex(float range, float wlo, float whi) {
        const float w = uniform(wlo, whi);
        return {uniform(-range, range) * w, uniform(-range, range) * w, uniform(-0.9f, 0.9f) * w,
                w};
    }

    // Two vertices on pixel centres an even number of pixels apart, so the edge between them
    // passes exactly through the centre halfway; the third anywhere. w is a power of two and
    // the cell 64 pixels wide, so window coordinates come back exactly.
    void centre_triangle(CellTriangle& t) {
        const float w =
            std::array<float, 3>{0.5f, 1.0f, 2.0f}[static_cast<std::size_t>(uniform_int(0, 2))];
        const auto clip_of = [&](float wx, float wy) {
            return std::array<float, 4>{(wx / 32.0f - 1.0f) * w, (wy / 32.0f - 1.0f) * w, 0.0f, w};
        };
        const int ax = uniform_int(-12, 75);
        const int ay = uniform_int(-12, 75);
        int dx = 2 * uniform_int(-12, 12);
        int dy = 2 * uniform_int(-12, 12);
        if (uniform(0, 1) < 0.3f) dy = 0;  // horizontal and vertical edges through centres
        if (uniform(0, 1) < 0.15f) dx = 0;
        if (dx == 0 && dy == 0) dx = 4;
        t.clip[0] = clip_of(static_cast<float>(ax) + 0.5f, static_cast<float>(ay) + 0.5f);
        t.clip[1] = clip_of(static_cast<float>(ax + dx) + 0.5f, static_cast<float>(ay + dy) + 0.5f);
        const bool grid = uniform(0, 1) < 0.5f;
        const float cx = grid ? static_cast<float>(uniform_int(-12, 75)) + 0.5f : uniform(-12, 76);
        const float cy = grid ? static_cast<float>(uniform_int(-12, 75)) + 0.5f : uniform(-12, 76);
        t.clip[2] = clip_of(cx, cy);
        // Shuffle so the centre edge is any of the three.
        std::shuffle(t.clip.begin(), t.clip.end(), rng_);
    }

    std::mt19937_64 rng_;
};

inline harness::Scene cell_scene(const std::vector<CellTriangle>& cells) {
    harness::Scene s;
    s.path = "random-cells";
    s.file.name = "random";
    s.file.target = {kSize, kSize, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    s.file.clear.color = {0, 0, 0, 1};
    s.draw_list.target = s.file.target;
    s.draw_list.clear = s.file.clear;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const auto& c = cells[i];
        refraster::Draw d;
        d.primitive = refraster::PrimitiveType::Triangles;
        const int cx = static_cast<int>(i % kGrid) * kCell;
        const int cy = static_cast<int>(i / kGrid) * kCell;
        d.state.viewport = {cx, cy, kCell, kCell};
        d.state.scissor = refraster::Rect{cx, cy, kCell, kCell};
        d.state.shade = refraster::ShadeModel::Flat;
        d.state.cull = c.cull;
        d.state.front_face = c.front_face;
        d.state.provoking_vertex = c.provoking;
        d.vertices.attributes = {{"color", 4}};
        for (const auto& v : c.clip) {
            d.vertices.data.insert(d.vertices.data.end(), v.begin(), v.end());
            d.vertices.data.insert(d.vertices.data.end(), c.color.begin(), c.color.end());
        }
        s.draw_list.draws.push_back(std::move(d));
    }
    return s;
}

inline std::string describe(const CellTriangle& t) {
    std::string s = "clip";
    char buf[160];
    for (const auto& v : t.clip) {
        std::snprintf(buf, sizeof buf, " (%a, %a, %a, %a)", static_cast<double>(v[0]),
                      static_cast<double>(v[1]), static_cast<double>(v[2]),
                      static_cast<double>(v[3]));
        s += buf;
    }
    std::snprintf(buf, sizeof buf, " cull %d front_face %d provoking %d", static_cast<int>(t.cull),
                  static_cast<int>(t.front_face), static_cast<int>(t.provoking));
    return s + buf;
}

}  // namespace testscenes

namespace testscenes {

// Cells of several overlapping, depth-tested triangles with random per-vertex colours,
// depth and w, and a random draw state from the fragment stage's options.
struct AttributeCell {
    std::vector<CellTriangle> tris;
    std::vector<std::array<std::array<float, 4>, 3>> colors;  // per triangle, per vertex
    refraster::ShadeModel shade = refraster::ShadeModel::Smooth;
    std::optional<refraster::CompareFunc> depth_test;
    bool depth_write = true;
    refraster::BlendPreset blend = refraster::BlendPreset::None;
    std::optional<refraster::PolygonOffset> offset;
    std::array<float, 2> depth_range{0.0f, 1.0f};
};

struct AttributeOptions {
    int triangles_per_cell = 2;
    bool vary_shade = false;  // flat and noperspective too, not only smooth
    bool vary_state = false;  // blending, polygon offset, depth write, depth range
};

class AttributeGenerator {
  public:
    AttributeGenerator(std::uint64_t seed, AttributeOptions o) : rng_(seed), o_(o) {}

    std::vector<AttributeCell> next_batch() {
        std::vector<AttributeCell> cells(kCells);
        static constexpr refraster::CompareFunc funcs[] = {
            refraster::CompareFunc::Less,    refraster::CompareFunc::Lequal,
            refraster::CompareFunc::Greater, refraster::CompareFunc::Gequal,
            refraster::CompareFunc::Equal,   refraster::CompareFunc::NotEqual,
            refraster::CompareFunc::Always,  refraster::CompareFunc::Never};
        for (auto& c : cells) {
            const float pick = uniform(0, 1);
            c.depth_test = pick < 0.5f ? refraster::CompareFunc::Less
                                       : funcs[static_cast<std::size_t>(uniform_int(0, 7))];
            if (o_.vary_shade) {
                const int s = uniform_int(0, 3);
                c.shade = s == 0   ? refraster::ShadeModel::Flat
                          : s == 1 ? refraster::ShadeModel::NoPerspective
                                   : refraster::ShadeModel::Smooth;
            }
            if (o_.vary_state) {
                c.depth_write = uniform(0, 1) < 0.8f;
                const int b = uniform_int(0, 3);
                c.blend = b == 0   ? refraster::BlendPreset::Alpha
                          : b == 1 ? refraster::BlendPreset::Add
                                   : refraster::BlendPreset::None;
                if (uniform(0, 1) < 0.4f) {
                    c.offset =
                        refraster::PolygonOffset{static_cast<float>(uniform_int(-4, 4)) * 0.5f,
                                                 static_cast<float>(uniform_int(-8, 8))};
                }
                if (uniform(0, 1) < 0.3f) c.depth_range = {uniform(0, 1), uniform(0, 1)};
            }
            for (int t = 0; t < o_.triangles_per_cell; ++t) {
                CellTriangle tri;
                const bool cross = uniform(0, 1) < 0.3f;
                for (auto& v : tri.clip) {
                    const float w = uniform(0.25f, 4.0f);
                    const float r = cross ? 1.6f : 0.95f;
                    v = {uniform(-r, r) * w, uniform(-r, r) * w, uniform(-0.99f, 0.99f) * w, w};
                }
                tri.provoking = uniform(0, 1) < 0.5f ? refraster::ProvokingVertex::Last
                                                     : refraster::ProvokingVertex::First;
                std::array<std::array<float, 4>, 3> col{};
                for (auto& vc : col) {
                    for (auto& ch : vc)
                        ch = uniform(0, 1) < 0.1f ? uniform(-0.3f, 1.3f) : uniform(0, 1);
                }
                c.tris.push_back(tri);
                c.colors.push_back(col);
            }
        }
        return cells;
    }

  private:
    float uniform(float lo, float hi) {
        return std::uniform_real_distribution<float>(lo, hi)(rng_);
    }
    int uniform_int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
    std::mt19937_64 rng_;
    AttributeOptions o_;
};

inline harness::Scene attribute_scene(const std::vector<AttributeCell>& cells,
                                      refraster::DepthFormat depth, refraster::ColorFormat color,
                                      std::array<float, 4> clear_color, float clear_depth) {
    harness::Scene s;
    s.path = "random-attribute-cells";
    s.file.name = "random";
    s.file.target = {kSize, kSize, color, depth, 1};
    s.file.clear.color = clear_color;
    s.file.clear.depth = clear_depth;
    s.draw_list.target = s.file.target;
    s.draw_list.clear = s.file.clear;
    for (std::size_t i = 0; i < cells.size(); ++i) {
        const auto& c = cells[i];
        const int cx = static_cast<int>(i % kGrid) * kCell;
        const int cy = static_cast<int>(i / kGrid) * kCell;
        for (std::size_t t = 0; t < c.tris.size(); ++t) {
            refraster::Draw d;
            d.primitive = refraster::PrimitiveType::Triangles;
            d.state.viewport = {cx, cy, kCell, kCell};
            d.state.scissor = refraster::Rect{cx, cy, kCell, kCell};
            d.state.shade = c.shade;
            d.state.depth_test = c.depth_test;
            d.state.depth_write = c.depth_write;
            d.state.blend = c.blend;
            d.state.polygon_offset = c.offset;
            d.state.depth_near = c.depth_range[0];
            d.state.depth_far = c.depth_range[1];
            d.state.provoking_vertex = c.tris[t].provoking;
            d.vertices.attributes = {{"color", 4}};
            for (std::size_t v = 0; v < 3; ++v) {
                const auto& p = c.tris[t].clip[v];
                d.vertices.data.insert(d.vertices.data.end(), p.begin(), p.end());
                d.vertices.data.insert(d.vertices.data.end(), c.colors[t][v].begin(),
                                       c.colors[t][v].end());
            }
            s.draw_list.draws.push_back(std::move(d));
        }
    }
    return s;
}

inline std::string describe(const AttributeCell& c) {
    std::string s;
    for (std::size_t t = 0; t < c.tris.size(); ++t) {
        s += "\n  triangle " + std::to_string(t) + ": " + describe(c.tris[t]) + " colours";
        char buf[64];
        for (const auto& v : c.colors[t]) {
            for (float ch : v) {
                std::snprintf(buf, sizeof buf, " %a", static_cast<double>(ch));
                s += buf;
            }
            s += " |";
        }
    }
    char buf[200];
    std::snprintf(
        buf, sizeof buf, "\n  shade %d depth_test %d write %d blend %d offset %s range %g %g",
        static_cast<int>(c.shade), c.depth_test ? static_cast<int>(*c.depth_test) : -1,
        static_cast<int>(c.depth_write), static_cast<int>(c.blend),
        c.offset
            ? (std::to_string(c.offset->factor) + "," + std::to_string(c.offset->units)).c_str()
            : "none",
        static_cast<double>(c.depth_range[0]), static_cast<double>(c.depth_range[1]));
    return s + buf;
}

// The two renderers every random test compares: the reference under `profile`, and OSMesa
// llvmpipe.
// A draw list of clip-space draws (colour attribute first) as a scene file, for writing a
// failing batch to JSON (REFRASTER_DUMP_SCENE) and rerunning it with the CLI.
inline harness::SceneFile scene_file_of(const harness::SceneFile& base,
                                        const refraster::DrawList& l) {
    harness::SceneFile f = base;
    f.draws.clear();
    for (const auto& d : l.draws) {
        harness::SceneDraw sd;
        sd.primitive = d.primitive;
        sd.space = harness::VertexSpace::Clip;
        sd.state = d.state;
        sd.indices = d.indices;
        const std::size_t stride = d.vertices.stride();
        for (std::size_t v = 0; v < d.vertices.size(); ++v) {
            harness::SceneVertex sv;
            for (std::size_t k = 0; k < 4; ++k) sv.position[k] = d.vertices.data[v * stride + k];
            sv.position_size = 4;
            for (std::size_t k = 0; k < 4 && stride >= 8; ++k)
                sv.color[k] = d.vertices.data[v * stride + 4 + k];
            sd.vertices.push_back(sv);
        }
        f.draws.push_back(sd);
    }
    return f;
}

struct Renderers {
    std::unique_ptr<harness::Backend> ref;
    std::unique_ptr<harness::Backend> osmesa;
};

inline Renderers make_renderers(const refraster::Profile& profile = {},
                                harness::Driver driver = harness::Driver::Llvmpipe) {
    harness::BackendOptions gl;
    gl.kind = harness::BackendKind::OSMesa;
    gl.driver = driver;
    harness::BackendOptions ro;
    ro.profile = profile;
    return {harness::make_backend(ro), harness::make_backend(gl)};
}

// Pixels of cell i that differ in colour (rgba8 bytes or rgba32f bits) or depth.
inline std::uint64_t cell_differences(const refraster::Framebuffer& a,
                                      const refraster::Framebuffer& b, std::size_t i) {
    const std::uint32_t cx = static_cast<std::uint32_t>(i % kGrid) * kCell;
    const std::uint32_t cy = static_cast<std::uint32_t>(i / kGrid) * kCell;
    std::uint64_t n = 0;
    for (std::uint32_t y = cy; y < cy + kCell; ++y) {
        for (std::uint32_t x = cx; x < cx + kCell; ++x) {
            const std::size_t p = a.index(x, y);
            bool diff = !a.depth.empty() && a.depth[p] != b.depth[p];
            for (std::size_t k = 0; k < 4 && !diff; ++k) {
                diff = a.color_format == refraster::ColorFormat::Rgba8
                           ? a.color8[4 * p + k] != b.color8[4 * p + k]
                           : std::bit_cast<std::uint32_t>(a.color32f[4 * p + k]) !=
                                 std::bit_cast<std::uint32_t>(b.color32f[4 * p + k]);
            }
            n += diff;
        }
    }
    return n;
}

}  // namespace testscenes
