// The preconditions of assert.hpp: checked in the core the unit tests link (REFRASTER_CHECKED),
// whatever the build type, and a failed one aborts with the condition and the place.
#include "refraster/assert.hpp"

#include <gtest/gtest.h>

#include "refraster/framebuffer.hpp"

namespace {

TEST(Preconditions, AreAssertedInTheCheckedCore) {
    EXPECT_TRUE(refraster::kAssertions);
}

TEST(PreconditionsDeathTest, APixelOutsideTheFramebufferAborts) {
    const refraster::Framebuffer fb(4, 2, refraster::ColorFormat::Rgba8,
                                    refraster::DepthFormat::None);
    EXPECT_EQ(fb.index(3, 1), 7u);
    EXPECT_DEATH((void)fb.index(4, 0), "precondition failed: x < width && y < height");
    EXPECT_DEATH((void)fb.index(0, 2), "a pixel inside the framebuffer");
}

TEST(PreconditionsDeathTest, AnIndexBeyondTheVerticesAborts) {
    refraster::Draw d;
    d.vertices.attributes = {{"color", 4}};
    d.vertices.data.assign(2 * 8, 0.0f);  // two vertices
    d.indices = std::vector<std::uint32_t>{0, 1, 2};
    EXPECT_EQ(d.element(1), 1u);
    EXPECT_DEATH((void)d.element(2), "indices within the vertex count");
}

}  // namespace
