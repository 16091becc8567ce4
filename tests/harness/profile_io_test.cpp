// Profiles as files and overrides: what `refraster profile` prints loads back to the same
// profile; unknown keys and values are refused naming the file and the key.
#include "harness/profile_io.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"

namespace {

TEST(ProfileIo, SavedProfileLoadsBackEqual) {
    testutil::TempDir dir;
    for (const auto& name : refraster::builtin_profile_names()) {
        auto p = refraster::builtin_profile(name);
        for (const auto& [k, v] :
             std::vector<std::pair<std::string, std::string>>{{"tie_rule", "right-top"},
                                                              {"viewport_fma", "off"},
                                                              {"subpixel_bits", "4"},
                                                              {"snap_rounding", "half-away"},
                                                              {"pixel_center_offset", "0.25"}})
            refraster::set_profile_parameter(p, k, v);
        harness::name_by_rules(p);
        const auto file = dir.write(name + ".json", harness::profile_to_json(p));
        EXPECT_EQ(harness::load_profile(file.string()), p) << name;
    }
}

TEST(ProfileIo, BuiltinsDiffer) {
    EXPECT_EQ(harness::load_profile("llvmpipe-22.3").model, refraster::CoverageModel::Snapped);
    EXPECT_EQ(harness::load_profile("gl-exact").model, refraster::CoverageModel::Exact);
}

TEST(ProfileIo, BadInputNamesFileAndKey) {
    testutil::TempDir dir;
    const auto f = dir.write("p.json", R"({"tie_rule": "upside-down"})");
    try {
        (void)harness::load_profile(f.string());
        FAIL();
    } catch (const refraster::ProfileError& e) {
        EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("tie_rule=upside-down"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("left-bottom"), std::string::npos) << e.what();
    }
    EXPECT_THROW(harness::load_profile(dir.write("q.json", R"({"tie": "left-bottom"})").string()),
                 refraster::ProfileError);
    EXPECT_THROW(harness::load_profile(dir.write("r.json", "[1]").string()),
                 refraster::ProfileError);
    EXPECT_THROW(harness::load_profile("no-such-profile"), refraster::ProfileError);
    refraster::Profile p;
    EXPECT_THROW(harness::apply_profile_overrides(p, {"subpixel_bits=9"}), refraster::ProfileError);
    EXPECT_THROW(harness::apply_profile_overrides(p, {"novalue"}), refraster::ProfileError);
}

// An override the profile's model does not read would rename the profile and change no pixel:
// refused, naming the override and why; the same key is accepted where a route reads it.
TEST(ProfileIo, OverridesTheModelDoesNotReadAreRefused) {
    const auto refused = [](const std::string& profile, std::vector<std::string> overrides) {
        auto p = refraster::builtin_profile(profile);
        try {
            harness::apply_profile_overrides(p, overrides);
        } catch (const refraster::ProfileError& e) {
            EXPECT_NE(std::string(e.what()).find(overrides.front()), std::string::npos) << e.what();
            return true;
        }
        return false;
    };
    for (const char* o :
         {"tie_rule=left-top", "subpixel_bits=4", "snap_rounding=half-away",
          "pixel_center_offset=0.25", "nine_vertex_quirk=false", "wrapping_arithmetic=false"})
        EXPECT_TRUE(refused("softpipe-22.3", {o})) << o;
    // Lines drawn by llvmpipe's rules read the snapped keys under the scanline model too.
    EXPECT_FALSE(refused("softpipe-22.3", {"tie_rule=left-top", "line_rule=parallelogram"}));
    EXPECT_FALSE(refused("softpipe-22.3", {"depth_rounding=truncate"}));
    for (const char* o : {"subpixel_bits=4", "clipping=guard-band", "line_rule=bresenham",
                          "tie_rule=none", "color_rounding=truncate"})
        EXPECT_TRUE(refused("gl-exact", {o})) << o;
    EXPECT_FALSE(refused("gl-exact", {"tie_rule=right-top"}));
    EXPECT_TRUE(refused("llvmpipe-22.3", {"fill_clear_writes_tiles=false"}));
    EXPECT_TRUE(refused("llvmpipe-22.3", {"wrapping_arithmetic=false", "subpixel_bits=4"}));
    for (const char* o : {"tie_rule=left-top", "subpixel_bits=4", "snap_rounding=half-away",
                          "clipping=guard-band", "line_rule=bresenham", "tie_rule=none"})
        EXPECT_FALSE(refused("llvmpipe-22.3", {o})) << o;
}

TEST(ProfileIo, CliRecordsProfileAndOverrides) {
    testutil::TempDir dir;
    const auto json = dir.path() / "r.json";
    const auto r = testutil::run_cli(
        {"compare", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
         "--against", "ref", "--profile-set", "tie_rule=right-top", "--json", json.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const auto text = testutil::read_text(json);
    // The result says which rules ran: not the built-in's name alone.
    EXPECT_EQ(text.find("\"profile\":\"llvmpipe-22.3\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"profile\":\"llvmpipe-22.3+tie_rule=right-top\""), std::string::npos)
        << text;
    EXPECT_NE(text.find("\"profile_overrides\":\"tie_rule=right-top\""), std::string::npos) << text;
    EXPECT_NE(text.find("\"profile_source\":\"built-in\""), std::string::npos) << text;
    EXPECT_NE(text.find("tie_rule=right-top;clipping="), std::string::npos)
        << text;  // profile_rules, every rule
    const auto bad = testutil::run_cli(
        {"render", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
         "--profile-set", "tie_rule=sideways", "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_EQ(testutil::count_lines(bad.err), 1u);
}

TEST(ProfileIo, DerivedProfileIsNotNamedAsItsBuiltIn) {
    // `refraster profile --profile-set` writes a profile named by what it changed, and a file
    // that claims a built-in's name with other rules is renamed the same way when loaded.
    testutil::TempDir dir;
    const auto r = testutil::run_cli(
        {"profile", "--profile-set", "tie_rule=right-top", "--profile-set", "subpixel_bits=4"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("\"name\": \"llvmpipe-22.3+subpixel_bits=4,tie_rule=right-top\""),
              std::string::npos)
        << r.out;
    const auto file = dir.write("p.json", r.out);
    EXPECT_EQ(harness::load_profile(file.string()).name,
              "llvmpipe-22.3+subpixel_bits=4,tie_rule=right-top");
    const auto claims =
        dir.write("c.json", R"({"name": "llvmpipe-22.3", "snap_rounding": "truncate"})");
    EXPECT_EQ(harness::load_profile(claims.string()).name, "llvmpipe-22.3+snap_rounding=truncate");
    const auto same =
        dir.write("s.json", R"({"name": "llvmpipe-22.3", "tie_rule": "left-bottom"})");
    EXPECT_EQ(harness::load_profile(same.string()).name,
              "llvmpipe-22.3");  // the built-in's rules: its name
    const auto own = dir.write("o.json", R"({"name": "my-driver", "tie_rule": "right-top"})");
    EXPECT_EQ(harness::load_profile(own.string()).name, "my-driver");
    // Recorded with its file, and shown in explain's header.
    const auto json = dir.path() / "r.json";
    const auto c = testutil::run_cli(
        {"compare", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
         "--against", "ref", "--profile", claims.string(), "--json", json.string()});
    EXPECT_EQ(c.exit_code, 0) << c.err;
    const auto text = testutil::read_text(json);
    EXPECT_NE(text.find("\"profile_source\":\"" + claims.string() + "\""), std::string::npos)
        << text;
    EXPECT_NE(text.find("\"profile\":\"llvmpipe-22.3+snap_rounding=truncate\""), std::string::npos)
        << text;
    const auto x = testutil::run_cli(
        {"explain", std::string(REFRASTER_SOURCE_DIR) + "/conformance/scenes/smoke/triangles.json",
         "--pixel", "3,2", "--no-backend", "--profile", claims.string()});
    EXPECT_EQ(x.exit_code, 0) << x.err;
    EXPECT_NE(x.out.find("profile llvmpipe-22.3+snap_rounding=truncate\nrules: "
                         "coverage=snapped;subpixel_bits=8;snap_rounding=truncate"),
              std::string::npos)
        << x.out;
}

}  // namespace
