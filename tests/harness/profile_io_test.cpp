// Profiles as files and overrides: what `refraster profile` prints loads back to the same
// profile; unknown keys and values are refused naming the file and the key.
#include <gtest/gtest.h>

#include "harness/profile_io.hpp"
#include "test_util.hpp"

namespace {

TEST(ProfileIo, SavedProfileLoadsBackEqual) {
    testutil::TempDir dir;
    for (const auto& name : refraster::builtin_profile_names()) {
        auto p = refraster::builtin_profile(name);
        harness::apply_profile_overrides(p, {"tie_rule=right-top", "viewport_fma=off", "subpixel_bits=4",
                                             "snap_rounding=half-away", "pixel_center_offset=0.25"});
        const auto file = dir.write(name + ".json", harness::profile_to_json(p));
        EXPECT_EQ(harness::load_profile(file.string()), p) << name;
    }
}

TEST(ProfileIo, BuiltinsDiffer) {
    EXPECT_EQ(harness::load_profile("llvmpipe-22.3").coverage, refraster::CoverageModel::Snapped);
    EXPECT_EQ(harness::load_profile("gl-exact").coverage, refraster::CoverageModel::Exact);
}

TEST(ProfileIo, BadInputNamesFileAndKey) {
    testutil::TempDir dir;
    const auto f = dir.write("p.json", R"({"tie_rule": "upside-down"})");
    try {
        (void)harness::load_profile(f.string());
        FAIL();
    } catch (const refraster::ProfileError& e) {
        EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("tie_rule=upside-down"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("left-bottom"), std::string::npos) << e.what();
    }
    EXPECT_THROW(harness::load_profile(dir.write("q.json", R"({"tie": "left-bottom"})").string()), refraster::ProfileError);
    EXPECT_THROW(harness::load_profile(dir.write("r.json", "[1]").string()), refraster::ProfileError);
    EXPECT_THROW(harness::load_profile("no-such-profile"), refraster::ProfileError);
    refraster::Profile p;
    EXPECT_THROW(harness::apply_profile_overrides(p, {"subpixel_bits=9"}), refraster::ProfileError);
    EXPECT_THROW(harness::apply_profile_overrides(p, {"novalue"}), refraster::ProfileError);
}

TEST(ProfileIo, CliRecordsProfileAndOverrides) {
    testutil::TempDir dir;
    const auto json = dir.path() / "r.json";
    const auto r = testutil::run_cli({"compare", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
                                      "--against", "ref", "--profile-set", "tie_rule=right-top", "--json", json.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto text = testutil::read_text(json);
    EXPECT_NE(text.find("\"profile\":\"llvmpipe-22.3\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"profile_overrides\":\"tie_rule=right-top\""), std::string::npos) << text;
    const auto bad = testutil::run_cli({"render", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
                                        "--profile-set", "tie_rule=sideways", "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_EQ(testutil::count_lines(bad.err), 1u);
}

}  // namespace
