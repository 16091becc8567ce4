// `refraster render` end to end: usage errors, NotSupported, and a written image.
#include <gtest/gtest.h>

#include "harness/image_io.hpp"
#include "test_util.hpp"

namespace {

TEST(Cli, UnknownSubcommandIsUsageError) {
    const auto r = testutil::run_cli({"frobnicate"});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
}

TEST(Cli, HelpOnSubcommand) {
    const auto r = testutil::run_cli({"render", "--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("--backend"), std::string::npos);
}

TEST(Cli, RefBackendRefusesPrimitivesWithExitFour) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 4, "height": 4, "samples": 4},
      "draws": [{"primitive": "lines", "vertices": [{"position": [0, 0]}, {"position": [4, 0]}]}]})");
    const auto out = dir.path() / "o.png";
    // The exact profile draws filled triangles of single-sample targets only.
    const auto r = testutil::run_cli({"render", scene.string(), "--backend", "ref", "--profile",
                                      "gl-exact", "-o", out.string()});
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
    EXPECT_NE(r.err.find("NotSupported"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(Cli, RequiredUnknownExtensionIsNotSupported) {
    testutil::TempDir dir;
    const auto scene =
        dir.write("s.json", R"({"format": "refraster-scene/1", "requires": ["x-future"],
      "target": {"width": 4, "height": 4}, "draws": []})");
    const auto r =
        testutil::run_cli({"render", scene.string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 4) << r.err;
    EXPECT_NE(r.err.find("x-future"), std::string::npos);
}

TEST(Cli, ClearOnlySceneRendersThroughRef) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 3, "height": 2}, "clear": {"color": [0, 1, 0, 1]}, "draws": []})");
    const auto out = dir.path() / "o.png";
    const auto r = testutil::run_cli({"render", scene.string(), "-o", out.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto img = harness::read_color_image(out);
    ASSERT_EQ(img.color8.size(), 24u);
    for (std::size_t i = 0; i < 6; ++i) {
        EXPECT_EQ(img.color8[4 * i + 1], 255);
        EXPECT_EQ(img.color8[4 * i + 0], 0);
    }
}

TEST(Cli, OutputExtensionMustMatchTarget) {
    testutil::TempDir dir;
    const auto scene = dir.write("s.json", R"({"format": "refraster-scene/1",
      "target": {"width": 3, "height": 2, "color": "rgba32f"}, "draws": []})");
    const auto r =
        testutil::run_cli({"render", scene.string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find(".exr"), std::string::npos);
}

}  // namespace
