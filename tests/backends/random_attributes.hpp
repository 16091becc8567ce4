// random_attributes.hpp: random attributed triangles in 64x64 cells (the attribute generator
// of random_scenes.hpp), rendered through the reference and OSMesa (either driver) and compared
// in colour and depth cell by cell.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <random>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "harness/reduce.hpp"
#include "random_scenes.hpp"
#include "refraster/renderer.hpp"

namespace testscenes::attributes {

struct Variant {
    const char* name;
    refraster::DepthFormat depth;
    refraster::ColorFormat color;
    testscenes::AttributeOptions options;
    int triangles;
};

// Renders `triangles` random triangles in cells and returns how many cells differ; reports
// the first few with everything needed to reproduce them.
inline int run_variant(std::uint64_t seed, const Variant& v, const refraster::Profile& profile = {},
                       bool report = true, harness::Driver driver = harness::Driver::Llvmpipe) {
    testscenes::AttributeGenerator gen(seed, v.options);
    auto [ref, osmesa] = testscenes::make_renderers(profile, driver);
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
        if (const char* dump = std::getenv("REFRASTER_DUMP_SCENE");
            dump != nullptr && c.mismatched_pixels != 0) {
            std::ofstream(dump) << harness::scene_to_json(
                testscenes::scene_file_of(scene.file, scene.draw_list));
        }
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

}  // namespace testscenes::attributes
