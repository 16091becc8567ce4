// refraster fingerprint against OSMesa: llvmpipe comes back as llvmpipe-22.3 and softpipe as
// softpipe-22.3, every probed rule decided (harness/fingerprint.hpp); and GL verdicts over the
// suite (harness/gl_verdict.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "harness/backend.hpp"
#include "harness/fingerprint.hpp"
#include "refraster/profile.hpp"

namespace {

harness::FingerprintResult fingerprint_osmesa(harness::Driver driver) {
    harness::BackendOptions o;
    o.kind = harness::BackendKind::OSMesa;
    o.driver = driver;
    const auto backend = harness::make_backend(o);
    return harness::fingerprint(*backend);
}

TEST(FingerprintOsmesa, LlvmpipeIsLlvmpipe223) {
    const auto r = fingerprint_osmesa(harness::Driver::Llvmpipe);
    EXPECT_TRUE(r.complete()) << harness::fingerprint_text(r);
    EXPECT_EQ(r.profile, refraster::llvmpipe_22_3_profile()) << harness::fingerprint_text(r);
}

TEST(FingerprintOsmesa, SoftpipeIsSoftpipe223) {
    const auto r = fingerprint_osmesa(harness::Driver::Softpipe);
    EXPECT_TRUE(r.complete()) << harness::fingerprint_text(r);
    EXPECT_EQ(r.profile, refraster::softpipe_22_3_profile()) << harness::fingerprint_text(r);
}

}  // namespace

// GL verdicts over the suite: OSMesa softpipe judged against the llvmpipe profile differs in
// many scenes and legally everywhere; the reference with no owner for centres on edges
// (tie_rule=none) is caught violating GL in the scenes with shared edges.
#include <filesystem>

#include "harness/gl_verdict.hpp"
#include "harness/image_io.hpp"
#include "harness/profile_io.hpp"
#include "refraster/renderer.hpp"

namespace {

std::vector<std::filesystem::path> single_sample_scenes() {
    std::vector<std::filesystem::path> out;
    for (const auto& e : std::filesystem::recursive_directory_iterator(
             std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes")) {
        if (e.path().extension() == ".json") out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

TEST(GlVerdictSuite, SoftpipeIsALegalVariationOfLlvmpipeEverywhere) {
    // Scenes with PNG textures read them through the image library.
    harness::set_texture_file_reader(&harness::read_texture_png);
    harness::BackendOptions o;
    o.kind = harness::BackendKind::OSMesa;
    o.driver = harness::Driver::Softpipe;
    const auto softpipe = harness::make_backend(o);
    const auto profile = refraster::llvmpipe_22_3_profile();
    int judged = 0, differing = 0;
    for (const auto& path : single_sample_scenes()) {
        const auto scene = harness::load_scene(path);
        if (scene.draw_list.target.samples != 1) continue;
        refraster::RenderOptions ro;
        ro.profile = profile;
        refraster::Framebuffer ref;
        ASSERT_EQ(refraster::render(scene.draw_list, ro, ref).status, refraster::RenderStatus::Ok);
        const auto r = softpipe->render(scene);
        ASSERT_EQ(r.status, harness::RenderStatus::Ok) << path << ": " << r.message;
        const auto v = harness::gl_verdict(scene, profile, ref, r.image);
        ++judged;
        differing += v.differing > 0;
        EXPECT_TRUE(v.passes()) << path << ": " << v.summary();
    }
    EXPECT_GT(judged, 250);
    EXPECT_GT(differing, 100);
}

TEST(GlVerdictSuite, MissingEdgeOwnersAreViolations) {
    const auto profile = refraster::llvmpipe_22_3_profile();
    auto broken = profile;
    harness::apply_profile_overrides(broken, {"tie_rule=none"});
    int violating = 0;
    for (const auto& path : single_sample_scenes()) {
        if (path.string().find("/coverage/") == std::string::npos) continue;
        const auto scene = harness::load_scene(path);
        refraster::RenderOptions a, b;
        a.profile = profile;
        b.profile = broken;
        refraster::Framebuffer ref, holes;
        ASSERT_EQ(refraster::render(scene.draw_list, a, ref).status, refraster::RenderStatus::Ok);
        ASSERT_EQ(refraster::render(scene.draw_list, b, holes).status, refraster::RenderStatus::Ok);
        const auto v = harness::gl_verdict(scene, profile, ref, holes);
        violating += v.violations > 0;
    }
    EXPECT_GT(violating, 3);
}

}  // namespace
