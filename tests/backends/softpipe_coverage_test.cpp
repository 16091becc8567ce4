// softpipe's triangle coverage and colour planes (refraster/src/models/softpipe/scanline_setup.cpp)
// against OSMesa softpipe, pixel for pixel: the random coverage generator's triangles that need no
// clipping, each alone in a 64x64 cell with its own viewport and scissor, cull mode and front face.
// The window positions are the draw module's C viewport transform (the reference's vertex stage,
// unfused: softpipe creates its draw module without LLVM). Seeds: two fixed, one from
// REFRASTER_TEST_SEED.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>

#include "harness/backend.hpp"
#include "models/softpipe/scanline_setup.hpp"
#include "random_scenes.hpp"
#include "refraster/renderer.hpp"
#include "stages/vertex_stage.hpp"

namespace {

using testscenes::kCell;
using testscenes::kGrid;

// One cell's triangle as the scanline model sees it: the draw module's window positions (its
// vertex stage), then setup with the cell's scissor, cull mode and front face.
struct ModelledCell {
    bool unclipped = false;  // no vertex needs the clipper (softpipe's is not modelled yet)
    bool drawn = false;      // setup drew it (not degenerate, not culled)
    refraster::detail::ScanlineTriangle triangle;
    std::array<float, 3> z{};           // window z
    std::array<float, 3> one_over_w{};  // window 1/w
};

ModelledCell model_cell(const refraster::Draw& d) {
    ModelledCell m;
    // softpipe's draw module is the C one: the viewport transform is unfused.
    const refraster::detail::VertexStage stage(d, {false, true, false, false});
    if (stage.clipmask(0) != 0 || stage.clipmask(1) != 0 || stage.clipmask(2) != 0) return m;
    m.unclipped = true;
    std::array<std::array<float, 2>, 3> w{};
    for (std::uint32_t i = 0; i < 3; ++i) {
        const auto v = stage.vertex(i);
        w[i] = {v.window[0], v.window[1]};
        m.z[i] = v.window[2];
        m.one_over_w[i] = v.window[3];
    }
    const auto& sc = *d.state.scissor;
    // st_atom_rasterizer.c: front_ccw = (FrontFace == GL_CCW), flipped for an FBO.
    const bool front_ccw = d.state.front_face != refraster::FrontFace::Ccw;
    m.drawn =
        refraster::detail::setup_scanline_triangle(
            w, d.state.cull, front_ccw, {sc.x, sc.y, sc.x + sc.width - 1, sc.y + sc.height - 1},
            m.triangle) == refraster::detail::ScanlineOutcome::Ok;
    return m;
}

std::unique_ptr<harness::Backend> make_softpipe() {
    harness::BackendOptions o;
    o.kind = harness::BackendKind::OSMesa;
    o.driver = harness::Driver::Softpipe;
    return harness::make_backend(o);
}

class SoftpipeCoverage : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(SoftpipeCoverage, UnclippedTrianglesMatchOsmesaSoftpipe) {
    std::cout << "seed " << GetParam() << "\n";
    testscenes::CoverageGenerator gen(GetParam());
    const auto softpipe = make_softpipe();
    testscenes::CategoryCounts counts;
    int compared = 0, differing = 0, drawn = 0, ties = 0;
    while (compared < 2000) {
        const auto cells = gen.next_batch(counts);
        const auto scene = testscenes::cell_scene(cells);
        const auto r = softpipe->render(scene);
        ASSERT_EQ(r.status, harness::RenderStatus::Ok) << r.message;
        // The covered pixels as the model draws them: a mask over the whole target.
        std::vector<ModelledCell> modelled;
        std::vector<std::uint8_t> mask(static_cast<std::size_t>(testscenes::kSize) *
                                       testscenes::kSize);
        for (const auto& d : scene.draw_list.draws) {
            modelled.push_back(model_cell(d));
            if (!modelled.back().drawn) continue;
            for (const auto& row : modelled.back().triangle.rows)
                for (int x = row.x0; x < row.x1; ++x)
                    mask[static_cast<std::size_t>(row.y * testscenes::kSize + x)] = 1;
        }
        for (std::size_t i = 0; i < cells.size(); ++i) {
            // The clipper's triangles: not modelled for softpipe yet.
            if (!modelled[i].unclipped) continue;
            ++compared;
            const int cx = static_cast<int>(i % kGrid) * kCell;
            const int cy = static_cast<int>(i / kGrid) * kCell;
            int diff = 0;
            for (int y = cy; y < cy + kCell; ++y) {
                for (int x = cx; x < cx + kCell; ++x) {
                    const std::size_t p =
                        r.image.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
                    const bool lit = r.image.color8[4 * p + 1] != 0;  // green is 1 when drawn
                    const bool model = mask[static_cast<std::size_t>(y * testscenes::kSize + x)];
                    drawn += lit;
                    diff += lit != model;
                }
            }
            if (diff != 0 && ++differing <= 5) {
                ADD_FAILURE() << "seed " << GetParam() << " cell " << i << ": " << diff
                              << " pixels differ" << testscenes::describe(cells[i]);
            }
        }
        ties = counts.centre_edges;
    }
    EXPECT_EQ(differing, 0) << "of " << compared << " triangles";
    EXPECT_GT(drawn, 0);
    EXPECT_GT(ties, 100);  // edges exactly through pixel centres are among them
}

// Smooth (perspective-correct) colours: softpipe's planes (tri_persp_coeff), evaluated a quad
// at a time and divided by the quad's interpolated 1/w, then RNE(fl(c * 255)) of the clamped
// value (docs/precision.md, "softpipe's triangle coverage" and its attributes).
TEST_P(SoftpipeCoverage, SmoothColoursMatchOsmesaSoftpipe) {
    testscenes::CoverageGenerator gen(GetParam() + 1000);
    std::mt19937 rng(static_cast<std::uint32_t>(GetParam()));
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const auto softpipe = make_softpipe();
    testscenes::CategoryCounts counts;
    int compared = 0, differing = 0;
    std::uint64_t pixels = 0;
    while (compared < 1000) {
        const auto cells = gen.next_batch(counts);
        auto scene = testscenes::cell_scene(cells);
        for (auto& d : scene.draw_list.draws) {
            d.state.shade = refraster::ShadeModel::Smooth;
            d.state.cull = refraster::CullMode::None;
            for (std::size_t v = 0; v < 3; ++v)
                for (std::size_t c = 0; c < 4; ++c) d.vertices.data[v * 8 + 4 + c] = unit(rng);
        }
        const auto r = softpipe->render(scene);
        ASSERT_EQ(r.status, harness::RenderStatus::Ok) << r.message;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const auto& d = scene.draw_list.draws[i];
            const ModelledCell m = model_cell(d);
            if (!m.drawn) continue;
            ++compared;
            const auto& t = m.triangle;
            const auto& oow = m.one_over_w;
            std::array<std::array<float, 3>, 4> colour{};
            for (std::size_t k = 0; k < 3; ++k)
                for (std::size_t c = 0; c < 4; ++c) colour[c][k] = d.vertices.data[k * 8 + 4 + c];
            const auto wplane = refraster::detail::scanline_plane(t, oow);
            std::array<refraster::detail::ScanlinePlane, 4> planes{};
            for (std::size_t c = 0; c < 4; ++c)
                planes[c] = refraster::detail::scanline_persp_plane(t, colour[c], oow);
            int diff = 0;
            for (const auto& row : t.rows) {
                for (int x = row.x0; x < row.x1; ++x) {
                    const int x0 = x & ~1, y0 = row.y & ~1;
                    const auto k = static_cast<std::size_t>((x & 1) + 2 * (row.y & 1));
                    const float wq = refraster::detail::scanline_quad(wplane, x0, y0)[k];
                    const std::size_t p = r.image.index(static_cast<std::uint32_t>(x),
                                                        static_cast<std::uint32_t>(row.y));
                    for (std::size_t c = 0; c < 4; ++c) {
                        const float v = refraster::detail::scanline_quad(planes[c], x0, y0)[k] / wq;
                        const float clamped = std::min(std::max(v, 0.0f), 1.0f);
                        const auto want = static_cast<int>(std::nearbyint(clamped * 255.0f));
                        diff += r.image.color8[4 * p + c] != want;
                    }
                    ++pixels;
                }
            }
            if (diff != 0 && ++differing <= 5) {
                ADD_FAILURE() << "seed " << GetParam() << " cell " << i << ": " << diff
                              << " channels differ" << testscenes::describe(cells[i]);
            }
        }
    }
    EXPECT_EQ(differing, 0) << "of " << compared << " triangles";
    EXPECT_GT(pixels, 10000u);
}

// Depth: the linear plane of window z evaluated a quad at a time, clamped and truncated to
// 24 bits (docs/precision.md). Each triangle alone in its cell with the test `less` and
// writes on, over a depth of 1.0: every covered pixel stores the triangle's value.
TEST_P(SoftpipeCoverage, Z24DepthMatchesOsmesaSoftpipe) {
    testscenes::CoverageGenerator gen(GetParam() + 2000);
    const auto softpipe = make_softpipe();
    testscenes::CategoryCounts counts;
    int compared = 0, differing = 0;
    std::uint64_t pixels = 0;
    while (compared < 1000) {
        const auto cells = gen.next_batch(counts);
        auto scene = testscenes::cell_scene(cells);
        scene.file.target.depth = refraster::DepthFormat::Z24;
        scene.draw_list.target.depth = refraster::DepthFormat::Z24;
        scene.file.clear.depth = 1.0f;
        scene.draw_list.clear.depth = 1.0f;
        for (auto& d : scene.draw_list.draws) {
            d.state.cull = refraster::CullMode::None;
            d.state.depth_test = refraster::CompareFunc::Less;
            d.state.depth_write = true;
        }
        const auto r = softpipe->render(scene);
        ASSERT_EQ(r.status, harness::RenderStatus::Ok) << r.message;
        ASSERT_FALSE(r.image.depth.empty());
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const ModelledCell m = model_cell(scene.draw_list.draws[i]);
            if (!m.drawn) continue;
            ++compared;
            const auto& t = m.triangle;
            const auto zplane = refraster::detail::scanline_plane(t, m.z);
            int diff = 0;
            for (const auto& row : t.rows) {
                for (int x = row.x0; x < row.x1; ++x) {
                    const auto k = static_cast<std::size_t>((x & 1) + 2 * (row.y & 1));
                    const float zq =
                        refraster::detail::scanline_quad(zplane, x & ~1, row.y & ~1)[k];
                    const std::uint32_t want =
                        refraster::detail::scanline_depth_value(zq, refraster::DepthFormat::Z24);
                    // 1.0 stays: the test `less` fails at the cleared depth.
                    if (want == 16777215u) continue;
                    const std::size_t p = r.image.index(static_cast<std::uint32_t>(x),
                                                        static_cast<std::uint32_t>(row.y));
                    diff += r.image.depth[p] != want;
                    ++pixels;
                }
            }
            if (diff != 0 && ++differing <= 5) {
                ADD_FAILURE() << "seed " << GetParam() << " cell " << i << ": " << diff
                              << " depth values differ" << testscenes::describe(cells[i]);
            }
        }
    }
    EXPECT_EQ(differing, 0) << "of " << compared << " triangles";
    EXPECT_GT(pixels, 10000u);
}

INSTANTIATE_TEST_SUITE_P(Seeds, SoftpipeCoverage,
                         ::testing::Values(std::uint64_t{1}, std::uint64_t{2},
                                           testscenes::ci_seed()));

}  // namespace
