// explain's verdict on every mismatching pixel of every shipped scene (of a 4x scene, every
// mismatching sample, one sample plane at a time): against softpipe (rules that really differ)
// and against llvmpipe under deliberately wrong profiles (where the rule that differs is known).
// Each verdict is checked against what the two renders show, and a named rule is checked by
// rendering the scene again under the alternative it names.
#include <gtest/gtest.h>

#include <bit>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "harness/explain.hpp"
#include "harness/profile_io.hpp"
#include "harness/rule_search.hpp"
#include "harness/scene.hpp"
#include "refraster/renderer.hpp"

namespace {

std::vector<std::filesystem::path> shipped_scenes() {
    std::vector<std::filesystem::path> out;
    for (const auto& e : std::filesystem::recursive_directory_iterator(
             std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes")) {
        if (e.is_regular_file() && e.path().extension() == ".json") out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::unique_ptr<harness::Backend> osmesa(harness::Driver d) {
    harness::BackendOptions o;
    o.kind = harness::BackendKind::OSMesa;
    o.driver = d;
    return harness::make_backend(o);
}

// The clear as the reference stores it, for telling untouched pixels apart.
refraster::Framebuffer clear_pixel(const harness::Scene& s) {
    refraster::DrawList empty;
    empty.target = {1, 1, s.draw_list.target.color, s.draw_list.target.depth, 1};
    empty.clear = s.draw_list.clear;
    refraster::Framebuffer fb;
    (void)refraster::render(empty, {}, fb);
    return fb;
}

bool same_color(const refraster::Framebuffer& a, std::size_t i, const refraster::Framebuffer& b,
                std::size_t j) {
    for (std::size_t k = 0; k < 4; ++k) {
        const bool same = a.color_format == refraster::ColorFormat::Rgba8
                              ? a.color8[4 * i + k] == b.color8[4 * j + k]
                              : std::bit_cast<std::uint32_t>(a.color32f[4 * i + k]) ==
                                    std::bit_cast<std::uint32_t>(b.color32f[4 * j + k]);
        if (!same) return false;
    }
    return true;
}

bool same_depth(const refraster::Framebuffer& a, std::size_t i, const refraster::Framebuffer& b,
                std::size_t j) {
    return a.depth_format == refraster::DepthFormat::None || a.depth[i] == b.depth[j];
}

const std::set<std::string> kCoverageOnlyRules{"tie rule", "snapping",  "nine-vertex analysis",
                                               "cull",     "line rule", "point rule"};

struct Tally {
    std::map<std::string, std::size_t> by_verdict;  // "difference/rule"
    std::size_t pixels = 0;
};

// Explains every mismatching pixel of every scene and checks each verdict, counting them in
// `tally`; stops at the first scene with a failure.
// `expected_rule`, when set, is the rule every verdict must name (or list as a candidate when
// the trace shows another candidate at work).
void check_every_pixel(harness::Backend& backend, const refraster::Profile& profile,
                       const std::string& expected_rule, Tally& tally) {
    for (const auto& file : shipped_scenes()) {
        const harness::Scene scene = harness::load_scene(file);
        // A 4x scene is explained sample by sample: each sample's plane is an image of its own.
        const bool multisampled = scene.draw_list.target.samples > 1;
        for (int sample = multisampled ? 0 : -1; sample < (multisampled ? 4 : 0); ++sample) {
            std::unique_ptr<harness::Explainer> made;
            try {
                made = std::make_unique<harness::Explainer>(scene, profile, &backend, sample);
            } catch (const std::runtime_error&) {
                if (multisampled) break;  // a driver without multisampling (softpipe)
                throw;
            }
            harness::Explainer& ex = *made;
            const auto& ref = ex.reference_image();
            const auto& act = ex.backend_image();
            const auto clear = clear_pixel(scene);
            const auto cmp =
                harness::compare_images(ref, act, scene.draw_list.clear, scene.file.expect);
            if (cmp.mismatched_pixels == 0) continue;
            std::map<std::string, std::unique_ptr<refraster::Framebuffer>>
                rerendered;  // by alternative
            for (std::uint32_t y = 0; y < ref.height; ++y) {
                for (std::uint32_t x = 0; x < ref.width; ++x) {
                    const std::size_t i = ref.index(x, y);
                    const auto cls = ex.classifier()->at(i).cls;
                    if (cls == harness::PixelClass::Equal) continue;
                    const auto e = ex.explain(static_cast<int>(x), static_cast<int>(y), false);
                    const std::string at =
                        file.filename().string() + " (" + std::to_string(x) + ", " +
                        std::to_string(y) + ")" +
                        (sample >= 0 ? " sample " + std::to_string(sample) : "") + ": " + e.verdict;
                    ++tally.pixels;
                    ++tally.by_verdict[e.difference + "/" + e.rule];
                    ASSERT_FALSE(e.agree) << at;
                    // The class follows from the pixels alone.
                    const bool ref_untouched =
                        same_color(ref, i, clear, 0) && same_depth(ref, i, clear, 0);
                    const bool act_untouched =
                        same_color(act, i, clear, 0) && same_depth(act, i, clear, 0);
                    if (ref_untouched != act_untouched) {
                        EXPECT_EQ(e.difference, "coverage") << at;
                    }
                    if (same_color(ref, i, act, i) && e.difference != "coverage") {
                        EXPECT_EQ(e.difference, "depth") << at;
                    }
                    if (!same_color(ref, i, act, i) && e.difference != "coverage") {
                        EXPECT_EQ(e.difference, "colour") << at;
                    }
                    if (e.difference != "coverage") {
                        EXPECT_EQ(kCoverageOnlyRules.count(e.rule), 0u) << at;
                    }
                    // A named rule is one whose alternative reproduces the backend at this pixel:
                    // render the scene under it and look.
                    const auto named =
                        std::find_if(e.candidates.begin(), e.candidates.end(),
                                     [&](const auto& c) { return c.first == e.rule; });
                    if ((e.rule == "line rule" || e.rule == "point rule") &&
                        named == e.candidates.end()) {
                        // Only lines (points) reach the pixel and nothing reproduces it.
                        EXPECT_TRUE(e.candidates.empty()) << at;
                    } else if (e.rule == "undecided") {
                        // Either nothing reproduces the backend, or several rules do equally well.
                        EXPECT_NE(e.candidates.size(), 1u) << at;
                    } else {
                        ASSERT_NE(named, e.candidates.end()) << at;
                        auto& fb = rerendered[named->second];
                        if (!fb) {
                            // The variation named, as the rule search states it.
                            const auto vars = harness::rule_variations(profile, scene);
                            const auto var = std::find_if(
                                vars.begin(), vars.end(),
                                [&](const auto& v) { return v.setting == named->second; });
                            ASSERT_NE(var, vars.end()) << at;
                            refraster::RenderOptions o;
                            o.profile = var->profile;
                            fb = std::make_unique<refraster::Framebuffer>();
                            ASSERT_EQ(refraster::render(
                                          (var->scene ? *var->scene : scene).draw_list, o, *fb)
                                          .status,
                                      refraster::RenderStatus::Ok);
                            if (sample >= 0) {
                                *fb = refraster::sample_plane(*fb,
                                                              static_cast<std::uint32_t>(sample));
                            }
                        }
                        const bool coverage_class = cls == harness::PixelClass::Missing ||
                                                    cls == harness::PixelClass::Extra ||
                                                    cls == harness::PixelClass::Coverage;
                        if (coverage_class) {
                            EXPECT_EQ(same_color(*fb, i, clear, 0) && same_depth(*fb, i, clear, 0),
                                      act_untouched)
                                << at;
                        } else {
                            // A colour or depth difference is reproduced byte for byte.
                            EXPECT_TRUE(same_color(*fb, i, act, i) && same_depth(*fb, i, act, i))
                                << at;
                        }
                    }
                    if (!expected_rule.empty()) {
                        const bool listed =
                            std::any_of(e.candidates.begin(), e.candidates.end(),
                                        [&](const auto& c) { return c.first == expected_rule; });
                        EXPECT_TRUE(listed) << at;
                        if (e.rule != "undecided") {
                            EXPECT_EQ(e.rule, expected_rule) << at;
                        }
                    }
                    if (::testing::Test::HasFailure()) return;
                }
            }
        }
    }
}

void print(const std::string& what, const Tally& t) {
    std::cout << what << ": " << t.pixels << " mismatching pixels;";
    for (const auto& [v, n] : t.by_verdict) std::cout << " " << v << " " << n << ";";
    std::cout << "\n";
}

TEST(ExplainVerdicts, EveryPixelAgainstSoftpipe) {
    auto backend = osmesa(harness::Driver::Softpipe);
    Tally t;
    check_every_pixel(*backend, harness::load_profile("llvmpipe-22.3"), "", t);
    print("softpipe", t);
    EXPECT_GT(t.pixels, 1000u);  // softpipe's rules really differ
    // Its tie rule differs from llvmpipe's: some of the differences are named by it.
    EXPECT_GT(t.by_verdict["coverage/tie rule"], 0u);
}

struct Mutation {
    const char* change;
    const char* rule;
};

class ExplainVerdictsMutated : public ::testing::TestWithParam<Mutation> {};

TEST_P(ExplainVerdictsMutated, EveryPixelNamesTheMutatedRule) {
    auto backend = osmesa(harness::Driver::Llvmpipe);
    auto profile = harness::load_profile("llvmpipe-22.3");
    harness::apply_profile_overrides(profile, {GetParam().change});
    if (std::string(GetParam().change) == "viewport_fma=off" && !refraster::host_has_fma()) {
        GTEST_SKIP() << "without FMA, unfused arithmetic is what llvmpipe does";
    }
    Tally t;
    check_every_pixel(*backend, profile, GetParam().rule, t);
    print(GetParam().change, t);
    // The mutated rule is named at nearly every pixel; "undecided" only where another rule
    // brings the image into agreement exactly as well (a point that the tie rule and a coarser
    // grid both move).
    EXPECT_LE(t.by_verdict["coverage/undecided"] + t.by_verdict["colour/undecided"] +
                  t.by_verdict["depth/undecided"],
              t.pixels / 100);
    EXPECT_GT(t.pixels, 0u) << "the mutation changes no pixel of the suite";
}

INSTANTIATE_TEST_SUITE_P(
    Profiles, ExplainVerdictsMutated,
    ::testing::Values(Mutation{"tie_rule=right-top", "tie rule"},
                      Mutation{"tie_rule=left-top", "tie rule"},
                      Mutation{"tie_rule=right-bottom", "tie rule"},
                      Mutation{"snap_rounding=half-away", "snapping"},
                      Mutation{"subpixel_bits=4", "snapping"},
                      Mutation{"nine_vertex_quirk=false", "nine-vertex analysis"},
                      Mutation{"draw_pipeline_cull=false", "cull"},
                      Mutation{"viewport_fma=off", "fused arithmetic"},
                      Mutation{"wrapping_arithmetic=false", "integer widths"},
                      Mutation{"draw_offset_nan_to_zero=false", "NaN depth from polygon offset"},
                      Mutation{"offset_units_scale=2", "polygon offset r"}),
    [](const auto& p) {
        std::string n = p.param.change;
        for (auto& c : n) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
        return n;
    });

#ifdef REFRASTER_HAVE_EGL
// zink on lavapipe, an implementation nobody modelled, under llvmpipe's profile: every verdict
// is checked as above, and the rules it differs by are named: polygon offset's r, the point
// and line clipping policy, and the two GL rules it breaks (edge flags, GL_MULTISAMPLE off).
TEST(ExplainVerdicts, EveryPixelAgainstZink) {
    harness::BackendOptions o;
    o.kind = harness::BackendKind::Egl;
    o.driver = harness::Driver::Zink;
    auto backend = harness::make_backend(o);
    Tally t;
    check_every_pixel(*backend, harness::load_profile("llvmpipe-22.3"), "", t);
    print("zink", t);
    EXPECT_GT(t.pixels, 0u);
    for (const char* named : {"depth/polygon offset r", "coverage/edge flags",
                              "coverage/multisample enable", "coverage/clipper"})
        EXPECT_GT(t.by_verdict[named], 0u) << named;
}
#endif

// softpipe under its own profile with one rule of its own mutated: the write-back of its
// colour tiles by a fill rule's stencil clear. Only the scenes that blend at or after a
// fill-rule draw change, and every pixel that does is put down to that rule.
TEST(ExplainVerdicts, SoftpipeTileWriteBackIsNamed) {
    auto backend = osmesa(harness::Driver::Softpipe);
    auto profile = harness::load_profile("softpipe-22.3");
    harness::apply_profile_overrides(profile, {"fill_clear_writes_tiles=false"});
    Tally t;
    check_every_pixel(*backend, profile, "tile write-back", t);
    print("softpipe, fill_clear_writes_tiles=false", t);
    EXPECT_GT(t.pixels, 0u) << "the mutation changes no pixel of the suite";
    EXPECT_EQ(t.by_verdict["colour/tile write-back"], t.pixels);
}

// The two scenes of these rules against both drivers under their own profiles: byte for byte.
TEST(ExplainVerdicts, NanOffsetAndTileWriteBackScenesMatch) {
    const std::string root = std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/";
    for (const char* name :
         {"points/polygon_mode_point_offset_nan.json", "polygons/blend_over_fill_star.json"}) {
        const harness::Scene scene = harness::load_scene(root + name);
        for (auto driver : {harness::Driver::Llvmpipe, harness::Driver::Softpipe}) {
            auto backend = osmesa(driver);
            const auto profile = harness::load_profile(
                driver == harness::Driver::Llvmpipe ? "llvmpipe-22.3" : "softpipe-22.3");
            harness::Explainer ex(scene, profile, backend.get(), -1);
            const auto cmp = harness::compare_images(ex.reference_image(), ex.backend_image(),
                                                     scene.draw_list.clear, scene.file.expect);
            EXPECT_EQ(cmp.mismatched_pixels, 0u)
                << name << (driver == harness::Driver::Llvmpipe ? " llvmpipe" : " softpipe");
        }
    }
}

}  // namespace
