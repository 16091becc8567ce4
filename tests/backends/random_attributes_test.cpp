// Random smooth-shaded, depth-tested triangles through the reference (llvmpipe-22.3) and
// OSMesa llvmpipe, compared in colour and depth: every byte and every depth value must agree.
// Seeds: two fixed, one from REFRASTER_TEST_SEED (3 unless set).
#include "random_attributes.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "random_scenes.hpp"
#include "refraster/renderer.hpp"

namespace {

using testscenes::attributes::run_variant;
using testscenes::attributes::Variant;

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
