// The one rule search (harness/rule_search.hpp): which variations a scene and a profile can
// show, their GL standing, and that explain and the GL verdict answer from it alike, for a
// freedom, a violation of draw state and another implementation's rule set.
#include "harness/rule_search.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "harness/backend.hpp"
#include "harness/explain.hpp"
#include "harness/gl_verdict.hpp"
#include "harness/profile_io.hpp"
#include "harness/scene.hpp"
#include "refraster/renderer.hpp"

namespace {

harness::Scene suite_scene(const std::string& relative) {
    return harness::load_scene(std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes" /
                               relative);
}

const harness::RuleVariation* find(const std::vector<harness::RuleVariation>& vars,
                                   const std::string& setting) {
    const auto it =
        std::find_if(vars.begin(), vars.end(), [&](const auto& v) { return v.setting == setting; });
    return it == vars.end() ? nullptr : &*it;
}

// A backend that draws the scene as the reference does under a profile, after `change` has
// altered the scene: an implementation that ignores some of its state.
class AlteringBackend : public harness::Backend {
  public:
    AlteringBackend(refraster::Profile p, std::function<void(harness::Scene&)> change)
        : profile_(std::move(p)), change_(std::move(change)) {}
    harness::BackendKind kind() const override { return harness::BackendKind::Ref; }
    std::string name() const override { return "altered"; }
    harness::RenderResult render(const harness::Scene& scene) override {
        harness::Scene s = scene;
        change_(s);
        harness::RenderResult r;
        refraster::RenderOptions o;
        o.profile = profile_;
        refraster::Framebuffer fb;
        const auto out = refraster::render(s.draw_list, o, fb);
        r.status = out.status == refraster::RenderStatus::Ok ? harness::RenderStatus::Ok
                                                             : harness::RenderStatus::InternalError;
        if (fb.samples > 1) {
            r.samples = fb;
            r.image = refraster::resolve_samples(fb);
        } else {
            r.image = std::move(fb);
        }
        return r;
    }

  private:
    refraster::Profile profile_;
    std::function<void(harness::Scene&)> change_;
};

TEST(RuleSearch, OnlyRulesTheModelReadsAndTheSceneShowsAreVaried) {
    const auto triangles = suite_scene("smoke/depth.json");
    const auto llvmpipe = harness::rule_variations(refraster::llvmpipe_22_3_profile(), triangles);
    EXPECT_NE(find(llvmpipe, "tie_rule=right-top"), nullptr);
    EXPECT_NE(find(llvmpipe, "snap_rounding=truncate"), nullptr);
    EXPECT_NE(find(llvmpipe, "softpipe-22.3"), nullptr);
    EXPECT_EQ(find(llvmpipe, "llvmpipe-22.3"), nullptr);  // the profile itself
    EXPECT_EQ(find(llvmpipe, "tie_rule=left-bottom"), nullptr);
    // Lines, points, offsets and fill rules are absent from a scene of filled triangles.
    EXPECT_EQ(find(llvmpipe, "line_rule=bresenham"), nullptr);
    EXPECT_EQ(find(llvmpipe, "point_rule=two-triangles"), nullptr);
    EXPECT_EQ(find(llvmpipe, "offset_units_scale=2"), nullptr);
    EXPECT_EQ(find(llvmpipe, "fill_clear_writes_tiles=false"), nullptr);
    // The scanline model does not snap: no snap rounding, and its holes and double hits are
    // those of llvmpipe's snapped rules.
    const auto softpipe = harness::rule_variations(refraster::softpipe_22_3_profile(), triangles);
    EXPECT_EQ(find(softpipe, "snap_rounding=truncate"), nullptr);
    EXPECT_EQ(find(softpipe, "tie_rule=right-top"), nullptr);
    const auto* hole = find(softpipe, "tie_rule=none");
    ASSERT_NE(hole, nullptr);
    EXPECT_FALSE(hole->legal);
    EXPECT_EQ(hole->profile.model, refraster::CoverageModel::Snapped);
    // No variation is the profile itself, and every one renders.
    for (const auto& v : llvmpipe) {
        EXPECT_TRUE(v.scene != nullptr ||
                    harness::profile_rules(v.profile) !=
                        harness::profile_rules(refraster::llvmpipe_22_3_profile()))
            << v.setting;
        EXPECT_FALSE(v.gl.empty()) << v.setting;
    }
}

TEST(RuleSearch, EveryVariationHasItsGlStanding) {
    EXPECT_EQ(harness::gl_standing("tie_rule", "right-top").rfind("legal: tie rule (14.6.1", 0),
              0u);
    EXPECT_EQ(harness::gl_standing("tie_rule", "none").rfind("violation: hole", 0), 0u);
    EXPECT_EQ(harness::gl_standing("nine_vertex_quirk", "true").rfind("violation: ", 0), 0u);
    EXPECT_EQ(harness::gl_standing("nine_vertex_quirk", "false").rfind("legal: ", 0), 0u);
    EXPECT_NE(harness::gl_standing("flush_denormals", "true").find("2.3.4.1"), std::string::npos);
    EXPECT_NE(harness::gl_standing("offset_units_scale", "2").find("14.6.5"), std::string::npos);
    EXPECT_EQ(harness::gl_standing("draw_segment_vertices", "3"), "");
    // The fingerprint searches the same values.
    EXPECT_EQ(harness::search_values("offset_units_scale"),
              (std::vector<std::string>{"0.25", "0.5", "1", "2", "4"}));
    const auto ties = harness::search_values("tie_rule");
    EXPECT_NE(std::find(ties.begin(), ties.end(), "none"), ties.end());
}

// Every rule of a profile is searched, or left out for a stated reason: a new parameter cannot
// be added without deciding its GL standing.
TEST(RuleSearch, EveryProfileParameterIsSearchedOrLeftOutForAReason) {
    const std::map<std::string, std::string> left_out{
        {"name", "not a rule"},
        {"coverage", "searched whole, as another implementation's rule set"},
        {"pixel_center_offset", "every GL implementation puts centres at half-integers"},
        {"draw_segment_vertices", "changes only where the draw module splits, never a pixel alone"},
    };
    for (const auto& [key, value] : refraster::profile_parameters(refraster::Profile{})) {
        const bool searched = !harness::search_values(key).empty();
        EXPECT_NE(searched, left_out.count(key) == 1) << key;
        if (searched) {
            EXPECT_FALSE(harness::gl_standing(key, harness::search_values(key).front()).empty())
                << key;
        }
    }
}

// An implementation that draws a GL_POLYGON's internal edges in polygon mode line: explain
// names the rule it breaks, and the verdict says the same at the same pixel.
TEST(RuleSearch, ExplainNamesIgnoredEdgeFlagsAsTheVerdictDoes) {
    const auto s = suite_scene("polygons/outline_polygon_mode_line_first.json");
    const auto profile = refraster::llvmpipe_22_3_profile();
    AlteringBackend fan(profile, [](harness::Scene& scene) {
        for (auto& d : scene.draw_list.draws)
            if (d.primitive == refraster::PrimitiveType::Polygon)
                d.primitive = refraster::PrimitiveType::TriangleFan;
    });
    harness::Explainer ex(s, profile, &fan);
    const auto& ref = ex.reference_image();
    std::optional<std::array<int, 2>> at;
    for (std::uint32_t y = 0; y < ref.height && !at; ++y)
        for (std::uint32_t x = 0; x < ref.width && !at; ++x)
            if (ex.classifier()->at(ref.index(x, y)).cls != harness::PixelClass::Equal)
                at = std::array<int, 2>{static_cast<int>(x), static_cast<int>(y)};
    ASSERT_TRUE(at.has_value());
    const auto e = ex.explain((*at)[0], (*at)[1]);
    EXPECT_EQ(e.rule, "edge flags") << e.verdict;
    EXPECT_EQ(e.standing.rfind("violation: edge flags ignored", 0), 0u) << e.standing;
    const auto v =
        harness::gl_verdict(s, profile, ref, ex.backend_image(), at, 0.0, 0, "edge flags ignored");
    EXPECT_EQ(v.at_pixel.rfind("violation: edge flags ignored", 0), 0u) << v.at_pixel;
}

// A backend with softpipe's depth rounding and llvmpipe's coverage: explain names the single
// rule, not softpipe's whole rule set, which it lists; a difference only softpipe's rule set
// reproduces is put down to it, legal in both outputs.
TEST(RuleSearch, AnotherImplementationIsNamedOnlyWhereNoSingleRuleIs) {
    const auto s = suite_scene("smoke/depth.json");
    const auto profile = refraster::llvmpipe_22_3_profile();
    auto truncating = refraster::llvmpipe_22_3_profile();
    harness::apply_profile_overrides(truncating, {"depth_rounding=truncate"});
    AlteringBackend backend(truncating, [](harness::Scene&) {});
    const auto e = harness::explain_pixel(s, profile, 0, 0, &backend);
    ASSERT_FALSE(e.agree);
    EXPECT_EQ(e.rule, "depth rounding") << e.verdict;
    EXPECT_NE(e.verdict.find("another implementation (softpipe-22.3)"), std::string::npos)
        << e.verdict;
    // softpipe itself at a pixel its coverage decides: named by its rule set when no single
    // parameter reproduces it.
    const auto t = suite_scene("triangles/coverage/square_through_centres.json");
    AlteringBackend softpipe(refraster::softpipe_22_3_profile(), [](harness::Scene&) {});
    harness::Explainer ex(t, profile, &softpipe);
    const auto& ref = ex.reference_image();
    std::size_t named_whole = 0;
    for (std::uint32_t y = 0; y < ref.height; ++y) {
        for (std::uint32_t x = 0; x < ref.width; ++x) {
            if (ex.classifier()->at(ref.index(x, y)).cls == harness::PixelClass::Equal) continue;
            const auto f = ex.explain(static_cast<int>(x), static_cast<int>(y), false);
            if (f.rule != "another implementation") continue;
            ++named_whole;
            EXPECT_EQ(f.standing, "legal: another conforming implementation's rules");
            for (const auto& [rule, change] : f.candidates)
                EXPECT_EQ(rule, "another implementation") << f.verdict;
        }
    }
    SUCCEED() << named_whole << " pixels put down to softpipe's rule set";
}

}  // namespace
