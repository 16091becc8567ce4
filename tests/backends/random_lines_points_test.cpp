// Random lines and points through the reference (llvmpipe-22.3) and OSMesa llvmpipe, compared
// in colour and depth. Seeds: two fixed, one from REFRASTER_TEST_SEED (3 unless set).
//
// Lines: widths 1, 1.4, 2, 2.5 and 3; endpoints on the 1/256 and 1/65536 grids and on
// integers; every octant; lines, strips and loops; some crossing the viewport. Points: sizes
// 1 to 5 in quarter steps at integer, half-integer and random positions.
#include "random_lines_points.hpp"

#include <gtest/gtest.h>

#include <cstdlib>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "random_scenes.hpp"
#include "refraster/renderer.hpp"

namespace {

using testscenes::lines_points::Counts;
using testscenes::lines_points::run;

class RandomLinesPoints : public ::testing::TestWithParam<std::uint64_t> {};

TEST_P(RandomLinesPoints, FiveThousandLinesTwoThousandPointsMatchLlvmpipe) {
    std::cout << "seed " << GetParam() << "\n";
    Counts counts;
    EXPECT_EQ(run(GetParam(), 5000, 2000, counts), 0);
    EXPECT_GE(counts.lines, 5000);
    EXPECT_GE(counts.points, 2000);
    for (int o : counts.octants) EXPECT_GT(o, 100);  // every octant
    for (int g : counts.grids) EXPECT_GT(g, 100);    // every endpoint grid
}

// The comparison can fail: with the tie rule flipped, line and point edges through pixel
// centres must show.
TEST(RandomLinesPointsSensitivity, FlippedTieRuleIsDetected) {
    refraster::Profile flipped;
    flipped.gl.tie_rule = refraster::TieRule::RightTop;
    Counts counts;
    EXPECT_GT(run(5, 1000, 400, counts, flipped, false), 10);
}

INSTANTIATE_TEST_SUITE_P(Seeds, RandomLinesPoints,
                         ::testing::Values(1u, 2u, testscenes::ci_seed()));

}  // namespace
