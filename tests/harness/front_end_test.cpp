// The shared front end: the scene format's formulas, in float32, in the written order.
#include "harness/front_end.hpp"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include "harness/scene.hpp"

namespace {

harness::SceneDraw window_draw(refraster::Rect vp, float n = 0.0f, float f = 1.0f) {
    harness::SceneDraw d;
    d.state.viewport = vp;
    d.state.depth_near = n;
    d.state.depth_far = f;
    return d;
}

harness::SceneVertex vertex(std::array<float, 4> p, std::uint32_t size) {
    harness::SceneVertex v;
    v.position = p;
    v.position_size = size;
    return v;
}

TEST(FrontEnd, WindowToClipHandComputed) {
    const auto d = window_draw({0, 0, 8, 8});
    // x = 2: (2/8)*2-1 = -0.5; y = 6: (6/8)*2-1 = 0.5; z = 0.75: 0.75*2-1 = 0.5; w = 2 scales.
    const auto c = harness::to_clip_space(d, vertex({2, 6, 0.75f, 2}, 4));
    EXPECT_EQ(c, (std::array<float, 4>{-1.0f, 1.0f, 1.0f, 2.0f}));
    // Omitted z is 0 (ndc -1), omitted w is 1.
    const auto c2 = harness::to_clip_space(d, vertex({4, 4, 0, 1}, 2));
    EXPECT_EQ(c2, (std::array<float, 4>{0.0f, 0.0f, -1.0f, 1.0f}));
}

TEST(FrontEnd, ViewportOffsetAndDepthRange) {
    const auto d = window_draw({-4, 2, 16, 4}, 0.25f, 0.75f);
    const auto c = harness::to_clip_space(d, vertex({0, 3, 0.5f, 1}, 3));
    EXPECT_EQ(c[0], (4.0f / 16.0f) * 2.0f - 1.0f);
    EXPECT_EQ(c[1], (1.0f / 4.0f) * 2.0f - 1.0f);
    EXPECT_EQ(c[2], 0.0f);  // (0.5-0.25)/(0.75-0.25)*2-1
}

TEST(FrontEnd, CollapsedDepthRangeGivesZeroNdcZ) {
    const auto d = window_draw({0, 0, 8, 8}, 0.5f, 0.5f);
    EXPECT_EQ(harness::to_clip_space(d, vertex({1, 1, 0.9f, 1}, 3))[2], 0.0f);
}

TEST(FrontEnd, ReversedDepthRange) {
    const auto d = window_draw({0, 0, 8, 8}, 1.0f, 0.0f);
    EXPECT_EQ(harness::to_clip_space(d, vertex({1, 1, 1.0f, 1}, 3))[2], -1.0f);
    EXPECT_EQ(harness::to_clip_space(d, vertex({1, 1, 0.0f, 1}, 3))[2], 1.0f);
}

TEST(FrontEnd, WindowFormulaIsRoundedAtEachStep) {
    // Non-power-of-two viewport: the division rounds, then *2 and -1 round separately.
    const auto d = window_draw({0, 0, 7, 7});
    const float x = 3.3f;
    volatile float q = x / 7.0f;  // volatile keeps each step a separate float operation
    volatile float t = q * 2.0f;
    const float expect = t - 1.0f;
    EXPECT_EQ(harness::to_clip_space(d, vertex({x, 0, 0, 1}, 2))[0], expect);
}

TEST(FrontEnd, ClipMatrixSumsLeftToRightNotAsGlm) {
    harness::SceneDraw d;
    d.space = harness::VertexSpace::Clip;
    std::array<float, 16> m{};
    // Row 0 terms: 1*1, 1e8*1, -1e8*1, 1*1.
    m[0] = 1.0f;
    m[4] = 1e8f;
    m[8] = -1e8f;
    m[12] = 1.0f;
    m[5] = m[10] = m[15] = 1.0f;
    d.matrix = m;
    const auto c = harness::to_clip_space(d, vertex({1, 1, 1, 1}, 4));
    // ((1 + 1e8) + -1e8) + 1 = 1 in float32; the pairwise (1 + 1e8) + (-1e8 + 1) gives 0.
    EXPECT_EQ(c[0], 1.0f);
    glm::mat4 g;
    for (int col = 0; col < 4; ++col) {
        for (int row = 0; row < 4; ++row) g[col][row] = m[static_cast<std::size_t>(4 * col + row)];
    }
    const glm::vec4 gv = g * glm::vec4(1, 1, 1, 1);
    EXPECT_EQ(gv.x, 0.0f) << "glm's order changed; the hand-written product is still required";
}

TEST(FrontEnd, ClipWithoutMatrixPassesThrough) {
    harness::SceneDraw d;
    d.space = harness::VertexSpace::Clip;
    EXPECT_EQ(harness::to_clip_space(d, vertex({0.1f, -2, 3, -0.5f}, 4)),
              (std::array<float, 4>{0.1f, -2, 3, -0.5f}));
}

TEST(FrontEnd, DrawListCarriesColourAsAttributeZero) {
    const auto s = harness::load_scene_text(R"({"format": "refraster-scene/1",
      "target": {"width": 4, "height": 4},
      "draws": [{"primitive": "lines", "vertices": [
        {"position": [0, 0], "color": [1, 0.5, 0.25, 1]}, {"position": [4, 4]}]}]})",
                                            "mem.json");
    const auto& draw = s.draw_list.draws.at(0);
    ASSERT_EQ(draw.vertices.attributes.size(), 1u);
    EXPECT_EQ(draw.vertices.attributes[0].name, "color");
    EXPECT_EQ(draw.vertices.stride(), 8u);
    ASSERT_EQ(draw.vertices.size(), 2u);
    const auto v0 = draw.vertices.vertex(0);
    EXPECT_EQ(std::vector<float>(v0.begin(), v0.end()),
              (std::vector<float>{-1, -1, -1, 1, 1, 0.5f, 0.25f, 1}));
    const auto v1 = draw.vertices.vertex(1);
    EXPECT_EQ(std::vector<float>(v1.begin(), v1.end()),
              (std::vector<float>{1, 1, -1, 1, 1, 1, 1, 1}));
}

}  // namespace
