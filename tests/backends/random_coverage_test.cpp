// Random flat-colour triangles through the reference (llvmpipe-22.3 profile) and OSMesa
// llvmpipe: every pixel must agree. Three seeds: two fixed, one from the environment
// (REFRASTER_TEST_SEED, 3 unless set; .ci/run prints it).
//
// Each scene is a 256x256 target cut into 16 cells of 64x64; every cell holds one triangle
// drawn with the cell as viewport and scissor, so triangles never hide one another and those
// that cross the viewport are clipped at the cell's edges. The triangle's colour encodes its
// index, so a mismatch names the triangle.
#include <gtest/gtest.h>

#include <cstdlib>
#include <random>
#include <sstream>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "harness/scene.hpp"
#include "random_scenes.hpp"

namespace {

class RandomCoverage : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(RandomCoverage, TenThousandTrianglesMatchLlvmpipe) {
    const std::uint64_t seed = GetParam();
    std::cout << "seed " << seed << "\n";
    testscenes::CoverageGenerator gen(seed);
    auto [ref, osmesa] = testscenes::make_renderers();

    testscenes::CategoryCounts counts;
    int mismatched_triangles = 0;
    for (int batch = 0; batch < 10000 / testscenes::kCells; ++batch) {
        const auto cells = gen.next_batch(counts);
        const harness::Scene scene = testscenes::cell_scene(cells);
        const auto a = ref->render(scene);
        const auto b = osmesa->render(scene);
        ASSERT_EQ(a.status, harness::RenderStatus::Ok) << a.message;
        ASSERT_EQ(b.status, harness::RenderStatus::Ok) << b.message;
        const auto c = harness::compare_images(a.image, b.image, scene.draw_list.clear, {});
        if (c.mismatched_pixels == 0) continue;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const auto diff = testscenes::cell_differences(a.image, b.image, i);
            if (diff == 0) continue;
            if (++mismatched_triangles <= 5) {
                ADD_FAILURE() << "seed " << seed << " batch " << batch << " cell " << i << ": "
                              << diff << " pixels differ; " << testscenes::describe(cells[i]);
            }
        }
    }
    EXPECT_EQ(mismatched_triangles, 0);
    // The generator's promises: a quarter crossing the viewport, a quarter with an edge
    // through pixel centres, some with w <= 0.
    EXPECT_GE(counts.crossing * 4, counts.total) << counts.crossing << " of " << counts.total;
    EXPECT_GE(counts.centre_edges * 4, counts.total)
        << counts.centre_edges << " of " << counts.total;
    EXPECT_GE(counts.w_nonpositive, counts.total / 20);
    EXPECT_EQ(counts.total, 10000);
}

// The comparison can fail: with the tie rule flipped, edges through pixel centres must show.
TEST(RandomCoverageSensitivity, FlippedTieRuleIsDetected) {
    testscenes::CoverageGenerator gen(7);
    refraster::Profile flipped;
    flipped.gl.tie_rule = refraster::TieRule::RightTop;
    auto [ref, osmesa] = testscenes::make_renderers(flipped);
    testscenes::CategoryCounts counts;
    std::uint64_t mismatched = 0;
    std::uint64_t lit = 0;
    for (int batch = 0; batch < 20; ++batch) {
        const harness::Scene scene = testscenes::cell_scene(gen.next_batch(counts));
        const auto a = ref->render(scene);
        const auto b = osmesa->render(scene);
        ASSERT_EQ(a.status, harness::RenderStatus::Ok) << a.message;
        mismatched +=
            harness::compare_images(a.image, b.image, scene.draw_list.clear, {}).mismatched_pixels;
        for (std::size_t i = 0; i < b.image.pixel_count(); ++i) lit += b.image.color8[4 * i] != 0;
    }
    EXPECT_GT(mismatched, 100u);
    EXPECT_GT(lit, 20u * 16u * 100u);  // the triangles draw plenty: on average over 100 pixels
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomCoverage, ::testing::Values(1u, 2u, testscenes::ci_seed()));

}  // namespace
