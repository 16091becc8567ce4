// GL verdicts (harness/gl_verdict.hpp) on backends whose rules are known: the reference under a
// legal tie rule differs only legally; under the rules that break the single-owner requirement
// (tie_rule=none, tie_rule=all) the holes and double hits on shared edges are violations; a
// pixel lit far from every primitive is outside every legal coverage.
#include "harness/gl_verdict.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>

#include "harness/backend.hpp"
#include "harness/explain.hpp"
#include "harness/profile_io.hpp"
#include "harness/scene.hpp"
#include "layered_scene.hpp"
#include "refraster/renderer.hpp"

namespace {

refraster::Framebuffer render(const harness::Scene& s, const refraster::Profile& p) {
    refraster::RenderOptions o;
    o.profile = p;
    refraster::Framebuffer fb;
    EXPECT_EQ(refraster::render(s.draw_list, o, fb).status, refraster::RenderStatus::Ok);
    return fb;
}

refraster::Profile llvmpipe_with(const std::string& rule) {
    auto p = refraster::llvmpipe_22_3_profile();
    harness::apply_profile_overrides(p, {rule});
    return p;
}

harness::Scene suite_scene(const std::string& relative) {
    return harness::load_scene(std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes" /
                               relative);
}

// The reference under `p` as a backend (what explain compares against).
std::unique_ptr<harness::Backend> reference_backend(const refraster::Profile& p) {
    return harness::make_reference_backend(p);
}

bool has_finding(const harness::GlVerdict& v, const std::string& words, bool legal) {
    for (const auto& f : v.findings)
        if (f.legal == legal && f.rule.find(words) != std::string::npos && f.pixels > 0)
            return true;
    return false;
}

// Triangle strips whose shared edges run through pixel centres.
const char* kSharedEdges = "triangles/coverage/strip_shared_edges.json";

TEST(GlVerdict, AnotherConsistentTieRuleIsLegal) {
    const auto s = suite_scene(kSharedEdges);
    const auto ref = render(s, refraster::llvmpipe_22_3_profile());
    const auto other = render(s, llvmpipe_with("tie_rule=right-top"));
    const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, other);
    EXPECT_GT(v.differing, 0u);
    EXPECT_TRUE(v.passes()) << v.summary();
    EXPECT_TRUE(has_finding(v, "tie rule", true)) << v.summary();
}

// OpenGL 4.6, 14.6.5 leaves polygon offset's minimum resolvable difference r to the
// implementation: a backend with twice Mesa's r (zink on lavapipe) differs in depth only, and
// legally. Without the variation the depths fall outside the legal range: non-monotonic.
TEST(GlVerdict, AnotherPolygonOffsetResolutionIsLegal) {
    for (const char* scene : {"triangles/attributes/polygon_offset_z24_f0_um2.json",
                              "triangles/attributes/polygon_offset_z16_f2_u4.json"}) {
        SCOPED_TRACE(scene);
        const auto s = suite_scene(scene);
        const auto ref = render(s, refraster::llvmpipe_22_3_profile());
        const auto other = render(s, llvmpipe_with("offset_units_scale=2"));
        const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, other);
        EXPECT_GT(v.differing, 0u);
        EXPECT_TRUE(v.passes()) << v.summary();
        EXPECT_TRUE(has_finding(v, "polygon offset", true)) << v.summary();
    }
}

// OpenGL 4.6, 2.3.4.1: NaN, infinite and huge (beyond 2^32) colours give unspecified results.
// A backend that converts them otherwise (here: as if they were 0, so the pixels look like
// the clear colour) differs legally, never by a "hole".
TEST(GlVerdict, ColoursBeyondGlRangeAreUnspecifiedNeverHoles) {
    for (const char* scene :
         {"extreme/colour_extreme_rgba8.json", "extreme/colour_overflow_rgba8_alpha.json"}) {
        SCOPED_TRACE(scene);
        const auto s = suite_scene(scene);
        auto zeroed = s;
        for (auto& d : zeroed.draw_list.draws) {
            const std::size_t stride = d.vertices.stride();
            for (std::size_t i = 0; i < d.vertices.data.size(); ++i) {
                float& v = d.vertices.data[i];
                if (i % stride >= 4 && (!std::isfinite(v) || std::fabs(v) > 0x1p32f)) v = 0.0f;
            }
        }
        const auto ref = render(s, refraster::llvmpipe_22_3_profile());
        const auto other = render(zeroed, refraster::llvmpipe_22_3_profile());
        const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, other);
        EXPECT_GT(v.differing, 0u);
        EXPECT_TRUE(v.passes()) << v.summary();
        EXPECT_TRUE(has_finding(v, "unspecified", true)) << v.summary();
    }
}

// A 4x target is judged sample by sample: polygon offset's depth differs at samples whose
// resolved pixel agrees (the resolve keeps sample 0's depth), and every such sample is legal.
TEST(GlVerdict, MultisampledTargetsAreJudgedSampleBySample) {
    const auto s = suite_scene("msaa/polygon_offset_z24_units_coplanar.json");
    ASSERT_EQ(s.draw_list.target.samples, 4u);
    const auto ref = render(s, refraster::llvmpipe_22_3_profile());
    const auto other = render(s, llvmpipe_with("offset_units_scale=2"));
    ASSERT_EQ(ref.samples, 4u);
    const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, other);
    EXPECT_EQ(v.unit, "samples");
    EXPECT_GT(v.differing, 0u);
    EXPECT_TRUE(v.passes()) << v.summary();
    EXPECT_TRUE(has_finding(v, "polygon offset", true)) << v.summary();
}

// Draw state a backend ignores is a violation named by the requirement and its section:
// GL_MULTISAMPLE disabled on a 4x target (14.3.1), and a polygon's edge flags in polygon
// mode line (its internal edges drawn).
TEST(GlVerdict, IgnoredStateIsNamedByTheRequirement) {
    {
        const auto s = suite_scene("msaa/multisample_off_triangles.json");
        auto on = s;
        for (auto& d : on.draw_list.draws) d.state.multisample = true;
        const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(),
                                           render(s, refraster::llvmpipe_22_3_profile()),
                                           render(on, refraster::llvmpipe_22_3_profile()));
        EXPECT_GT(v.violations, 0u) << v.summary();
        EXPECT_TRUE(has_finding(v, "GL_MULTISAMPLE disabled is ignored (14.3.1", false))
            << v.summary();
    }
    {
        const auto s = suite_scene("polygons/outline_polygon_mode_line_first.json");
        auto fan = s;
        for (auto& d : fan.draw_list.draws)
            if (d.primitive == refraster::PrimitiveType::Polygon)
                d.primitive = refraster::PrimitiveType::TriangleFan;
        const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(),
                                           render(s, refraster::llvmpipe_22_3_profile()),
                                           render(fan, refraster::llvmpipe_22_3_profile()));
        EXPECT_GT(v.violations, 0u) << v.summary();
        EXPECT_TRUE(has_finding(v, "edge flags ignored", false)) << v.summary();
    }
}

// One answer: the rule explain names at a pixel is the freedom the GL verdict names there.
// smoke.depth against a backend that truncates depth: explain's alternatives include the
// conversions, so it names depth rounding, never "undecided", and the verdict agrees.
TEST(GlVerdict, ExplainAndVerdictNameTheSameRule) {
    const auto s = suite_scene("smoke/depth.json");
    auto backend = reference_backend(llvmpipe_with("depth_rounding=truncate"));
    const auto e =
        harness::explain_pixel(s, refraster::llvmpipe_22_3_profile(), 0, 0, backend.get());
    ASSERT_FALSE(e.agree);
    EXPECT_EQ(e.rule, "depth rounding") << e.verdict;
    std::string preferred;
    for (const auto& [rule, change] : e.candidates)
        if (rule == e.rule) preferred = change;
    EXPECT_EQ(preferred, "depth_rounding=truncate");
    const auto v =
        harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), e.reference_image,
                            e.backend->image, std::array<int, 2>{0, 0}, 0.0, 0, preferred);
    EXPECT_NE(v.at_pixel.find("legal: "), std::string::npos) << v.at_pixel;
    EXPECT_NE(v.at_pixel.find(preferred), std::string::npos) << v.at_pixel;
}

// At a corner shared by two triangles the explanation names the primitive that draws the
// pixel, on either side: pixel (10, 10) of square_through_centres has its centre on edges 0
// and 1 of triangle 0 and on two edges of triangle 1; under llvmpipe's left-bottom rule
// triangle 0 draws it, under right-top neither does.
TEST(GlVerdict, TheTieAtACornerNamesThePrimitiveThatDrawsIt) {
    const auto s = suite_scene("triangles/coverage/square_through_centres.json");
    // The reference draws it, the backend does not.
    auto right_top = reference_backend(llvmpipe_with("tie_rule=right-top"));
    const auto e =
        harness::explain_pixel(s, refraster::llvmpipe_22_3_profile(), 10, 10, right_top.get());
    ASSERT_FALSE(e.agree) << e.verdict;
    EXPECT_EQ(e.rule, "tie rule") << e.verdict;
    EXPECT_NE(e.verdict.find("edges 0 and 1 of draws[0] triangle 0, and the left-bottom rule "
                             "gives the pixel to it"),
              std::string::npos)
        << e.verdict;
    EXPECT_EQ(e.verdict.find("triangle 1"), std::string::npos) << e.verdict;
    // The backend draws it (triangle 0), the reference does not.
    auto left_bottom = reference_backend(refraster::llvmpipe_22_3_profile());
    const auto f =
        harness::explain_pixel(s, llvmpipe_with("tie_rule=right-top"), 10, 10, left_bottom.get());
    ASSERT_FALSE(f.agree) << f.verdict;
    EXPECT_NE(f.verdict.find("of draws[0] triangle 0, and the right-top rule keeps the pixel"),
              std::string::npos)
        << f.verdict;
    EXPECT_EQ(f.verdict.find("triangle 1"), std::string::npos) << f.verdict;
}

TEST(GlVerdict, CentresOnSharedEdgesWithoutOwnerAreHoles) {
    const auto s = suite_scene(kSharedEdges);
    const auto ref = render(s, refraster::llvmpipe_22_3_profile());
    const auto holes = render(s, llvmpipe_with("tie_rule=none"));
    const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, holes);
    EXPECT_FALSE(v.passes()) << v.summary();
    EXPECT_GT(v.violations, 0u);
    EXPECT_TRUE(has_finding(v, "hole on a shared edge", false)) << v.summary();
}

// Two triangles sharing a diagonal through pixel centres, added into the target: a centre
// drawn by both shows twice the colour.
harness::Scene blended_pair() {
    harness::Scene s;
    s.file.name = "blended_pair";
    s.file.target = {16, 16, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None, 1};
    s.draw_list.target = s.file.target;
    refraster::Draw d;
    d.primitive = refraster::PrimitiveType::Triangles;
    d.state.viewport = {0, 0, 16, 16};
    d.state.blend = refraster::BlendPreset::Add;
    d.vertices.attributes = {{"color", 4}};
    // Window corners (2.5, 2.5), (12.5, 2.5), (12.5, 12.5), (2.5, 12.5): the diagonal
    // (2.5, 2.5)-(12.5, 12.5) passes through the centres (k + 0.5, k + 0.5).
    const auto v = [&](float x, float y) {
        d.vertices.data.insert(d.vertices.data.end(), {x / 8.0f - 1.0f, y / 8.0f - 1.0f, 0.0f, 1.0f,
                                                       0.25f, 0.25f, 0.25f, 0.25f});
    };
    v(2.5f, 2.5f), v(12.5f, 2.5f), v(12.5f, 12.5f);
    v(2.5f, 2.5f), v(12.5f, 12.5f), v(2.5f, 12.5f);
    s.draw_list.draws.push_back(d);
    return s;
}

TEST(GlVerdict, CentresOnSharedEdgesWithTwoOwnersAreDoubleHits) {
    const auto s = blended_pair();
    const auto ref = render(s, refraster::llvmpipe_22_3_profile());
    const auto doubled = render(s, llvmpipe_with("tie_rule=all"));
    const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, doubled);
    EXPECT_FALSE(v.passes()) << v.summary();
    EXPECT_TRUE(has_finding(v, "double hit on a shared edge", false)) << v.summary();
}

TEST(GlVerdict, APixelFarFromEveryPrimitiveIsOutsideEveryLegalCoverage) {
    const auto s = blended_pair();
    const auto ref = render(s, refraster::llvmpipe_22_3_profile());
    auto stray = ref;
    const std::size_t i = stray.index(15, 0);
    for (std::size_t k = 0; k < 4; ++k) stray.color8[4 * i + k] = 200;
    const auto v =
        harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, stray, std::array{15, 0});
    EXPECT_EQ(v.differing, 1u);
    EXPECT_EQ(v.violations, 1u);
    EXPECT_TRUE(has_finding(v, "outside every legal coverage", false)) << v.summary();
    EXPECT_NE(v.at_pixel.find("violation"), std::string::npos) << v.at_pixel;
}

// Each variation's render is bounded by the timeout: on a scene that takes the reference
// many seconds a render (13 s on two threads of the development machine), every variation
// stops within its 0.05 s and, since a variation that could not be rendered might have
// reproduced the pixel, nothing is called a violation: the pixel is unexplained, and the
// summary says why.
TEST(GlVerdict, VariationsStopAtTheTimeoutAndProveNothing) {
    const auto s = harness::load_scene_text(testutil::layered_scene(2048, 400), "layers.json");
    harness::Scene cleared = s;
    cleared.draw_list.draws.clear();
    const auto ref = render(cleared, refraster::llvmpipe_22_3_profile());
    auto stray = ref;
    const std::size_t i = stray.index(5, 5);
    for (std::size_t k = 0; k < 4; ++k) stray.color8[4 * i + k] = 200;
    const auto v = harness::gl_verdict(s, refraster::llvmpipe_22_3_profile(), ref, stray,
                                       std::array{5, 5}, 0.05);
    EXPECT_EQ(v.differing, 1u);
    EXPECT_GT(v.variations, 0u);
    EXPECT_GE(v.stopped, v.variations) << v.summary();  // each variation (the clear may finish)
    EXPECT_EQ(v.violations, 0u) << v.summary();
    EXPECT_EQ(v.unexplained, 1u) << v.summary();
    EXPECT_NE(v.at_pixel.find("stopped at the timeout"), std::string::npos) << v.at_pixel;
    EXPECT_NE(v.summary().find("variations stopped at the timeout, so no violation is claimed"),
              std::string::npos)
        << v.summary();
}

}  // namespace
