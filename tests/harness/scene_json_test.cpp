// Scene loading: what a valid file becomes, and how every kind of bad input is refused
// (one line naming the file and the JSON path or line:column, exit code 2, nothing written).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <random>
#include <set>

#include "harness/reduce.hpp"
#include "harness/scene.hpp"
#include "test_util.hpp"

namespace {

using harness::SceneError;
using testutil::TempDir;

// A small valid scene; malformed cases are this text with one thing broken.
std::string scene_with(const std::string& target, const std::string& draws,
                       const std::string& extra = "") {
    return R"({"format": "refraster-scene/1", "name": "t", )" + extra + R"("target": )" + target +
           R"(, "draws": )" + draws + "}";
}
const std::string kTarget = R"({"width": 8, "height": 8})";
std::string tri(const std::string& vertex0, const std::string& more = "") {
    return R"([{"primitive": "triangles", "vertices": [)" + vertex0 +
           R"(, {"position": [6, 1]}, {"position": [1, 6]}])" + more + "}]";
}

// `n` draws that draw nothing.
std::string many_draws(std::size_t n) {
    std::string d = "[";
    for (std::size_t i = 0; i < n; ++i) d += R"({"primitive": "points", "vertices": []},)";
    d.back() = ']';
    return d;
}
// `item` `n` times, comma-separated.
std::string repeated(const std::string& item, std::size_t n) {
    std::string s;
    s.reserve((item.size() + 1) * n);
    for (std::size_t i = 0; i < n; ++i) s += item + ",";
    s.pop_back();
    return s;
}
// One draw of `n` triangles, each covering the whole target (clip space).
std::string fullscreen_triangles(std::size_t n) {
    return R"([{"primitive": "triangles", "space": "clip", "vertices": [)" +
           repeated(
               R"({"position": [-1, -1, 0, 1]}, {"position": [3, -1, 0, 1]}, {"position": [-1, 3, 0, 1]})",
               n) +
           "]}]";
}

struct Malformed {
    std::string name;
    std::string text;  // file contents (ignored by the special cases below)
    std::string path;  // the JSON path the error must name; empty for line:column errors
    std::string detail;
};

// Test names print as the case name, not as the struct's bytes.
void PrintTo(const Malformed& m, std::ostream* os) {
    *os << m.name;
}

std::vector<Malformed> malformed_cases() {
    const std::string v0 = R"({"position": [1, 1]})";
    std::vector<Malformed> c = {
        {"truncated", R"({"format": "refraster-scene/1", "target": {"width": 8)", "",
         "invalid JSON"},
        {"empty_file", "", "", "invalid JSON"},
        {"trailing_garbage", scene_with(kTarget, "[]") + " x", "", "invalid JSON"},
        {"bad_utf8", "{\"format\": \"\xff\xfe\"}", "", "invalid JSON"},
        {"root_not_object", "[1, 2]", "(root)", "expected an object"},
        {"missing_format", R"({"target": {"width": 8, "height": 8}, "draws": []})", "(root)",
         "missing required key \"format\""},
        {"wrong_format",
         R"({"format": "refraster-scene/2", "target": {"width": 8, "height": 8}, "draws": []})",
         "format", "expected \"refraster-scene/1\""},
        {"missing_draws", R"({"format": "refraster-scene/1", "target": {"width": 8, "height": 8}})",
         "(root)", "missing required key \"draws\""},
        {"draws_not_array", scene_with(kTarget, R"({"primitive": "points"})"), "draws",
         "expected an array of draws"},
        {"unknown_top_key", scene_with(kTarget, "[]", R"("colour": 1, )"), "colour",
         "unknown key \"colour\""},
        {"unknown_vertex_key",
         scene_with(kTarget, tri(R"({"position": [1, 1], "normal": [0, 0, 1]})")),
         "draws[0].vertices[0].normal", "unknown key \"normal\""},
        {"duplicate_top_key",
         R"({"format": "refraster-scene/1", "format": "refraster-scene/1", "target": {"width": 8, "height": 8}, "draws": []})",
         "format", "duplicate key \"format\""},
        {"duplicate_state_key",
         scene_with(kTarget, tri(v0, R"(, "state": {"cull": "back", "cull": "front"})")),
         "draws[0].state.cull", "duplicate key \"cull\""},
        // The walk checks duplicate keys where it reads them; a duplicate takes precedence
        // over any other refusal, wherever it sits.
        {"duplicate_vertex_key",
         scene_with(kTarget, tri(R"({"position": [1, 1], "position": [2, 2]})")),
         "draws[0].vertices[0].position", "duplicate key \"position\""},
        {"duplicate_colour_after_a_bad_primitive",
         scene_with(
             kTarget,
             R"([{"primitive": "quads", "vertices": [{"position": [1, 1], "color": [1, 1, 1, 1], "color": [0, 0, 0, 1]}]}])"),
         "draws[0].vertices[0].color", "duplicate key \"color\""},
        {"duplicate_key_after_a_bad_vertex",
         scene_with(kTarget, tri(R"({"position": [1, 1], "normal": 1})"),
                    R"("clear": {"depth": 1, "depth": 0}, )"),
         "clear.depth", "duplicate key \"depth\""},
        {"duplicate_key_in_brackets_in_a_string",
         scene_with(kTarget, tri(v0, R"(, "state": {"cull": "back", "cull": "front"})"),
                    R"("description": "[{", )"),
         "draws[0].state.cull", "duplicate key \"cull\""},
        {"width_wrong_type", scene_with(R"({"width": "8", "height": 8})", "[]"), "target.width",
         "expected an integer, got the string \"8\""},
        {"width_fraction", scene_with(R"({"width": 8.5, "height": 8})", "[]"), "target.width",
         "expected an integer, got 8.5"},
        {"target_100000", scene_with(R"({"width": 100000, "height": 100000})", "[]"),
         "target.width", "expected an integer in [1, 16384], got 100000"},
        {"target_area", scene_with(R"({"width": 16384, "height": 16384, "samples": 4})", "[]"),
         "target", "exceeds the limit of 67108864"},
        {"samples_2", scene_with(R"({"width": 8, "height": 8, "samples": 2})", "[]"),
         "target.samples", "expected 1 or 4"},
        {"unknown_color_format",
         scene_with(R"({"width": 8, "height": 8, "color": "rgb565"})", "[]"), "target.color",
         "expected one of rgba8, rgba32f"},
        {"number_1e400", scene_with(kTarget, tri(R"({"position": [1e400, 1]})")),
         "draws[0].vertices[0].position[0]", "number 1e400 is out of range"},
        {"number_overflows_float32",
         scene_with(kTarget, tri(R"({"position": [1, 1], "color": [1e39, 0, 0, 1]})")),
         "draws[0].vertices[0].color[0]", "does not fit in float32"},
        {"one_coordinate", scene_with(kTarget, tri(R"({"position": [1]})")),
         "draws[0].vertices[0].position", "expected [x, y], [x, y, z] or [x, y, z, w]"},
        {"clip_three_coordinates",
         scene_with(
             kTarget,
             R"([{"primitive": "points", "space": "clip", "vertices": [{"position": [0, 0, 0]}]}])"),
         "draws[0].vertices[0].position", "expected [x, y, z, w]"},
        {"window_w_zero", scene_with(kTarget, tri(R"({"position": [1, 1, 0, 0]})")),
         "draws[0].vertices[0].position[3]", "expected w > 0 in window space"},
        {"window_w_negative", scene_with(kTarget, tri(R"({"position": [1, 1, 0, -2]})")),
         "draws[0].vertices[0].position[3]", "expected w > 0 in window space"},
        {"color_three_components",
         scene_with(kTarget, tri(R"({"position": [1, 1], "color": [1, 0, 0]})")),
         "draws[0].vertices[0].color", "expected four numbers"},
        {"index_past_count", scene_with(kTarget, tri(v0, R"(, "indices": [0, 1, 3])")),
         "draws[0].indices[2]", "expected an integer in [0, 2], got 3"},
        {"index_negative", scene_with(kTarget, tri(v0, R"(, "indices": [0, -1, 2])")),
         "draws[0].indices[1]", "expected an integer in [0, 2], got -1"},
        {"index_fraction", scene_with(kTarget, tri(v0, R"(, "indices": [0, 1.5, 2])")),
         "draws[0].indices[1]", "expected an integer, got 1.5"},
        {"unknown_primitive", scene_with(kTarget, R"([{"primitive": "quads", "vertices": []}])"),
         "draws[0].primitive", "expected one of points, lines"},
        {"matrix_with_window",
         scene_with(kTarget, tri(v0, R"(, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1])")),
         "draws[0].matrix", "allowed only with \"space\": \"clip\""},
        {"matrix_non_finite_result",
         scene_with(
             kTarget,
             R"([{"primitive": "points", "space": "clip", "matrix": [3e38,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "vertices": [{"position": [3e38, 0, 0, 1]}]}])"),
         "draws[0].vertices[0].position", "non-finite"},
        {"line_width_zero", scene_with(kTarget, tri(v0, R"(, "state": {"line_width": 0})")),
         "draws[0].state.line_width", "expected a number in (0, 255], got 0"},
        {"line_width_negative", scene_with(kTarget, tri(v0, R"(, "state": {"line_width": -0.5})")),
         "draws[0].state.line_width", "expected a number in (0, 255], got -0.5"},
        {"line_width_rounds_to_zero_in_float32",
         scene_with(kTarget, tri(v0, R"(, "state": {"line_width": 1e-50})")),
         "draws[0].state.line_width", "expected a number in (0, 255], got 1e-50"},
        {"point_size_zero", scene_with(kTarget, tri(v0, R"(, "state": {"point_size": 0})")),
         "draws[0].state.point_size", "expected a number in (0, 255], got 0"},
        {"point_size_above_255", scene_with(kTarget, tri(v0, R"(, "state": {"point_size": 256})")),
         "draws[0].state.point_size", "expected a number in (0, 255], got 256"},
        {"point_size_string", scene_with(kTarget, tri(v0, R"(, "state": {"point_size": "1"})")),
         "draws[0].state.point_size", "expected a number, got the string \"1\""},
        {"multisample_number", scene_with(kTarget, tri(v0, R"(, "state": {"multisample": 1})")),
         "draws[0].state.multisample", "expected true or false, got 1"},
        {"multisample_string",
         scene_with(kTarget, tri(v0, R"(, "state": {"multisample": "false"})")),
         "draws[0].state.multisample", "expected true or false, got the string \"false\""},
        {"multisample_null", scene_with(kTarget, tri(v0, R"(, "state": {"multisample": null})")),
         "draws[0].state.multisample", "expected true or false, got null"},
        {"requires_multisample_not_a_string", scene_with(kTarget, "[]", R"("requires": [true], )"),
         "requires[0]", "expected a string, got true"},
        {"depth_range_above_one",
         scene_with(kTarget, tri(v0, R"(, "state": {"depth_range": [0, 1.5]})")),
         "draws[0].state.depth_range[1]", "expected a number in [0, 1]"},
        {"viewport_width_zero",
         scene_with(kTarget, tri(v0, R"(, "state": {"viewport": [0, 0, 0, 8]})")),
         "draws[0].state.viewport[2]", "expected an integer in [1, 16384]"},
        {"viewport_origin_range",
         scene_with(kTarget, tri(v0, R"(, "state": {"viewport": [40000, 0, 8, 8]})")),
         "draws[0].state.viewport[0]", "expected an integer in [-32768, 32767]"},
        {"scissor_negative",
         scene_with(kTarget, tri(v0, R"(, "state": {"scissor": [0, 0, 4, -1]})")),
         "draws[0].state.scissor[3]", "expected an integer in [0, "},
        {"polygon_offset_missing_units",
         scene_with(kTarget, tri(v0, R"(, "state": {"polygon_offset": {"factor": 1}})")),
         "draws[0].state.polygon_offset", "missing required key \"units\""},
        {"depth_write_string", scene_with(kTarget, tri(v0, R"(, "state": {"depth_write": "yes"})")),
         "draws[0].state.depth_write", "expected true or false"},
        {"state_not_object", scene_with(kTarget, tri(v0, R"(, "state": [])")), "draws[0].state",
         "expected an object"},
        {"clear_depth_negative", scene_with(kTarget, "[]", R"("clear": {"depth": -0.5}, )"),
         "clear.depth", "expected a number in [0, 1]"},
        {"deep_nesting",
         scene_with(kTarget, "[]",
                    R"("description": )" + std::string(100, '[') + std::string(100, ']') + ", "),
         "", "nesting deeper than 64"},
        // Keys, paths and strings from the file are escaped: the message stays on one line.
        {"unknown_key_with_newline", scene_with(kTarget, "[]", R"("a\nb": 1, )"), R"(["a\nb"])",
         R"(unknown key "a\nb" (allowed: format, name)"},
        {"unknown_nested_key_with_tab",
         scene_with(kTarget, tri(R"({"position": [1, 1], "x\ty": 0})")),
         R"(draws[0].vertices[0]["x\ty"])", R"(unknown key "x\ty")"},
        {"duplicate_key_below_a_newline_key",
         scene_with(kTarget, "[]", R"("a\nb": {"k": 1, "k": 2}, )"), R"(["a\nb"].k)",
         R"(duplicate key "k")"},
        {"enum_with_newline",
         scene_with(kTarget, R"([{"primitive": "tri\nangles", "vertices": []}])"),
         "draws[0].primitive",
         R"(expected one of points, lines, line_strip, line_loop, triangles, triangle_strip, triangle_fan, got "tri\nangles")"},
        // Extension "polygons": its keys need "requires", and a fill rule needs one polygon
        // filled face on.
        {"polygon_without_requires",
         scene_with(kTarget, R"([{"primitive": "polygon", "vertices": []}])"), "draws[0].primitive",
         R"(the primitive "polygon" belongs to the extension "polygons"; list it in "requires")"},
        {"fill_rule_without_requires",
         scene_with(kTarget, tri(v0, R"(, "state": {"fill_rule": "evenodd"})")),
         "draws[0].state.fill_rule", R"(belongs to the extension "polygons")"},
        {"fill_rule_unknown",
         scene_with(kTarget,
                    R"([{"primitive": "polygon", "vertices": [], "state": {"fill_rule": "odd"}}])",
                    R"("requires": ["polygons"], )"),
         "draws[0].state.fill_rule", R"(expected one of evenodd, nonzero, got "odd")"},
        {"fill_rule_on_triangles",
         scene_with(kTarget, tri(v0, R"(, "state": {"fill_rule": "nonzero"})"),
                    R"("requires": ["polygons"], )"),
         "draws[0].state.fill_rule",
         R"(applies to the primitive "polygon" only, not to "triangles")"},
        {"fill_rule_with_cull",
         scene_with(
             kTarget,
             R"([{"primitive": "polygon", "vertices": [], "state": {"fill_rule": "nonzero", "cull": "back"}}])",
             R"("requires": ["polygons"], )"),
         "draws[0].state.fill_rule", R"(needs "cull": "none")"},
        {"fill_rule_with_polygon_mode",
         scene_with(
             kTarget,
             R"([{"primitive": "polygon", "vertices": [], "state": {"fill_rule": "evenodd", "polygon_mode": "line"}}])",
             R"("requires": ["polygons"], )"),
         "draws[0].state.fill_rule", R"(needs "polygon_mode": "fill")"},
        {"enum_with_control_character",
         scene_with(kTarget, tri(v0, R"(, "state": {"cull": "back\u0001\u007f"})")),
         "draws[0].state.cull", R"(got "back\u0001\u007f")"},
        {"format_with_carriage_return",
         R"({"format": "refraster-scene/1\r", "target": {"width": 8, "height": 8}, "draws": []})",
         "format", R"(got the string "refraster-scene/1\r")"},
        {"raw_newline_inside_a_string", "{\"format\": \"a\nb\"}", "", "invalid JSON"},
        {"syntax_error_after_three_hundred_digits",
         R"({"format": -1)" + std::string(300, '0') + ")}", "",
         "last read: '-1" + std::string(35, '0') + "...'"},
        {"raw_del_and_control_inside_a_key", "{\"a\x7f\x01\": 1}", "", "invalid JSON"},
        // Numbers print short, however the file spells them.
        {"line_width_1e308", scene_with(kTarget, tri(v0, R"(, "state": {"line_width": 1e308})")),
         "draws[0].state.line_width", "number 1e+308 does not fit in float32"},
        {"line_width_309_digits",
         scene_with(kTarget,
                    tri(v0, R"(, "state": {"line_width": 1)" + std::string(308, '0') + "}")),
         "draws[0].state.line_width", "number 1e+308 does not fit in float32"},
        {"line_width_400_digits",
         scene_with(kTarget,
                    tri(v0, R"(, "state": {"line_width": 1)" + std::string(399, '0') + "}")),
         "draws[0].state.line_width", "number 100000000000... (400 characters) is out of range"},
        {"line_width_above_255",
         scene_with(kTarget, tri(v0, R"(, "state": {"line_width": 255.00001})")),
         "draws[0].state.line_width", "expected a number in (0, 255], got 255.00001"},
        {"integer_1e300", scene_with(R"({"width": 1e300, "height": 8})", "[]"), "target.width",
         "expected an integer in [1, 16384], got 1e+300"},
        // Work limits (docs/limits.md), at their default values.
        {"too_many_draws", scene_with(kTarget, many_draws(4097)), "draws",
         "4097 draws exceed the limit of 4096 draws a scene"},
        {"indices_repeat_a_vertex_millions_of_times",
         scene_with(kTarget, tri(v0, R"(, "indices": [)" + repeated("0", 4'194'305) + "]")),
         "draws[0].indices", "this brings the scene to 4194305 indices, over the limit of 4194304"},
        {"estimated_fragments",
         scene_with(R"({"width": 16384, "height": 4096})", fullscreen_triangles(33)), "draws[0]",
         "estimated fragments to 2214592512, over the limit of 2147483648"},
        {"a_million_brackets", std::string(1'000'000, '['), "", "nesting deeper than 64"},
    };
    return c;
}

class MalformedScene : public ::testing::TestWithParam<Malformed> {};

TEST_P(MalformedScene, RefusedWithFileAndPath) {
    const Malformed& m = GetParam();
    TempDir dir("malformed");
    const auto file = dir.write(m.name + ".json", m.text);
    try {
        (void)harness::load_scene(file);
        FAIL() << "accepted: " << m.name;
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.file(), file.string());
        EXPECT_EQ(what.rfind(file.string() + ":", 0), 0u) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        for (const char ch : what) {
            EXPECT_FALSE(static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
                << "control character " << static_cast<int>(ch) << " in: " << what;
        }
        EXPECT_LT(what.size(), file.string().size() + 600) << what;  // short, whatever the input
        EXPECT_NE(e.detail().find(m.detail), std::string::npos) << what;
        if (m.path.empty()) {
            if (m.detail == "invalid JSON") {
                EXPECT_GE(e.line(), 1u) << what;
                EXPECT_GE(e.column(), 1u) << what;
            }
        } else {
            EXPECT_EQ(e.json_path(), m.path) << what;
            EXPECT_NE(what.find(": " + m.path + ": "), std::string::npos) << what;
        }
    }
}

// The same refusals through `refraster render`: exit 2, one line on stderr, no image.
TEST_P(MalformedScene, CliExitsTwoAndWritesNothing) {
    const Malformed& m = GetParam();
    TempDir dir("malformed-cli");
    const auto file = dir.write(m.name + ".json", m.text);
    const auto out = dir.path() / "out.png";
    const auto r = testutil::run_cli({"render", file.string(), "-o", out.string()});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(testutil::count_lines(r.err), 1u) << r.err;
    EXPECT_EQ(r.err.rfind(file.string() + ":", 0), 0u) << r.err;
    if (!m.path.empty()) {
        EXPECT_NE(r.err.find(m.path), std::string::npos) << r.err;
    }
    EXPECT_FALSE(std::filesystem::exists(out));
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()),
                            std::filesystem::directory_iterator{}),
              1);  // only the scene file itself
}

INSTANTIATE_TEST_SUITE_P(All, MalformedScene, ::testing::ValuesIn(malformed_cases()),
                         [](const auto& p) { return p.param.name; });

TEST(SceneFiles, SyntaxErrorNamesLineAndColumn) {
    TempDir dir;
    const auto file = dir.write(
        "s.json", "{\n  \"format\": \"refraster-scene/1\",\n  \"target\": {\"width\": 8,,}\n}");
    try {
        (void)harness::load_scene(file);
        FAIL();
    } catch (const SceneError& e) {
        EXPECT_EQ(e.line(), 3u) << e.what();
        EXPECT_EQ(e.column(), 25u) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind(file.string() + ":3:25: invalid JSON", 0), 0u)
            << e.what();
    }
}

TEST(SceneFiles, MissingFile) {
    TempDir dir;
    const auto file = dir.path() / "absent.json";
    const auto r =
        testutil::run_cli({"render", file.string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, file.string() + ": cannot open: no such file\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "o.png"));
}

TEST(SceneFiles, Directory) {
    TempDir dir;
    const auto r =
        testutil::run_cli({"render", dir.path().string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, dir.path().string() + ": is a directory, expected a scene file\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "o.png"));
}

TEST(SceneFiles, FiftyMegabytesOfRandomBytes) {
    TempDir dir;
    std::string bytes(50u << 20, '\0');
    std::mt19937_64 rng(12345);
    for (std::size_t i = 0; i < bytes.size(); i += 8) {
        const auto v = rng();
        for (std::size_t k = 0; k < 8; ++k) bytes[i + k] = static_cast<char>(v >> (8 * k));
    }
    bytes[0] = 'q';  // not a valid JSON start whatever the generator gives
    const auto file = dir.write("random.bin", bytes);
    const auto r =
        testutil::run_cli({"render", file.string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err.rfind(file.string() + ":1:1: invalid JSON", 0), 0u) << r.err;
    EXPECT_EQ(testutil::count_lines(r.err), 1u);
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "o.png"));
}

TEST(SceneFiles, ValidSceneValuesAndDefaults) {
    const std::string text = R"({
      "format": "refraster-scene/1", "name": "a/b", "description": "d",
      "target": {"width": 16.0, "height": 8, "color": "rgba32f", "depth": "z16"},
      "clear": {"color": [0.1, 0, 0, 1]},
      "expect": {"color_tolerance": 2, "max_mismatched_pixels": 3},
      "draws": [
        {"primitive": "triangle_fan", "vertices": [{"position": [1, 2]}, {"position": [3, 4, 0.5]},
          {"position": [5, 6, 0.25, 2], "color": [0, 0.5, 1, 0]}], "indices": [2, 1.0, 0],
         "state": {"cull": "front_and_back", "depth_test": "gequal", "shade": "flat",
                   "provoking_vertex": "first", "polygon_offset": {"factor": 1.5, "units": -2},
                   "blend": "add", "scissor": [1, 2, 0, 4], "line_width": 2.5}},
        {"primitive": "points", "space": "clip", "vertices": [],
         "state": {"depth_test": null, "blend": null, "scissor": null, "polygon_offset": null}}
      ]})";
    const auto s = harness::load_scene_text(text, "mem.json");
    EXPECT_EQ(s.file.name, "a/b");
    EXPECT_EQ(s.file.target.width, 16u);
    EXPECT_EQ(s.file.target.color, refraster::ColorFormat::Rgba32f);
    EXPECT_EQ(s.file.target.depth, refraster::DepthFormat::Z16);
    EXPECT_EQ(s.file.target.samples, 1u);
    EXPECT_EQ(s.file.clear.color[0], 0.1f);  // rounded once to float32
    EXPECT_EQ(s.file.clear.depth, 1.0f);
    EXPECT_EQ(s.file.expect.color_tolerance, 2u);
    EXPECT_EQ(s.file.expect.max_mismatched_pixels, 3u);
    ASSERT_EQ(s.file.draws.size(), 2u);
    const auto& d = s.file.draws[0];
    EXPECT_EQ(d.primitive, refraster::PrimitiveType::TriangleFan);
    EXPECT_EQ(d.vertices[0].position_size, 2u);
    EXPECT_EQ(d.vertices[2].position[3], 2.0f);
    EXPECT_EQ(d.vertices[0].color, (std::array<float, 4>{1, 1, 1, 1}));
    EXPECT_EQ(*d.indices, (std::vector<std::uint32_t>{2, 1, 0}));
    EXPECT_EQ(d.state.viewport, (refraster::Rect{0, 0, 16, 8}));
    EXPECT_EQ(d.state.cull, refraster::CullMode::FrontAndBack);
    EXPECT_EQ(d.state.depth_test, refraster::CompareFunc::Gequal);
    EXPECT_EQ(d.state.shade, refraster::ShadeModel::Flat);
    EXPECT_EQ(d.state.provoking_vertex, refraster::ProvokingVertex::First);
    EXPECT_EQ(d.state.polygon_offset, (refraster::PolygonOffset{1.5f, -2.0f}));
    EXPECT_EQ(d.state.blend, refraster::BlendPreset::Add);
    EXPECT_EQ(d.state.scissor, (refraster::Rect{1, 2, 0, 4}));
    EXPECT_EQ(d.state.line_width, 2.5f);
    const auto& e = s.file.draws[1];
    EXPECT_EQ(e.space, harness::VertexSpace::Clip);
    EXPECT_FALSE(e.state.depth_test.has_value());
    EXPECT_FALSE(e.state.scissor.has_value());
    EXPECT_EQ(e.state.viewport, (refraster::Rect{0, 0, 16, 8}));
    EXPECT_TRUE(s.unsupported_extensions.empty());
}

TEST(SceneFiles, UnknownRequiredExtensionIsNotSupportedNotAnError) {
    const auto s = harness::load_scene_text(
        scene_with(kTarget, "[]", R"("requires": ["cube_maps"], )"), "mem.json");
    EXPECT_EQ(s.unsupported_extensions, (std::vector<std::string>{"cube_maps"}));
}

// "multisample" is implemented: listing it leaves the scene supported, and only the other
// names stay unsupported.
TEST(SceneFiles, MultisampleExtensionIsKnown) {
    auto s = harness::load_scene_text(scene_with(kTarget, "[]", R"("requires": ["multisample"], )"),
                                      "mem.json");
    EXPECT_EQ(s.file.requires_extensions, (std::vector<std::string>{"multisample"}));
    EXPECT_TRUE(s.unsupported_extensions.empty());
    s = harness::load_scene_text(
        scene_with(kTarget, "[]", R"("requires": ["cube_maps", "multisample", "Multisample"], )"),
        "mem.json");
    EXPECT_EQ(s.unsupported_extensions, (std::vector<std::string>{"cube_maps", "Multisample"}));
}

// reduce writes a scene the loader reads back the same: "multisample": false is kept, the
// default is left out, and thin widths survive.
TEST(SceneFiles, SceneToJsonKeepsMultisampleAndThinWidths) {
    const std::string text = scene_with(R"({"width": 8, "height": 8, "samples": 4})",
                                        R"([{"primitive": "lines", "vertices": [],
          "state": {"multisample": false, "line_width": 0.5}},
         {"primitive": "points", "vertices": [], "state": {"point_size": 0.7}}])",
                                        R"("requires": ["multisample"], )");
    const auto first = harness::parse_scene(text, "mem.json");
    const std::string written = harness::scene_to_json(first);
    const auto j = nlohmann::json::parse(written);
    EXPECT_EQ(j["draws"][0]["state"]["multisample"], false);
    EXPECT_EQ(j["draws"][0]["state"]["line_width"], 0.5);
    EXPECT_FALSE(j["draws"][1]["state"].contains("multisample"));
    EXPECT_EQ(j["requires"], nlohmann::json::array({"multisample"}));
    const auto again = harness::parse_scene(written, "again.json");
    ASSERT_EQ(again.draws.size(), 2u);
    EXPECT_EQ(again.draws[0].state, first.draws[0].state);
    EXPECT_EQ(again.draws[1].state, first.draws[1].state);
    EXPECT_EQ(again.draws[1].state.point_size, 0.7f);
}

// The draw state key "multisample" (default true), allowed without "requires", reaches the
// draw list; widths and sizes below 1 load as written.
TEST(SceneFiles, MultisampleStateAndThinLinesAndSmallPoints) {
    const std::string text = scene_with(R"({"width": 8, "height": 8, "samples": 4})",
                                        R"([{"primitive": "lines", "vertices": [],
          "state": {"multisample": false, "line_width": 0.5}},
         {"primitive": "points", "vertices": [], "state": {"multisample": true, "point_size": 0.7}},
         {"primitive": "points", "vertices": []}])");
    const auto s = harness::load_scene_text(text, "mem.json");
    ASSERT_EQ(s.draw_list.draws.size(), 3u);
    EXPECT_FALSE(s.file.draws[0].state.multisample);
    EXPECT_FALSE(s.draw_list.draws[0].state.multisample);
    EXPECT_EQ(s.draw_list.draws[0].state.line_width, 0.5f);
    EXPECT_TRUE(s.draw_list.draws[1].state.multisample);
    EXPECT_EQ(s.draw_list.draws[1].state.point_size, 0.7f);
    EXPECT_TRUE(s.draw_list.draws[2].state.multisample);
    EXPECT_EQ(s.draw_list.draws[2].state.line_width, 1.0f);
    EXPECT_TRUE(s.unsupported_extensions.empty());
    // The smallest positive float32 and 255 itself are inside the range.
    EXPECT_EQ(harness::load_scene_text(scene_with(kTarget, R"([{"primitive": "points",
          "vertices": [], "state": {"point_size": 1.4e-45, "line_width": 255}}])"),
                                       "mem.json")
                  .draw_list.draws[0]
                  .state.line_width,
              255.0f);
}

// A file name with a newline in it still gives a one-line message.
TEST(SceneMessages, FileLabelIsEscaped) {
    try {
        (void)harness::load_scene_text("{", "dir/a\nb.json");
        FAIL();
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind("dir/a\\nb.json:1:", 0), 0u) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_EQ(e.file(), "dir/a\nb.json");  // the label itself is kept as given
    }
}

// The number in a range message is the short form, not hundreds of digits.
TEST(SceneMessages, HugeNumbersPrintShort) {
    const std::string v0 = R"({"position": [1, 1]})";
    for (const std::string& width :
         {std::string("1e308"), "1" + std::string(308, '0'), "-1" + std::string(308, '0') + ".5"}) {
        try {
            (void)harness::load_scene_text(
                scene_with(kTarget, tri(v0, R"(, "state": {"line_width": )" + width + "}")),
                "huge.json");
            FAIL() << width;
        } catch (const SceneError& e) {
            const std::string what = e.what();
            EXPECT_EQ(what.rfind("huge.json: draws[0].state.line_width: number ", 0), 0u) << what;
            EXPECT_NE(what.find("e+308 does not fit in float32"), std::string::npos) << what;
            EXPECT_EQ(what.find("0000"), std::string::npos) << what;
            EXPECT_LT(what.size(), 100u) << what;
        }
    }
}

// The limits docs/limits.md documents.
TEST(SceneLimits, DefaultsAreTheDocumentedOnes) {
    const harness::SceneLimits l;
    EXPECT_EQ(l.max_file_bytes, 1'073'741'824u);
    EXPECT_EQ(l.max_nesting_depth, 64u);
    EXPECT_EQ(l.max_json_values, 67'108'864u);
    EXPECT_EQ(l.max_target_pixels, 67'108'864u);
    EXPECT_EQ(l.max_draws, 4'096u);
    EXPECT_EQ(l.max_vertices, 4'194'304u);
    EXPECT_EQ(l.max_indices, 4'194'304u);
    EXPECT_EQ(l.max_primitives, 4'194'304u);
    EXPECT_EQ(l.max_fragments, 2'147'483'648u);
    // Texture files (docs/limits.md, "Texture files"): 128 MiB, and no root beyond the scene's
    // own folder.
    EXPECT_EQ(l.max_texture_file_bytes, 134'217'728u);
    EXPECT_TRUE(l.texture_root.empty());
}

// Each limit refuses one past it with one line naming the file and the JSON path, and accepts
// what reaches it exactly. Lowered limits keep the texts small; the code path is the same.
struct LimitCase {
    std::string name;
    harness::SceneLimits limits;
    std::string at_limit;    // accepted
    std::string past_limit;  // refused
    std::string path;
    std::string detail;
};
void PrintTo(const LimitCase& c, std::ostream* os) {
    *os << c.name;
}

harness::SceneLimits with(std::uint64_t harness::SceneLimits::*field, std::uint64_t value) {
    harness::SceneLimits l;
    l.*field = value;
    return l;
}

std::vector<LimitCase> limit_cases() {
    using L = harness::SceneLimits;
    const std::string v = R"({"position": [1, 1]})";
    const auto points = [&](std::size_t n) {
        return R"([{"primitive": "points", "vertices": [)" + repeated(v, n) + "]}]";
    };
    const auto indexed = [&](std::size_t n) {
        return R"([{"primitive": "points", "vertices": [)" + v + R"(], "indices": [)" +
               repeated("0", n) + "]}]";
    };
    // Two draws, so that the refusal names the draw whose count crosses the limit.
    const auto two_draws = [&](const std::string& first, const std::string& second) {
        return "[" + first.substr(1, first.size() - 2) + ", " +
               second.substr(1, second.size() - 2) + "]";
    };
    harness::SceneLimits depth;
    depth.max_nesting_depth = 4;
    harness::SceneLimits depth3;
    depth3.max_nesting_depth = 3;
    return {
        {"file_bytes", with(&L::max_file_bytes, 200), scene_with(kTarget, "[]"),
         scene_with(kTarget, "[]") + std::string(200, ' '), "",
         "bytes exceeds the scene size limit of 200"},
        {"nesting", depth,
         scene_with(kTarget, R"([{"primitive": "points", "vertices": [], "state": {}}])"),
         scene_with(
             kTarget,
             R"([{"primitive": "points", "vertices": [], "state": {"polygon_offset": {"factor": 1, "units": 1}}}])"),
         "draws[0].state.polygon_offset", "nesting deeper than 4 levels"},
        // The root, format, name, target, width, height and draws: 7 values; with a
        // description, the draws are the eighth.
        // An empty array one level too deep, which simdjson's own depth check lets through.
        {"nesting_of_an_empty_array", depth3, scene_with(kTarget, "[]"),
         scene_with(kTarget, R"([{"primitive": "points", "vertices": []}])"), "draws[0].vertices",
         "nesting deeper than 3 levels"},
        {"json_values", with(&L::max_json_values, 7), scene_with(kTarget, "[]"),
         scene_with(kTarget, "[]", R"("description": "d", )"), "draws", "more than 7 JSON values"},
        {"target_pixels", with(&L::max_target_pixels, 64), scene_with(kTarget, "[]"),
         scene_with(R"({"width": 8, "height": 9})", "[]"), "target", "exceeds the limit of 64"},
        {"draws", with(&L::max_draws, 3), scene_with(kTarget, many_draws(3)),
         scene_with(kTarget, many_draws(4)), "draws", "4 draws exceed the limit of 3"},
        {"vertices", with(&L::max_vertices, 5),
         scene_with(kTarget, two_draws(points(2), points(3))),
         scene_with(kTarget, two_draws(points(2), points(4))), "draws[1].vertices",
         "this brings the scene to 6 vertices, over the limit of 5"},
        {"indices", with(&L::max_indices, 5),
         scene_with(kTarget, two_draws(indexed(2), indexed(3))),
         scene_with(kTarget, two_draws(indexed(2), indexed(4))), "draws[1].indices",
         "this brings the scene to 6 indices, over the limit of 5"},
        // Repeated indices make primitives out of one vertex.
        {"primitives", with(&L::max_primitives, 5),
         scene_with(kTarget, two_draws(indexed(3), points(2))),
         scene_with(kTarget, two_draws(indexed(3), points(3))), "draws[1]",
         "this brings the scene to 6 primitives, over the limit of 5"},
        // 8x8 target: each point of size 1 counts 3x3 pixels (a pixel of margin each side).
        {"fragments", with(&L::max_fragments, 45), scene_with(kTarget, points(5)),
         scene_with(kTarget, two_draws(points(5), points(1))), "draws[1]",
         "estimated fragments to 54, over the limit of 45"},
    };
}

class SceneLimit : public ::testing::TestWithParam<LimitCase> {};

TEST_P(SceneLimit, RefusesPastTheLimitOnly) {
    const LimitCase& c = GetParam();
    EXPECT_NO_THROW((void)harness::load_scene_text(c.at_limit, "limit.json", c.limits));
    EXPECT_NO_THROW((void)harness::load_scene_text(c.past_limit, "limit.json"))
        << "the default limits accept it";
    try {
        (void)harness::load_scene_text(c.past_limit, "limit.json", c.limits);
        FAIL() << "accepted: " << c.name;
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        EXPECT_EQ(what.rfind("limit.json: ", 0), 0u) << what;
        EXPECT_EQ(e.json_path(), c.path) << what;
        EXPECT_NE(e.detail().find(c.detail), std::string::npos) << what;
    }
}

INSTANTIATE_TEST_SUITE_P(All, SceneLimit, ::testing::ValuesIn(limit_cases()),
                         [](const auto& p) { return p.param.name; });

// What the estimate counts, against hand-computed boxes.
TEST(SceneWork, EstimatesBoundingBoxesClippedToTheRegion) {
    const auto work = [](const std::string& target, const std::string& draws) {
        const auto s = harness::load_scene_text(scene_with(target, draws), "w.json");
        return harness::estimate_work(s.draw_list);
    };
    const std::string big = R"({"width": 1024, "height": 1024})";
    const std::string v0 = R"({"position": [2, 2]})";
    // tri(): (2, 2) (6, 1) (1, 6); its box [1, 6] x [1, 6] with a pixel of margin is 7 x 7.
    EXPECT_EQ(work(big, tri(v0)).fragments, 49u);
    EXPECT_EQ(work(big, tri(v0)).primitives, 1u);
    EXPECT_EQ(work(big, tri(v0, R"(, "state": {"scissor": [0, 0, 4, 3]})")).fragments, 12u);
    EXPECT_EQ(work(big, tri(v0, R"(, "state": {"scissor": [0, 0, 0, 3]})")).fragments, 0u);
    // 4x: every sample counts, and the scissor's region reaches a pixel further left and down
    // (its multisample leak): scissor [2, 2, 4, 3] becomes [1, 1] to [5, 4], 5 x 4 pixels.
    const std::string big4 = R"({"width": 1024, "height": 1024, "samples": 4})";
    EXPECT_EQ(work(big4, tri(v0)).fragments, 4u * 49u);
    EXPECT_EQ(work(big4, tri(v0, R"(, "state": {"scissor": [2, 2, 4, 3]})")).fragments, 4u * 20u);
    // Polygon mode point: three corners of 4 x 4 (a pixel and a margin each side), two of them
    // cut by the target's edge: 16 + 12 + 12.
    EXPECT_EQ(work(big, tri(v0, R"(, "state": {"polygon_mode": "point"})")).fragments, 40u);
    // A point of size 255: 129 pixels each side of its centre, cut by the target's edge.
    const auto point = [](const std::string& at) {
        return R"([{"primitive": "points", "vertices": [{"position": )" + at +
               R"(}], "state": {"point_size": 255}}])";
    };
    EXPECT_EQ(work(big, point("[512, 512]")).fragments, 258u * 258u);
    EXPECT_EQ(work(big, point("[0, 0]")).fragments, 129u * 129u);
    // A long diagonal line counts its length times its width, not its box.
    const auto diagonal = work(
        big,
        R"([{"primitive": "lines", "vertices": [{"position": [0, 0.5]}, {"position": [1024, 1024]}]}])");
    EXPECT_GT(diagonal.fragments, 5'800u);
    EXPECT_LT(diagonal.fragments, 5'810u);
    // A vertex behind the eye (w <= 0) has no window position: the whole target counts.
    EXPECT_EQ(
        work(
            big,
            R"([{"primitive": "triangles", "space": "clip", "vertices": [{"position": [0, 0, 0, 1]}, {"position": [1, 0, 0, 1]}, {"position": [0, 1, 0, -1]}]}])")
            .fragments,
        1024u * 1024u);
}

// The limits change no shipped scene: each stays below a tenth of every one of them (the
// extreme scenes included, which reach the largest targets the format allows).
TEST(SceneLimits, ShippedScenesStayFarBelow) {
    const harness::SceneLimits l;
    int n = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(
             std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes")) {
        if (e.path().extension() != ".json") continue;
        const auto s = harness::load_scene(e.path());
        const auto w = harness::estimate_work(s.draw_list);
        std::uint64_t vertices = 0;
        std::uint64_t indices = 0;
        for (const auto& d : s.draw_list.draws) {
            vertices += d.vertices.size();
            indices += d.indices ? d.indices->size() : 0;
        }
        EXPECT_LE(s.draw_list.draws.size() * 10, l.max_draws) << e.path();
        EXPECT_LE(vertices * 10, l.max_vertices) << e.path();
        EXPECT_LE(indices * 10, l.max_indices) << e.path();
        EXPECT_LE(w.primitives * 10, l.max_primitives) << e.path();
        EXPECT_LE(w.fragments * 10, l.max_fragments) << e.path();
        ++n;
    }
    EXPECT_GT(n, 100);
}

// The fuzzers' dictionary holds every key and enum string of the published schema, quoted as
// in a file, so that it keeps up with the format.
void collect_words(const nlohmann::json& schema, std::set<std::string>& words) {
    if (schema.is_object()) {
        if (schema.contains("properties")) {
            for (const auto& [k, _] : schema["properties"].items()) words.insert(k);
        }
        for (const char* key : {"enum", "const"}) {
            if (!schema.contains(key)) continue;
            const auto& v = schema[key];
            for (const auto& e : v.is_array() ? v : nlohmann::json::array({v})) {
                if (e.is_string()) words.insert(e.get<std::string>());
            }
        }
        for (const auto& [_, child] : schema.items()) collect_words(child, words);
    } else if (schema.is_array()) {
        for (const auto& child : schema) collect_words(child, words);
    }
}

TEST(FuzzDictionary, HoldsEveryKeyAndEnumStringOfTheSchema) {
    const std::filesystem::path source = REFRASTER_SOURCE_DIR;
    std::set<std::string> words;
    collect_words(
        nlohmann::json::parse(testutil::read_text(source / "conformance/schema/scene.schema.json")),
        words);
    const std::string dict = testutil::read_text(source / "fuzz/scene.dict");
    EXPECT_GT(words.size(), 60u);
    for (const auto& w : words) {
        EXPECT_NE(dict.find("\"\\\"" + w + "\\\"\"\n"), std::string::npos) << w;
    }
}

}  // namespace

namespace {

// A shared-edge scene whose name ends in _ccw or _cw draws its triangles with that winding in
// window space, y up, as its name and description say (the _ccw ones were once copies of the
// _cw ones). In the cull scenes the suffix names glFrontFace, not the winding.
TEST(SceneFiles, WindingInANameIsTheTrianglesWinding) {
    int checked = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(
             std::filesystem::path(REFRASTER_SOURCE_DIR) / "conformance/scenes")) {
        if (e.path().extension() != ".json") continue;
        const std::string stem = e.path().stem().string();
        if (stem.rfind("shared_edge_", 0) != 0) continue;
        const bool ccw = stem.size() > 4 && stem.substr(stem.size() - 4) == "_ccw";
        const bool cw = !ccw && stem.size() > 3 && stem.substr(stem.size() - 3) == "_cw";
        if (!ccw && !cw) continue;
        const auto s = harness::load_scene(e.path());
        for (const auto& d : s.draw_list.draws) {
            if (d.primitive != refraster::PrimitiveType::Triangles || d.indices) continue;
            const std::size_t stride = d.vertices.stride();
            const auto at = [&](std::size_t v) {
                const float* p = d.vertices.data.data() + v * stride;
                return std::array<double, 2>{double{p[0]} / double{p[3]},
                                             double{p[1]} / double{p[3]}};
            };
            for (std::size_t v = 0; v + 2 < d.vertices.size(); v += 3) {
                const auto a = at(v), b = at(v + 1), c = at(v + 2);
                const double area = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
                EXPECT_EQ(area > 0, ccw) << e.path() << " triangle " << v / 3;
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 24);
}

}  // namespace
