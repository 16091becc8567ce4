// Random triangles, lines and points on a 4x multisampled target through the reference
// (llvmpipe-22.3) and OSMesa llvmpipe, compared sample by sample: every sample's colour and
// depth, and the resolved image, must agree exactly. Seeds: two fixed, one from
// REFRASTER_TEST_SEED (3 unless set).
//
// Each scene is a 256x256 4x target cut into 64 cells of 32x32; every cell holds one
// primitive (a triangle, a line, a strip or loop of lines, or up to three points) drawn with
// the cell as viewport and scissor, so primitives never touch one another and a mismatch
// names its primitive. Per seed: 5,000 triangles (smooth and flat, both windings, blending on
// and off, on z24 and z32f targets, vertices on the 1/256 grid, at full float precision and a
// quarter with an edge or a vertex exactly on a sample position), 2,000 lines (widths 0.5 to
// 4, including 0.5, 1, 1.5, 2 and 3) and 1,000 points (sizes 0.7 to 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "harness/files.hpp"
#include "harness/reduce.hpp"
#include "harness/scene.hpp"
#include "random_scenes.hpp"
#include "refraster/framebuffer.hpp"

namespace {

constexpr int kCell = 32;
constexpr int kGrid = 8;
constexpr int kCells = kGrid * kGrid;
constexpr int kSize = kCell * kGrid;
constexpr int kSamples = 4;

// The 4x sample positions from the pixel's bottom-left corner (docs/precision.md, "Multisampling
// (4x)").
constexpr std::array<std::array<float, 2>, 4> kSamplePos{
    {{0.375f, 0.125f}, {0.875f, 0.375f}, {0.125f, 0.625f}, {0.625f, 0.875f}}};

constexpr std::array<float, 5> kLineWidths{0.5f, 1.0f, 1.5f, 2.0f, 3.0f};
constexpr std::array<float, 7> kPointSizes{0.7f, 1.0f, 1.5f, 2.0f, 2.5f, 3.0f, 4.0f};

enum class Kind { Triangle, Line, Point };

struct Counts {
    int triangles = 0;
    int lines = 0;  // segments
    int points = 0;
    int on_sample = 0;  // triangles with an edge or a vertex exactly on a sample position
    int grid = 0;       // triangles with every vertex on the 1/256 grid (on_sample included)
    int full_float = 0;
    int flat = 0;
    int smooth = 0;
    int blended = 0;
    int ccw = 0;  // window-space winding of the triangles that are not degenerate
    int cw = 0;
    int z24 = 0;
    int z32f = 0;
    std::array<int, kLineWidths.size()> widths{};  // lines of each of the listed widths
    std::array<int, kPointSizes.size()> sizes{};   // points of each of the listed sizes
};

struct Cell {
    Kind kind = Kind::Triangle;
    refraster::Draw draw;
};

class MsaaGenerator {
  public:
    explicit MsaaGenerator(std::uint64_t seed) : rng_(seed) {}

    // One batch: a cell for each of kCells primitives, chosen by what is still wanted.
    std::vector<Cell> next_batch(Counts& counts, int triangles, int lines, int points,
                                 refraster::DepthFormat depth) {
        std::vector<Cell> cells;
        for (int i = 0; i < kCells; ++i) {
            const int need_t = std::max(0, triangles - counts.triangles);
            const int need_l = std::max(0, lines - counts.lines);
            const int need_p = std::max(0, points - counts.points);
            const int total = need_t + need_l + need_p;
            if (total == 0) break;
            const int r = uniform_int(0, total - 1);
            Cell c;
            c.kind = r < need_t ? Kind::Triangle : r < need_t + need_l ? Kind::Line : Kind::Point;
            const int cx = (i % kGrid) * kCell;
            const int cy = (i / kGrid) * kCell;
            c.draw.state.viewport = {cx, cy, kCell, kCell};
            c.draw.state.scissor = refraster::Rect{cx, cy, kCell, kCell};
            c.draw.vertices.attributes = {{"color", 4}};
            random_state(c.draw.state);
            switch (c.kind) {
                case Kind::Triangle:
                    triangle(c.draw, counts);
                    counts.z24 += depth == refraster::DepthFormat::Z24;
                    counts.z32f += depth == refraster::DepthFormat::Z32f;
                    break;
                case Kind::Line:
                    line(c.draw, counts);
                    break;
                case Kind::Point:
                    point(c.draw, counts);
                    break;
            }
            cells.push_back(std::move(c));
        }
        return cells;
    }

    float uniform(float lo, float hi) {
        return std::uniform_real_distribution<float>(lo, hi)(rng_);
    }
    int uniform_int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

  private:
    // Depth test, blending, shading and provoking vertex, shared by every kind.
    void random_state(refraster::DrawState& s) {
        static constexpr refraster::CompareFunc funcs[] = {
            refraster::CompareFunc::Less,    refraster::CompareFunc::Lequal,
            refraster::CompareFunc::Greater, refraster::CompareFunc::Gequal,
            refraster::CompareFunc::Always,  refraster::CompareFunc::NotEqual};
        if (uniform(0, 1) < 0.6f) s.depth_test = funcs[static_cast<std::size_t>(uniform_int(0, 5))];
        s.depth_write = uniform(0, 1) < 0.9f;
        const int b = uniform_int(0, 3);
        s.blend = b == 0   ? refraster::BlendPreset::Alpha
                  : b == 1 ? refraster::BlendPreset::Add
                           : refraster::BlendPreset::None;
        const int sh = uniform_int(0, 4);
        s.shade = sh < 2   ? refraster::ShadeModel::Smooth
                  : sh < 4 ? refraster::ShadeModel::Flat
                           : refraster::ShadeModel::NoPerspective;
        s.provoking_vertex = uniform_int(0, 1) ? refraster::ProvokingVertex::First
                                               : refraster::ProvokingVertex::Last;
    }

    std::array<float, 4> random_color() {
        return {uniform(0, 1), uniform(0, 1), uniform(0, 1), uniform(0.1f, 1)};
    }

    // A window position local to the cell, exactly, with a power-of-two w: the viewport is
    // 32 pixels wide, so the GL side's viewport transform gives the position back exactly.
    void push_window(refraster::Draw& d, float x, float y, float w) {
        const float z = uniform(-0.95f, 0.95f) * w;
        const auto c = random_color();
        d.vertices.data.insert(
            d.vertices.data.end(),
            {(x / 16.0f - 1.0f) * w, (y / 16.0f - 1.0f) * w, z, w, c[0], c[1], c[2], c[3]});
    }
    // A clip position at full float precision: ndc in [-range, range] times a random w.
    void push_float(refraster::Draw& d, float range, float wlo, float whi) {
        const float w = uniform(wlo, whi);
        const auto c = random_color();
        d.vertices.data.insert(d.vertices.data.end(),
                               {uniform(-range, range) * w, uniform(-range, range) * w,
                                uniform(-0.95f, 0.95f) * w, w, c[0], c[1], c[2], c[3]});
    }
    float power_of_two_w() {
        return std::array<float, 3>{0.5f, 1.0f, 2.0f}[static_cast<std::size_t>(uniform_int(0, 2))];
    }
    float grid(float lo, float hi) { return std::round(uniform(lo, hi) * 256.0f) / 256.0f; }
    std::array<float, 2> on_sample(int lo, int hi) {
        const auto& s = kSamplePos[static_cast<std::size_t>(uniform_int(0, 3))];
        return {static_cast<float>(uniform_int(lo, hi)) + s[0],
                static_cast<float>(uniform_int(lo, hi)) + s[1]};
    }

    void triangle(refraster::Draw& d, Counts& counts) {
        d.primitive = refraster::PrimitiveType::Triangles;
        std::array<std::array<float, 2>, 3> win{};
        bool window = true;
        const float r = uniform(0, 1);
        if (r < 0.3f) {
            // An edge between two samples an even number of pixels apart in x and y: it passes
            // through the sample of the same index halfway, and through more when the
            // offsets share a factor; the third vertex on a sample half the time.
            const auto a = on_sample(-3, 34);
            int dx = 2 * uniform_int(-8, 8);
            int dy = 2 * uniform_int(-8, 8);
            if (uniform(0, 1) < 0.3f) dy = 0;
            if (uniform(0, 1) < 0.2f) dx = 0;
            if (dx == 0 && dy == 0) dx = 6;
            win[0] = a;
            win[1] = {a[0] + static_cast<float>(dx), a[1] + static_cast<float>(dy)};
            win[2] = uniform(0, 1) < 0.5f ? on_sample(-3, 34)
                                          : std::array<float, 2>{grid(-4, 36), grid(-4, 36)};
            std::shuffle(win.begin(), win.end(), rng_);
            ++counts.on_sample;
            ++counts.grid;
        } else if (r < 0.6f) {
            for (auto& p : win) p = {grid(-4, 36), grid(-4, 36)};
            ++counts.grid;
        } else {
            window = false;
            const float range = uniform(0, 1) < 0.7f ? 0.95f : 1.6f;
            for (int k = 0; k < 3; ++k) push_float(d, range, 0.25f, 4.0f);
            ++counts.full_float;
        }
        if (window) {
            const float w = power_of_two_w();
            for (const auto& p : win) push_window(d, p[0], p[1], w);
        }
        // Winding in window space (w > 0 everywhere: the sign of the clip-space 2D cross
        // product over w).
        std::array<std::array<double, 2>, 3> n{};
        for (std::size_t k = 0; k < 3; ++k) {
            const auto p = d.vertices.position(k);
            n[k] = {double{p[0]} / double{p[3]}, double{p[1]} / double{p[3]}};
        }
        const double area =
            (n[1][0] - n[0][0]) * (n[2][1] - n[0][1]) - (n[2][0] - n[0][0]) * (n[1][1] - n[0][1]);
        counts.ccw += area > 0;
        counts.cw += area < 0;
        counts.flat += d.state.shade == refraster::ShadeModel::Flat;
        counts.smooth += d.state.shade != refraster::ShadeModel::Flat;
        counts.blended += d.state.blend != refraster::BlendPreset::None;
        ++counts.triangles;
    }

    void line(refraster::Draw& d, Counts& counts) {
        const int kind = uniform_int(0, 9);
        d.primitive = kind < 7   ? refraster::PrimitiveType::Lines
                      : kind < 9 ? refraster::PrimitiveType::LineStrip
                                 : refraster::PrimitiveType::LineLoop;
        const int n = kind < 7 ? 2 : 3;
        if (uniform(0, 1) < 0.5f) {
            const auto k = static_cast<std::size_t>(uniform_int(0, kLineWidths.size() - 1));
            d.state.line_width = kLineWidths[k];
            counts.widths[k] += kind < 7 ? 1 : kind < 9 ? 2 : 3;
        } else {
            d.state.line_width = uniform(0.5f, 4.0f);
        }
        const int mode = uniform_int(0, 2);
        const float w = power_of_two_w();
        std::array<float, 2> prev{};
        for (int i = 0; i < n; ++i) {
            if (mode == 2) {
                push_float(d, 1.2f, 0.5f, 2.0f);
                continue;
            }
            std::array<float, 2> p =
                mode == 0 ? std::array<float, 2>{grid(-4, 36), grid(-4, 36)} : on_sample(-2, 33);
            // Axis-aligned segments between samples now and then: their long sides run
            // through a row or column of samples when the width is even.
            if (mode == 1 && i > 0 && uniform(0, 1) < 0.4f) {
                const auto axis = static_cast<std::size_t>(uniform_int(0, 1));
                p[axis] = prev[axis];
            }
            // No zero-length segments: their direction is undefined.
            if (i > 0 && p == prev) p[0] += 2.0f;
            prev = p;
            push_window(d, p[0], p[1], w);
        }
        counts.lines += kind < 7 ? 1 : kind < 9 ? 2 : 3;
    }

    void point(refraster::Draw& d, Counts& counts) {
        d.primitive = refraster::PrimitiveType::Points;
        if (uniform(0, 1) < 0.6f) {
            const auto k = static_cast<std::size_t>(uniform_int(0, kPointSizes.size() - 1));
            d.state.point_size = kPointSizes[k];
            counts.sizes[k] += 1;  // counted once per draw; the points below share it
        } else {
            d.state.point_size = uniform(0.7f, 4.0f);
        }
        const int n = uniform_int(1, 3);
        for (int i = 0; i < n; ++i) {
            const int mode = uniform_int(0, 4);
            const float w = power_of_two_w();
            if (mode == 0) {
                const auto p = on_sample(-1, 32);
                push_window(d, p[0], p[1], w);
            } else if (mode == 1) {
                push_window(d, static_cast<float>(uniform_int(0, 31)) + 0.5f,
                            static_cast<float>(uniform_int(0, 31)) + 0.5f, w);
            } else if (mode == 2) {
                push_window(d, static_cast<float>(uniform_int(0, 32)),
                            static_cast<float>(uniform_int(0, 32)), w);
            } else if (mode == 3) {
                push_window(d, grid(-1, 33), grid(-1, 33), w);
            } else {
                push_float(d, 1.05f, 0.5f, 2.0f);
            }
        }
        counts.points += n;
    }

    std::mt19937_64 rng_;
};

harness::Scene msaa_scene(const std::vector<Cell>& cells, refraster::DepthFormat depth,
                          std::array<float, 4> clear_color, float clear_depth) {
    harness::Scene s;
    s.path = "random-msaa-cells";
    s.file.name = "random";
    s.file.target = {kSize, kSize, refraster::ColorFormat::Rgba8, depth, kSamples};
    s.file.clear.color = clear_color;
    s.file.clear.depth = clear_depth;
    s.draw_list.target = s.file.target;
    s.draw_list.clear = s.file.clear;
    for (const auto& c : cells) {
        s.draw_list.draws.push_back(c.draw);
        // The same draw as a scene file writes it (clip space), for REFRASTER_TEST_DUMP_DIR.
        harness::SceneDraw sd;
        sd.primitive = c.draw.primitive;
        sd.space = harness::VertexSpace::Clip;
        sd.state = c.draw.state;
        sd.indices = c.draw.indices;
        for (std::size_t i = 0; i < c.draw.vertices.size(); ++i) {
            const auto v = c.draw.vertices.vertex(i);
            harness::SceneVertex sv;
            sv.position = {v[0], v[1], v[2], v[3]};
            sv.position_size = 4;
            sv.color = {v[4], v[5], v[6], v[7]};
            sd.vertices.push_back(sv);
        }
        s.file.draws.push_back(sd);
    }
    return s;
}

// With REFRASTER_TEST_DUMP_DIR set, a batch with differences is written there as a scene file
// (msaa_SEED_BATCH.json), to be explained with `refraster explain --sample`.
void dump_batch(const harness::Scene& scene, std::uint64_t seed, int batch) {
    const char* dir = std::getenv("REFRASTER_TEST_DUMP_DIR");
    if (dir == nullptr || *dir == '\0') return;
    harness::SceneFile f = scene.file;
    f.name = "random.msaa_" + std::to_string(seed) + "_" + std::to_string(batch);
    const auto path = std::filesystem::path(dir) / "random" /
                      ("msaa_" + std::to_string(seed) + "_" + std::to_string(batch) + ".json");
    std::filesystem::create_directories(path.parent_path());
    harness::write_file_atomically(path, harness::scene_to_json(f));
}

std::string describe(const refraster::Draw& d) {
    std::string s(refraster::to_string(d.primitive));
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  " width %a size %a shade %d provoking %d depth_test %d write %d blend %d; "
                  "clip positions",
                  double{d.state.line_width}, double{d.state.point_size},
                  static_cast<int>(d.state.shade), static_cast<int>(d.state.provoking_vertex),
                  d.state.depth_test ? static_cast<int>(*d.state.depth_test) : -1,
                  static_cast<int>(d.state.depth_write), static_cast<int>(d.state.blend));
    s += buf;
    for (std::size_t i = 0; i < d.vertices.size(); ++i) {
        const auto v = d.vertices.vertex(i);
        std::snprintf(buf, sizeof buf, " (%a, %a, %a, %a | %a %a %a %a)", double{v[0]},
                      double{v[1]}, double{v[2]}, double{v[3]}, double{v[4]}, double{v[5]},
                      double{v[6]}, double{v[7]});
        s += buf;
    }
    return s;
}

// The first difference inside cell i, sample by sample, then in the resolved image; empty when
// the cell agrees.
struct CellDiff {
    std::uint64_t samples = 0;  // differing samples (colour or depth)
    std::uint64_t pixels = 0;   // differing resolved pixels (colour or depth)
    std::string first;
    std::uint32_t x = 0;  // the first difference's pixel
    std::uint32_t y = 0;
};

std::string bytes(const refraster::PixelVector<std::uint8_t>& c, std::size_t at) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "(%u, %u, %u, %u)", c[at], c[at + 1], c[at + 2], c[at + 3]);
    return buf;
}

bool same_rgba(const refraster::PixelVector<std::uint8_t>& a,
               const refraster::PixelVector<std::uint8_t>& b, std::size_t at) {
    for (std::size_t c = 0; c < 4; ++c) {
        if (a[at + c] != b[at + c]) return false;
    }
    return true;
}

CellDiff cell_diff(const harness::RenderResult& ref, const harness::RenderResult& gl,
                   std::size_t i) {
    CellDiff out;
    const auto cx = static_cast<std::uint32_t>(i % kGrid) * kCell;
    const auto cy = static_cast<std::uint32_t>(i / kGrid) * kCell;
    const auto& a = ref.samples;
    const auto& b = gl.samples;
    const bool depth = a.depth_format != refraster::DepthFormat::None;
    for (std::uint32_t y = cy; y < cy + kCell; ++y) {
        for (std::uint32_t x = cx; x < cx + kCell; ++x) {
            for (std::uint32_t s = 0; s < kSamples; ++s) {
                const std::size_t k = a.sample_index(x, y, s);
                const bool colour = !same_rgba(a.color8, b.color8, 4 * k);
                const bool z = depth && a.depth[k] != b.depth[k];
                if (!colour && !z) continue;
                if (out.samples++ == 0) {
                    out.x = x;
                    out.y = y;
                    out.first = "pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                ") sample " + std::to_string(s) + ": reference colour " +
                                bytes(a.color8, 4 * k) + " depth " +
                                (depth ? std::to_string(a.depth[k]) : "-") + ", llvmpipe " +
                                bytes(b.color8, 4 * k) + " depth " +
                                (depth ? std::to_string(b.depth[k]) : "-");
                }
            }
            const std::size_t p = ref.image.index(x, y);
            const bool colour = !same_rgba(ref.image.color8, gl.image.color8, 4 * p);
            const bool z = !ref.image.depth.empty() && ref.image.depth[p] != gl.image.depth[p];
            if (!colour && !z) continue;
            if (out.pixels++ == 0 && out.samples == 0) {
                out.x = x;
                out.y = y;
                out.first = "resolved pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                            "): reference " + bytes(ref.image.color8, 4 * p) + ", llvmpipe " +
                            bytes(gl.image.color8, 4 * p);
            }
        }
    }
    return out;
}

// What makes a render usable here: Ok, the resolved image of the target's size and every
// sample of the 4x target.
::testing::AssertionResult usable(const harness::RenderResult& r, const char* who,
                                  refraster::DepthFormat depth) {
    if (r.status != harness::RenderStatus::Ok) {
        return ::testing::AssertionFailure()
               << who << " answered " << harness::to_string(r.status) << ": " << r.message;
    }
    const auto& s = r.samples;
    const std::size_t n = std::size_t{kSize} * kSize * kSamples;
    if (s.width != kSize || s.height != kSize || s.samples != kSamples ||
        s.color8.size() != 4 * n ||
        (depth != refraster::DepthFormat::None && s.depth.size() != n)) {
        return ::testing::AssertionFailure()
               << who << " returned no samples of the 4x target (" << s.width << "x" << s.height
               << "x" << s.samples << ", " << s.color8.size() / 4 << " colour and "
               << s.depth.size() << " depth values)";
    }
    if (r.image.width != kSize || r.image.height != kSize || r.image.samples != 1 ||
        r.image.color8.size() != 4 * std::size_t{kSize} * kSize) {
        return ::testing::AssertionFailure() << who << " returned no resolved image";
    }
    return ::testing::AssertionSuccess();
}

// Under 4x llvmpipe's scissor admits some samples of the column left of it and the row
// below it, so a primitive of the cell to the right or above can reach into a cell's last
// column or top row: name it too when the difference lies there.
std::string neighbours(const std::vector<Cell>& cells, std::size_t i, const CellDiff& d) {
    std::string s;
    const auto cx = static_cast<std::uint32_t>(i % kGrid) * kCell;
    const auto cy = static_cast<std::uint32_t>(i / kGrid) * kCell;
    if (d.x == cx + kCell - 1 && i % kGrid + 1 < kGrid && i + 1 < cells.size())
        s += "; the cell to the right holds " + describe(cells[i + 1].draw);
    if (d.y == cy + kCell - 1 && i + kGrid < cells.size())
        s += "; the cell above holds " + describe(cells[i + kGrid].draw);
    return s;
}

struct RunResult {
    int bad_cells = 0;
    std::uint64_t differing_samples = 0;
    std::uint64_t lit_samples = 0;     // llvmpipe samples that differ from the clear colour
    std::uint64_t partial_pixels = 0;  // llvmpipe pixels whose samples are not all equal
    bool ok = true;
};

// Renders until the counts are reached and compares every cell sample by sample.
RunResult run(std::uint64_t seed, int triangles, int lines, int points, Counts& counts,
              const refraster::Profile& profile = {}, bool report = true) {
    MsaaGenerator gen(seed);
    auto [ref, osmesa] = testscenes::make_renderers(profile);
    RunResult out;
    for (int batch = 0;
         counts.triangles < triangles || counts.lines < lines || counts.points < points; ++batch) {
        const auto depth =
            batch % 2 == 0 ? refraster::DepthFormat::Z24 : refraster::DepthFormat::Z32f;
        const auto cells = gen.next_batch(counts, triangles, lines, points, depth);
        // A clear colour of whole bytes, so that its stored bytes are known.
        std::array<std::uint8_t, 4> clear_bytes{};
        std::array<float, 4> clear{};
        for (std::size_t c = 0; c < 4; ++c) {
            clear_bytes[c] = static_cast<std::uint8_t>(gen.uniform_int(0, 255));
            clear[c] = static_cast<float>(clear_bytes[c]) / 255.0f;
        }
        const float clear_depth = gen.uniform(0, 1) < 0.5f ? 1.0f : gen.uniform(0.2f, 1.0f);
        const auto scene = msaa_scene(cells, depth, clear, clear_depth);
        const auto a = ref->render(scene);
        const auto b = osmesa->render(scene);
        const auto ua = usable(a, "the reference", depth);
        const auto ub = usable(b, "OSMesa llvmpipe", depth);
        if (!ua || !ub) {
            ADD_FAILURE() << "seed " << seed << " batch " << batch << ": "
                          << (!ua ? ua.message() : "") << (!ua && !ub ? "; " : "")
                          << (!ub ? ub.message() : "");
            out.ok = false;
            return out;
        }
        // The resolve of llvmpipe's own samples is its resolved image: the samples read back
        // are the ones the blit averaged.
        const auto resolved = refraster::resolve_samples(b.samples);
        if (resolved.color8 != b.image.color8) {
            ADD_FAILURE() << "seed " << seed << " batch " << batch
                          << ": llvmpipe's resolved image is not the resolve of its samples";
            out.ok = false;
        }
        for (std::size_t p = 0; p < b.samples.pixel_count(); ++p) {
            bool partial = false;
            for (std::size_t s = 0; s < kSamples; ++s) {
                const std::size_t k = (p * kSamples + s) * 4;
                bool lit = false;
                for (std::size_t c = 0; c < 4; ++c) {
                    lit = lit || b.samples.color8[k + c] != clear_bytes[c];
                    partial = partial || b.samples.color8[k + c] != b.samples.color8[p * 16 + c];
                }
                out.lit_samples += lit;
            }
            out.partial_pixels += partial;
        }
        bool dumped = false;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const auto d = cell_diff(a, b, i);
            if (d.samples == 0 && d.pixels == 0) continue;
            if (!dumped && report) dump_batch(scene, seed, batch);
            dumped = true;
            out.differing_samples += d.samples;
            if (++out.bad_cells <= 5 && report) {
                ADD_FAILURE() << "seed " << seed << " batch " << batch << " cell " << i << " ("
                              << refraster::to_string(depth) << "): " << d.samples
                              << " samples and " << d.pixels << " resolved pixels differ; first "
                              << d.first << "; primitive " << describe(cells[i].draw)
                              << neighbours(cells, i, d);
            }
        }
    }
    return out;
}

class RandomMsaa : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(RandomMsaa, TrianglesLinesPointsMatchLlvmpipeSampleBySample) {
    const std::uint64_t seed = GetParam();
    std::cout << "seed " << seed << "\n";
    Counts counts;
    const auto r = run(seed, 5000, 2000, 1000, counts);
    ASSERT_TRUE(r.ok);
    EXPECT_EQ(r.bad_cells, 0);
    // The generator's promises.
    EXPECT_GE(counts.triangles, 5000);
    EXPECT_GE(counts.lines, 2000);
    EXPECT_GE(counts.points, 1000);
    EXPECT_GE(counts.on_sample * 4, counts.triangles) << counts.on_sample;
    EXPECT_GE(counts.full_float * 4, counts.triangles) << counts.full_float;
    EXPECT_GE(counts.grid * 4, counts.triangles) << counts.grid;
    EXPECT_GE(counts.flat * 4, counts.triangles) << counts.flat;
    EXPECT_GE(counts.smooth * 4, counts.triangles) << counts.smooth;
    EXPECT_GE(counts.blended * 4, counts.triangles) << counts.blended;
    EXPECT_GE(counts.ccw * 4, counts.triangles) << counts.ccw;
    EXPECT_GE(counts.cw * 4, counts.triangles) << counts.cw;
    EXPECT_GE(counts.z24 * 4, counts.triangles) << counts.z24;
    EXPECT_GE(counts.z32f * 4, counts.triangles) << counts.z32f;
    for (int n : counts.widths) EXPECT_GE(n, 50);
    for (int n : counts.sizes) EXPECT_GE(n, 10);
    // The scenes exercise multisampling: many pixels hold samples of different values.
    EXPECT_GT(r.partial_pixels, 10000u);
    EXPECT_GT(r.lit_samples, 100000u);
}

// The comparison can fail: with the tie rule flipped, edges and sides exactly through sample
// positions must show, sample by sample.
TEST(RandomMsaaSensitivity, FlippedTieRuleIsDetected) {
    refraster::Profile flipped;
    refraster::set_profile_parameter(flipped, "tie_rule", "right-top");
    Counts counts;
    const auto r = run(11, 1000, 300, 150, counts, flipped, false);
    ASSERT_TRUE(r.ok);
    EXPECT_GT(r.bad_cells, 20);
    EXPECT_GT(r.differing_samples, 200u);
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomMsaa, ::testing::Values(1u, 2u, testscenes::ci_seed()));

}  // namespace
