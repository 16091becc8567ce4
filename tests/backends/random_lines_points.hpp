// random_lines_points.hpp: random lines and points in 64x64 cells, rendered through the
// reference and OSMesa (either driver) and compared cell by cell.
//
// Lines: widths 1, 1.4, 2, 2.5 and 3; endpoints on the 1/256 and 1/65536 grids and on
// integers; every octant; lines, strips and loops; some crossing the viewport. Points: sizes
// 1 to 5 in quarter steps at integer, half-integer and random positions. Random shade model,
// provoking vertex, depth test (z24) and colours.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "random_scenes.hpp"
#include "refraster/renderer.hpp"

namespace testscenes::lines_points {

struct Counts {
    int lines = 0;
    int points = 0;
    std::array<int, 8> octants{};
    std::array<int, 3> grids{};  // 1/256, 1/65536, integer
};

class Generator {
  public:
    explicit Generator(std::uint64_t seed) : rng_(seed) {}

    float uniform(float lo, float hi) {
        return std::uniform_real_distribution<float>(lo, hi)(rng_);
    }
    int uniform_int(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }

    // A window coordinate in the cell (local, -8..72 so some cross), on the chosen grid.
    float coord(int grid) {
        const float v = uniform(-8.0f, 72.0f);
        switch (grid) {
            case 0:
                return std::round(v * 256.0f) / 256.0f;
            case 1:
                return std::round(v * 65536.0f) / 65536.0f;
            default:
                return std::round(v);
        }
    }

    refraster::Draw line_draw(int cx, int cy, Counts& counts) {
        refraster::Draw d;
        const int kind = uniform_int(0, 2);
        d.primitive = kind == 0   ? refraster::PrimitiveType::Lines
                      : kind == 1 ? refraster::PrimitiveType::LineStrip
                                  : refraster::PrimitiveType::LineLoop;
        static constexpr float widths[] = {1.0f, 1.4f, 2.0f, 2.5f, 3.0f};
        d.state.line_width = widths[static_cast<std::size_t>(uniform_int(0, 4))];
        const int n = kind == 0 ? 2 * uniform_int(1, 2) : uniform_int(2, 4);
        const int grid = uniform_int(0, 2);
        counts.grids[static_cast<std::size_t>(grid)] += 1;
        std::vector<std::array<float, 2>> pts;
        for (int i = 0; i < n; ++i) pts.push_back({coord(grid), coord(grid)});
        for (int i = 0; i + 1 < n; ++i) {
            const float dx =
                pts[static_cast<std::size_t>(i + 1)][0] - pts[static_cast<std::size_t>(i)][0];
            const float dy =
                pts[static_cast<std::size_t>(i + 1)][1] - pts[static_cast<std::size_t>(i)][1];
            const int octant =
                (dx >= 0 ? 0 : 4) + (dy >= 0 ? 0 : 2) + (std::fabs(dx) >= std::fabs(dy) ? 0 : 1);
            counts.octants[static_cast<std::size_t>(octant)] += 1;
        }
        counts.lines +=
            static_cast<int>(refraster::primitive_count(d.primitive, static_cast<std::size_t>(n)));
        fill(d, cx, cy, pts);
        return d;
    }

    refraster::Draw point_draw(int cx, int cy, Counts& counts) {
        refraster::Draw d;
        d.primitive = refraster::PrimitiveType::Points;
        d.state.point_size = 1.0f + 0.25f * static_cast<float>(uniform_int(0, 16));
        std::vector<std::array<float, 2>> pts;
        const int n = uniform_int(1, 4);
        for (int i = 0; i < n; ++i) {
            const int pos = uniform_int(0, 2);
            float x = uniform(-3.0f, 67.0f);
            float y = uniform(-3.0f, 67.0f);
            if (pos == 0) x = std::round(x), y = std::round(y);
            if (pos == 1) x = std::floor(x) + 0.5f, y = std::floor(y) + 0.5f;
            pts.push_back({x, y});
        }
        counts.points += n;
        fill(d, cx, cy, pts);
        return d;
    }

  private:
    // Window-space points of a 64x64 cell to clip space (power-of-two viewport: exact), with
    // random z, w in [0.5, 2], colours, and a random shade model, depth test and provoking
    // vertex.
    void fill(refraster::Draw& d, int cx, int cy, const std::vector<std::array<float, 2>>& pts) {
        d.state.viewport = {cx, cy, testscenes::kCell, testscenes::kCell};
        d.state.scissor = refraster::Rect{cx, cy, testscenes::kCell, testscenes::kCell};
        const int shade = uniform_int(0, 2);
        d.state.shade = shade == 0   ? refraster::ShadeModel::Smooth
                        : shade == 1 ? refraster::ShadeModel::NoPerspective
                                     : refraster::ShadeModel::Flat;
        d.state.provoking_vertex = uniform_int(0, 1) ? refraster::ProvokingVertex::First
                                                     : refraster::ProvokingVertex::Last;
        if (uniform_int(0, 1)) d.state.depth_test = refraster::CompareFunc::Lequal;
        d.vertices.attributes = {{"color", 4}};
        for (const auto& p : pts) {
            const float w = uniform_int(0, 2) == 0 ? 1.0f : uniform(0.5f, 2.0f);
            const float x = (p[0] / 32.0f - 1.0f) * w;
            const float y = (p[1] / 32.0f - 1.0f) * w;
            const float z = uniform(-0.9f, 0.9f) * w;
            d.vertices.data.insert(d.vertices.data.end(),
                                   {x, y, z, w, uniform(0, 1), uniform(0, 1), uniform(0, 1), 1.0f});
        }
    }

    std::mt19937_64 rng_;
};

inline harness::Scene scene_of(std::vector<refraster::Draw> draws) {
    harness::Scene s;
    s.path = "random-lines-points";
    s.file.target = {testscenes::kSize, testscenes::kSize, refraster::ColorFormat::Rgba8,
                     refraster::DepthFormat::Z24, 1};
    s.file.clear.color = {0, 0, 0, 1};
    s.draw_list.target = s.file.target;
    s.draw_list.clear = s.file.clear;
    s.draw_list.draws = std::move(draws);
    return s;
}

// Renders until `lines` lines and `points` points are drawn; returns the cells that differ.
inline int run(std::uint64_t seed, int lines, int points, Counts& counts,
               const refraster::Profile& profile = {}, bool report = true,
               harness::Driver driver = harness::Driver::Llvmpipe) {
    Generator gen(seed);
    auto [ref, osmesa] = testscenes::make_renderers(profile, driver);
    int bad = 0;
    for (int batch = 0; counts.lines < lines || counts.points < points; ++batch) {
        std::vector<refraster::Draw> draws;
        for (int i = 0; i < testscenes::kCells; ++i) {
            const int cx = (i % testscenes::kGrid) * testscenes::kCell;
            const int cy = (i / testscenes::kGrid) * testscenes::kCell;
            const bool want_line =
                counts.lines < lines && (counts.points >= points || gen.uniform_int(0, 2) > 0);
            draws.push_back(want_line ? gen.line_draw(cx, cy, counts)
                                      : gen.point_draw(cx, cy, counts));
        }
        const auto scene = scene_of(draws);
        const auto a = ref->render(scene);
        const auto b = osmesa->render(scene);
        if (a.status != harness::RenderStatus::Ok || b.status != harness::RenderStatus::Ok) {
            ADD_FAILURE() << a.message << " / " << b.message;
            return -1;
        }
        for (std::size_t i = 0; i < draws.size(); ++i) {
            const auto n = testscenes::cell_differences(a.image, b.image, i);
            if (n == 0) continue;
            if (++bad <= 3 && report) {
                std::string desc;
                char buf[96];
                const auto& d = draws[i];
                for (std::size_t k = 0; k < d.vertices.data.size(); k += 8) {
                    std::snprintf(buf, sizeof buf, " (%a, %a, %a, %a)", double{d.vertices.data[k]},
                                  double{d.vertices.data[k + 1]}, double{d.vertices.data[k + 2]},
                                  double{d.vertices.data[k + 3]});
                    desc += buf;
                }
                ADD_FAILURE() << "seed " << seed << " batch " << batch << " cell " << i << ": " << n
                              << " pixels differ; " << refraster::to_string(d.primitive)
                              << " width " << d.state.line_width << " size " << d.state.point_size
                              << " shade " << static_cast<int>(d.state.shade) << " vertices"
                              << desc;
            }
        }
    }
    return bad;
}

}  // namespace testscenes::lines_points
