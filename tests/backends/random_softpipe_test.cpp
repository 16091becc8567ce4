// Random primitives through the reference under softpipe-22.3 and OSMesa softpipe, compared in
// colour and depth: every byte and every depth value must agree. A seed draws 5,000 triangles
// (z16, z24 and z32f depth with every compare function, every shade model, both blend presets,
// polygon offset, depth writes off and depth ranges, rgba8 and rgba32f targets), 2,000 lines and
// 1,000 points (random_lines_points.hpp). Seeds: two fixed, one from REFRASTER_TEST_SEED (set
// per CI run).
#include <gtest/gtest.h>

#include <iostream>

#include "random_attributes.hpp"
#include "random_lines_points.hpp"
#include "random_scenes.hpp"
#include "refraster/profile.hpp"

namespace {

using testscenes::attributes::run_variant;
using testscenes::attributes::Variant;

constexpr auto kSoftpipe = harness::Driver::Softpipe;

class RandomSoftpipe : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(RandomSoftpipe, FiveThousandTrianglesMatchSoftpipe) {
    std::cout << "seed " << GetParam() << "\n";
    const auto profile = refraster::softpipe_22_3_profile();
    const Variant variants[] = {
        {"z24", refraster::DepthFormat::Z24, refraster::ColorFormat::Rgba8, {3, true, true}, 1500},
        {"z16", refraster::DepthFormat::Z16, refraster::ColorFormat::Rgba8, {3, true, true}, 1500},
        {"z32f",
         refraster::DepthFormat::Z32f,
         refraster::ColorFormat::Rgba8,
         {3, true, true},
         1000},
        {"rgba32f",
         refraster::DepthFormat::Z24,
         refraster::ColorFormat::Rgba32f,
         {3, true, true},
         1000},
    };
    for (const auto& v : variants) {
        SCOPED_TRACE(v.name);
        EXPECT_EQ(run_variant(GetParam(), v, profile, true, kSoftpipe), 0) << v.name;
    }
}

TEST_P(RandomSoftpipe, TwoThousandLinesThousandPointsMatchSoftpipe) {
    std::cout << "seed " << GetParam() << "\n";
    testscenes::lines_points::Counts counts;
    EXPECT_EQ(testscenes::lines_points::run(GetParam(), 2000, 1000, counts,
                                            refraster::softpipe_22_3_profile(), true, kSoftpipe),
              0);
    EXPECT_GE(counts.lines, 2000);
    EXPECT_GE(counts.points, 1000);
    for (int o : counts.octants) EXPECT_GT(o, 40);  // every octant
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomSoftpipe, ::testing::Values(1u, 2u, testscenes::ci_seed()));

// The comparison can fail: the llvmpipe profile against softpipe must differ on both the
// triangles and the lines.
TEST(RandomSoftpipeSensitivity, LlvmpipeProfileIsDetected) {
    const Variant v{
        "z24", refraster::DepthFormat::Z24, refraster::ColorFormat::Rgba8, {3, true, true}, 300};
    EXPECT_GT(run_variant(3, v, refraster::llvmpipe_22_3_profile(), false, kSoftpipe), 10);
    testscenes::lines_points::Counts counts;
    EXPECT_GT(testscenes::lines_points::run(3, 200, 50, counts, refraster::llvmpipe_22_3_profile(),
                                            false, kSoftpipe),
              10);
}

}  // namespace
