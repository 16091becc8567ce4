// Random smooth-shaded, depth-tested triangles through the reference (llvmpipe-22.3) and
// OSMesa llvmpipe, compared in colour and depth: every byte and every depth value must agree.
// Seeds: two fixed, one from REFRASTER_TEST_SEED (set per CI run).
#include <gtest/gtest.h>

#include <cstdlib>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "random_scenes.hpp"
#include "refraster/renderer.hpp"

namespace {

struct Variant {
    const char* name;
    refraster::DepthFormat depth;
    refraster::ColorFormat color;
    testscenes::AttributeOptions options;
    int triangles;
};

// Renders `triangles` random triangles in cells and returns how many cells differ; reports
// the first few with everything needed to reproduce them.
int run_variant(std::uint64_t seed, const Variant& v, const refraster::Profile& profile = {},
                bool report = true) {
    testscenes::AttributeGenerator gen(seed, v.options);
    auto [ref, osmesa] = testscenes::make_renderers(profile);
    std::mt19937 clear_rng(static_cast<std::uint32_t>(seed));
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int per_batch = testscenes::kCells * v.options.triangles_per_cell;
    int bad_cells = 0;
    int drawn_pixels = 0;
    for (int done = 0; done < v.triangles; done += per_batch) {
        const auto cells = gen.next_batch();
        const std::array<float, 4> clear{u(clear_rng), u(clear_rng), u(clear_rng), u(clear_rng)};
        const float clear_depth = u(clear_rng) < 0.5f ? 1.0f : u(clear_rng);
        const auto scene = testscenes::attribute_scene(cells, v.depth, v.color, clear, clear_depth);
        const auto a = ref->render(scene);
        const auto b = osmesa->render(scene);
        EXPECT_EQ(a.status, harness::RenderStatus::Ok) << a.message;
        EXPECT_EQ(b.status, harness::RenderStatus::Ok) << b.message;
        if (a.status != harness::RenderStatus::Ok || b.status != harness::RenderStatus::Ok)
            return -1;
        const auto c = harness::compare_images(a.image, b.image, scene.draw_list.clear, {});
        drawn_pixels += static_cast<int>(c.mask.pixel_count());
        if (c.mismatched_pixels == 0) continue;
        for (std::size_t i = 0; i < cells.size(); ++i) {
            const auto n = testscenes::cell_differences(a.image, b.image, i);
            if (n == 0) continue;
            if (++bad_cells <= 3 && report) {
                ADD_FAILURE() << v.name << " seed " << seed << " batch " << done / per_batch
                              << " cell " << i << ": " << n << " pixels differ (" << c.summary()
                              << ")" << testscenes::describe(cells[i]);
            }
        }
    }
    EXPECT_GT(drawn_pixels, 0);
    return bad_cells;
}

class RandomAttributes : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(RandomAttributes, TenThousandSmoothDepthTestedTrianglesZ24) {
    const Variant v{"smooth-z24",
                    refraster::DepthFormat::Z24,
                    refraster::ColorFormat::Rgba8,
                    {2, false, false},
                    10000};
    std::cout << "seed " << GetParam() << "\n";
    EXPECT_EQ(run_variant(GetParam(), v), 0);
}

// The comparison can fail: llvmpipe fuses the per-pixel plane evaluation on this CPU, and an
// unfused reference must show it somewhere in 10,000 triangles.
TEST(RandomAttributesSensitivity, UnfusedInterpolationIsDetected) {
    if (!refraster::host_has_fma())
        GTEST_SKIP() << "the CPU has no FMA: llvmpipe does not fuse either";
    refraster::Profile unfused;
    unfused.gl.viewport_fma = refraster::FmaMode::Off;
    const Variant v{"smooth-z24",
                    refraster::DepthFormat::Z24,
                    refraster::ColorFormat::Rgba8,
                    {2, false, false},
                    10000};
    EXPECT_GT(run_variant(1, v, unfused, false), 0);
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomAttributes, ::testing::Values(1u, 2u, testscenes::ci_seed()));

// Every depth format, float colour, every shade model and the fragment state: 2,000
// triangles each, with a fixed seed.
TEST(RandomAttributesVariants, DepthFormatsShadesBlendingOffsetFloat) {
    const Variant variants[] = {
        {"z16", refraster::DepthFormat::Z16, refraster::ColorFormat::Rgba8, {3, true, false}, 2000},
        {"z32f",
         refraster::DepthFormat::Z32f,
         refraster::ColorFormat::Rgba8,
         {3, true, false},
         2000},
        {"state-z24",
         refraster::DepthFormat::Z24,
         refraster::ColorFormat::Rgba8,
         {3, true, true},
         2000},
        {"state-z16",
         refraster::DepthFormat::Z16,
         refraster::ColorFormat::Rgba8,
         {3, true, true},
         2000},
        {"state-z32f",
         refraster::DepthFormat::Z32f,
         refraster::ColorFormat::Rgba8,
         {3, true, true},
         2000},
        {"rgba32f",
         refraster::DepthFormat::Z24,
         refraster::ColorFormat::Rgba32f,
         {3, true, true},
         2000},
    };
    for (const auto& v : variants) {
        SCOPED_TRACE(v.name);
        EXPECT_EQ(run_variant(11, v), 0) << v.name;
    }
}

}  // namespace
