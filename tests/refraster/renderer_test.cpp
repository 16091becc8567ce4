// The reference renderer's entry point: primitive assembly and its counts, clears, and refusals.
#include "refraster/renderer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "refraster/assembly.hpp"

namespace {

using refraster::PrimitiveType;

// The driver's vertex order, which the reducer relies on through assemble_primitives.
TEST(Assembly, PrimitivesInTheDriversVertexOrder) {
    using E = std::vector<std::vector<std::uint32_t>>;
    EXPECT_EQ(refraster::assemble_primitives(PrimitiveType::Points, 2, false), (E{{0}, {1}}));
    EXPECT_EQ(refraster::assemble_primitives(PrimitiveType::LineLoop, 3, false),
              (E{{0, 1}, {1, 2}, {2, 0}}));
    EXPECT_EQ(refraster::assemble_primitives(PrimitiveType::TriangleStrip, 5, false),
              (E{{0, 1, 2}, {2, 1, 3}, {2, 3, 4}}));
    EXPECT_EQ(refraster::assemble_primitives(PrimitiveType::TriangleStrip, 4, true),
              (E{{0, 1, 2}, {1, 3, 2}}));
    EXPECT_EQ(refraster::assemble_primitives(PrimitiveType::TriangleFan, 4, false),
              (E{{0, 1, 2}, {0, 2, 3}}));
    EXPECT_EQ(refraster::assemble_primitives(PrimitiveType::TriangleFan, 4, true),
              (E{{1, 2, 0}, {2, 3, 0}}));
    // The same triangles as the segmented assembly, whatever the segment size.
    const auto segmented =
        refraster::assemble_triangles(PrimitiveType::TriangleFan, 3000, false, 4096);
    const auto plain = refraster::assemble_primitives(PrimitiveType::TriangleFan, 3000, false);
    ASSERT_EQ(segmented.size(), plain.size());
    for (std::size_t i = 0; i < plain.size(); ++i) {
        EXPECT_EQ(plain[i], (std::vector<std::uint32_t>(segmented[i].element.begin(),
                                                        segmented[i].element.end())));
    }
}

// A triangle list's segments: triangle t of a draw longer than one segment lies in segment
// t / (simple / 3), simple being max_vertices unindexed and min(1024, max_vertices) with 32-bit
// indices (draw_pt_vsplit.c); one segment when the draw fits.
TEST(Assembly, TriangleListSegmentsHoldWholeTriangles) {
    for (const int max_vertices : {3, 4, 9, 128, 4096}) {
        for (const bool indexed : {false, true}) {
            for (const std::size_t count :
                 {std::size_t{0}, std::size_t{3}, std::size_t{8}, std::size_t{300},
                  std::size_t{3077}, std::size_t{12290}}) {
                const auto tris = refraster::assemble_triangles(PrimitiveType::Triangles, count,
                                                                false, max_vertices, indexed);
                ASSERT_EQ(tris.size(), count / 3);
                const auto mv = static_cast<std::size_t>(max_vertices);
                const std::size_t simple = indexed ? std::min<std::size_t>(1024, mv) : mv;
                const std::size_t per = std::max<std::size_t>(simple / 3, 1);
                for (std::size_t t = 0; t < tris.size(); ++t) {
                    const std::uint32_t want =
                        count > simple ? static_cast<std::uint32_t>(t / per) : 0u;
                    ASSERT_EQ(tris[t].segment, want)
                        << "triangle " << t << " of " << count << ", max_vertices " << max_vertices
                        << (indexed ? ", indexed" : "");
                    ASSERT_EQ(tris[t].element[0], 3 * t);
                }
            }
        }
    }
}

TEST(PrimitiveCount, FollowsGlAssembly) {
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::Points, 5), 5u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::Lines, 5), 2u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::LineStrip, 1), 0u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::LineStrip, 4), 3u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::LineLoop, 1), 0u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::LineLoop, 3), 3u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::Triangles, 5), 1u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::TriangleStrip, 2), 0u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::TriangleStrip, 5), 3u);
    EXPECT_EQ(refraster::primitive_count(PrimitiveType::TriangleFan, 4), 2u);
}

refraster::DrawList cleared_list(refraster::DepthFormat depth, float z) {
    refraster::DrawList l;
    l.target = {3, 2, refraster::ColorFormat::Rgba8, depth, 1};
    l.clear.color = {1.0f, 0.0f, 51.0f / 255.0f, 1.0f};
    l.clear.depth = z;
    return l;
}

TEST(Render, ClearOnlyFillsEveryPixel) {
    refraster::Framebuffer fb;
    const auto r = refraster::render(cleared_list(refraster::DepthFormat::Z24, 0.5f), fb);
    ASSERT_EQ(r.status, refraster::RenderStatus::Ok) << r.message;
    ASSERT_EQ(fb.color8.size(), 24u);
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(fb.color8[4 * i + 0], 255);
        EXPECT_EQ(fb.color8[4 * i + 1], 0);
        EXPECT_EQ(fb.color8[4 * i + 2], 51);
        EXPECT_EQ(fb.color8[4 * i + 3], 255);
        // RNE(0.5 * 16777215) = RNE(8388607.5) = 8388608 (even).
        EXPECT_EQ(fb.depth[i], 8388608u);
    }
}

TEST(Render, ClearDepthFormats) {
    refraster::Framebuffer fb;
    ASSERT_EQ(refraster::render(cleared_list(refraster::DepthFormat::Z16, 0.5f), fb).status,
              refraster::RenderStatus::Ok);
    EXPECT_EQ(fb.depth[0], 32768u);  // RNE(32767.5) = 32768
    ASSERT_EQ(refraster::render(cleared_list(refraster::DepthFormat::Z32f, 0.3f), fb).status,
              refraster::RenderStatus::Ok);
    EXPECT_EQ(fb.depth[0], std::bit_cast<std::uint32_t>(0.3f));
}

TEST(Render, UnormClearRoundsLikeFloatToUbyte) {
    // float_to_ubyte: 0.5 * 255/256 + 32768 = 32768.498046875, which float rounds to
    // 32768 + 128/256 (a tie, to even): 128. 0.2 gives 51; values outside [0, 1] clamp.
    auto l = cleared_list(refraster::DepthFormat::None, 1.0f);
    l.clear.color = {0.5f, 0.2f, -3.0f, 7.0f};
    refraster::Framebuffer fb;
    ASSERT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
    EXPECT_EQ(fb.color8[0], 128);
    EXPECT_EQ(fb.color8[1], 51);
    EXPECT_EQ(fb.color8[2], 0);
    EXPECT_EQ(fb.color8[3], 255);
}

TEST(Render, A4xTargetIsClearedInEverySample) {
    auto l = cleared_list(refraster::DepthFormat::Z24, 0.25f);
    l.target.samples = 4;
    refraster::Framebuffer fb;
    ASSERT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
    ASSERT_EQ(fb.samples, 4u);
    ASSERT_EQ(fb.color8.size(), fb.pixel_count() * 4 * 4);
    for (std::size_t i = 0; i < fb.pixel_count() * 4; ++i) {
        EXPECT_EQ(fb.color8[4 * i + 0], 255);
        EXPECT_EQ(fb.color8[4 * i + 2], 51);
        EXPECT_EQ(fb.depth[i], 4194304u);  // RNE(0.25 * (2^24 - 1)) in double
    }
    // Only 1 and 4 samples exist; the exact profile draws single-sample targets only.
    l.target.samples = 2;
    auto r = refraster::render(l, fb);
    EXPECT_EQ(r.status, refraster::RenderStatus::NotSupported);
    EXPECT_NE(r.message.find("2 samples"), std::string::npos);
    l.target.samples = 4;
    refraster::Draw d;
    d.vertices.attributes = {{"color", 4}};
    d.vertices.data.assign(3 * 8, 0.0f);
    l.draws.push_back(d);
    refraster::RenderOptions o;
    o.profile = refraster::gl_exact_profile();
    r = refraster::render(l, o, fb);
    EXPECT_EQ(r.status, refraster::RenderStatus::NotSupported);
    EXPECT_NE(r.message.find("single-sample"), std::string::npos);
}

TEST(Render, ExactProfileRefusesLines) {
    auto l = cleared_list(refraster::DepthFormat::None, 1.0f);
    refraster::Draw d;
    d.primitive = PrimitiveType::Lines;
    d.vertices.attributes = {{"color", 4}};
    d.vertices.data.assign(2 * 8, 0.0f);
    d.vertices.data[3] = d.vertices.data[11] = 1.0f;
    l.draws.push_back(d);
    refraster::RenderOptions o;
    o.profile = refraster::gl_exact_profile();
    refraster::Framebuffer fb;
    const auto r = refraster::render(l, o, fb);
    EXPECT_EQ(r.status, refraster::RenderStatus::NotSupported);
    EXPECT_NE(r.message.find("draws[0]"), std::string::npos);
    // A draw with a leftover vertex only assembles nothing and is accepted.
    l.draws[0].vertices.data.assign(1 * 8, 0.0f);
    EXPECT_EQ(refraster::render(l, o, fb).status, refraster::RenderStatus::Ok);
    // The snapped profile draws the line.
    l.draws[0].vertices.data.assign(2 * 8, 0.0f);
    EXPECT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
}

}  // namespace

namespace {

// A few overlapping triangles and a line and points: every stage has work.
refraster::DrawList staged_list() {
    refraster::DrawList l;
    l.target = {64, 48, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24, 1};
    l.clear.color = {0.0f, 0.0f, 0.0f, 1.0f};
    const auto add = [&](refraster::PrimitiveType p, std::vector<std::array<float, 4>> pos) {
        refraster::Draw d;
        d.primitive = p;
        d.state.viewport = {0, 0, 64, 48};
        d.state.depth_test = refraster::CompareFunc::Less;
        d.state.point_size = 3.0f;
        d.vertices.attributes = {{"color", 4}};
        for (const auto& v : pos)
            d.vertices.data.insert(d.vertices.data.end(),
                                   {v[0], v[1], v[2], v[3], 1, 0.5f, 0.25f, 1});
        l.draws.push_back(d);
    };
    add(refraster::PrimitiveType::Triangles, {{-0.9f, -0.8f, 0.1f, 1},
                                              {0.7f, -0.6f, 0.2f, 1},
                                              {-0.2f, 0.9f, 0.3f, 1},
                                              {-0.5f, -0.9f, -0.5f, 1},
                                              {2.0f, 0.1f, 0.5f, 1},
                                              {0.1f, 3.0f, 0.0f, 2}});
    add(refraster::PrimitiveType::Lines, {{-1, -1, 0, 1}, {1, 0.5f, 0, 1}});
    add(refraster::PrimitiveType::Points, {{0, 0, -0.9f, 1}, {0.5f, -0.5f, -0.9f, 1}});
    return l;
}

TEST(Render, StopsAfterEachStageWithoutDrawing) {
    const auto list = staged_list();
    refraster::Framebuffer full;
    ASSERT_EQ(refraster::render(list, full).status, refraster::RenderStatus::Ok);
    refraster::Framebuffer cleared;
    refraster::DrawList empty = list;
    empty.draws.clear();
    (void)refraster::render(empty, cleared);
    ASSERT_NE(full, cleared);
    for (auto stage : {refraster::RenderStage::Load, refraster::RenderStage::Setup,
                       refraster::RenderStage::Raster}) {
        refraster::RenderOptions o;
        o.stop_after = stage;
        refraster::Framebuffer fb;
        const auto r = refraster::render(list, o, fb);
        ASSERT_EQ(r.status, refraster::RenderStatus::Ok);
        EXPECT_EQ(fb, cleared) << static_cast<int>(stage);  // nothing shaded
        EXPECT_EQ(r.fragments == 0, stage != refraster::RenderStage::Raster)
            << static_cast<int>(stage);
    }
}

TEST(Render, TraversalCountsEveryCoveredPixel) {
    // One draw per primitive on a fresh target, depth test off: the covered pixels are exactly
    // the pixels the full render changes, for triangles, lines and points alike.
    const auto list = staged_list();
    for (std::size_t d = 0; d < list.draws.size(); ++d) {
        refraster::DrawList one = list;
        one.draws = {list.draws[d]};
        one.draws[0].state.depth_test.reset();
        refraster::RenderOptions o;
        o.stop_after = refraster::RenderStage::Raster;
        refraster::Framebuffer scratch, drawn;
        const auto counted = refraster::render(one, o, scratch).fragments;
        // Draw each primitive alone and count the pixels it changes.
        std::uint64_t changed = 0;
        const auto n =
            refraster::primitive_count(one.draws[0].primitive, one.draws[0].vertices.size());
        const std::size_t per = one.draws[0].primitive == refraster::PrimitiveType::Triangles ? 3
                                : one.draws[0].primitive == refraster::PrimitiveType::Lines   ? 2
                                                                                              : 1;
        for (std::size_t p = 0; p < n; ++p) {
            refraster::DrawList single = one;
            auto& data = single.draws[0].vertices.data;
            const std::size_t stride = single.draws[0].vertices.stride();
            data.assign(
                one.draws[0].vertices.data.begin() + static_cast<std::ptrdiff_t>(p * per * stride),
                one.draws[0].vertices.data.begin() +
                    static_cast<std::ptrdiff_t>((p + 1) * per * stride));
            ASSERT_EQ(refraster::render(single, drawn).status, refraster::RenderStatus::Ok);
            for (std::size_t i = 0; i < drawn.pixel_count(); ++i)
                changed += drawn.color8[4 * i] == 255;
        }
        EXPECT_EQ(counted, changed) << "draw " << d;
        EXPECT_GT(counted, 0u) << "draw " << d;
    }
}

}  // namespace

// The exact profile interpolates as GL asks: perspective-correct colour (the clip-space
// barycentric weights), noperspective colour (the window-space ones) and window depth, here
// on a triangle whose vertices' w are 1, 3 and 9. llvmpipe's rules interpolate the same values
// in float32, so the two images differ by at most one step of colour and depth.
TEST(Render, ExactProfileInterpolatesLikeTheSnappedOne) {
    for (const auto shade : {refraster::ShadeModel::Smooth, refraster::ShadeModel::NoPerspective}) {
        refraster::DrawList l;
        l.target = {32, 32, refraster::ColorFormat::Rgba8, refraster::DepthFormat::Z24, 1};
        refraster::Draw d;
        d.state.viewport = {0, 0, 32, 32};
        d.state.depth_test = refraster::CompareFunc::Always;
        d.state.shade = shade;
        d.vertices.attributes = {{"color", 4}};
        const float w[3] = {1.0f, 3.0f, 9.0f};
        const float ndc[3][3] = {{-0.9f, -0.9f, -0.5f}, {0.9f, -0.8f, 0.2f}, {-0.1f, 0.9f, 0.7f}};
        const float color[3][4] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
        for (int i = 0; i < 3; ++i) {
            for (int c = 0; c < 3; ++c) d.vertices.data.push_back(ndc[i][c] * w[i]);
            d.vertices.data.push_back(w[i]);
            for (float c : color[i]) d.vertices.data.push_back(c);
        }
        l.draws.push_back(d);
        refraster::Framebuffer snapped, exact;
        ASSERT_EQ(refraster::render(l, snapped).status, refraster::RenderStatus::Ok);
        refraster::RenderOptions o;
        o.profile = refraster::gl_exact_profile();
        ASSERT_EQ(refraster::render(l, o, exact).status, refraster::RenderStatus::Ok);
        int compared = 0;
        for (std::size_t i = 0; i < exact.pixel_count(); ++i) {
            if (exact.color8[4 * i + 3] == 0 || snapped.color8[4 * i + 3] == 0) continue;
            for (std::size_t c = 0; c < 3; ++c)
                EXPECT_LE(std::abs(exact.color8[4 * i + c] - snapped.color8[4 * i + c]), 1)
                    << "pixel " << i << " channel " << c;
            EXPECT_LE(
                std::abs(static_cast<long>(exact.depth[i]) - static_cast<long>(snapped.depth[i])),
                2)
                << "pixel " << i;
            ++compared;
        }
        EXPECT_GT(compared, 200);
    }
}

namespace {

// A fill rule is decided on the snapped outline (docs/scene-format.md, "Fill rules"): a vertex
// inside the view volume whose window position cannot be snapped (here x = 0 over a subnormal
// w, so x / w is 0 * inf = NaN) is refused with the message the format documents, naming the
// draw. Without the fill rule the same polygon is drawn.
TEST(Render, AFillRuleVertexOutsideTheSnappedRangeIsNotSupported) {
    auto l = cleared_list(refraster::DepthFormat::None, 1.0f);
    l.target.width = 8;
    l.target.height = 8;
    refraster::Draw d;
    d.primitive = PrimitiveType::Polygon;
    d.state.viewport = {0, 0, 8, 8};
    d.state.fill_rule = refraster::FillRule::EvenOdd;
    d.vertices.attributes = {{"color", 4}};
    d.vertices.data = {-1, -1, 0, 1,      1, 1, 1, 1,  //
                       1,  -1, 0, 1,      1, 1, 1, 1,  //
                       0,  0,  0, 1e-45f, 1, 1, 1, 1};
    l.draws = {refraster::Draw{}, d};  // an empty draw first: the index is the draw's own
    refraster::Framebuffer fb;
    const auto r = refraster::render(l, fb);
    EXPECT_EQ(r.status, refraster::RenderStatus::NotSupported);
    EXPECT_EQ(r.message, "a fill rule's vertex outside the snapped range (draws[1])");
    l.draws[1].state.fill_rule.reset();
    EXPECT_EQ(refraster::render(l, fb).status, refraster::RenderStatus::Ok);
}

}  // namespace
