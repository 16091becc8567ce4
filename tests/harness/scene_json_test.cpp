// Scene loading: what a valid file becomes, and how every kind of bad input is refused
// (one line naming the file and the JSON path or line:column, exit code 2, nothing written).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

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

struct Malformed {
    std::string name;
    std::string text;  // file contents (ignored by the special cases below)
    std::string path;  // the JSON path the error must name; empty for line:column errors
    std::string detail;
};

// Test names print as the case name, not as the struct's bytes.
void PrintTo(const Malformed& m, std::ostream* os) { *os << m.name; }

std::vector<Malformed> malformed_cases() {
    const std::string v0 = R"({"position": [1, 1]})";
    std::vector<Malformed> c = {
        {"truncated", R"({"format": "refraster-scene/1", "target": {"width": 8)", "", "invalid JSON"},
        {"empty_file", "", "", "invalid JSON"},
        {"trailing_garbage", scene_with(kTarget, "[]") + " x", "", "invalid JSON"},
        {"bad_utf8", "{\"format\": \"\xff\xfe\"}", "", "invalid JSON"},
        {"root_not_object", "[1, 2]", "(root)", "expected an object"},
        {"missing_format", R"({"target": {"width": 8, "height": 8}, "draws": []})", "(root)",
         "missing required key \"format\""},
        {"wrong_format", R"({"format": "refraster-scene/2", "target": {"width": 8, "height": 8}, "draws": []})",
         "format", "expected \"refraster-scene/1\""},
        {"missing_draws", R"({"format": "refraster-scene/1", "target": {"width": 8, "height": 8}})",
         "(root)", "missing required key \"draws\""},
        {"draws_not_array", scene_with(kTarget, R"({"primitive": "points"})"), "draws",
         "expected an array of draws"},
        {"unknown_top_key", scene_with(kTarget, "[]", R"("colour": 1, )"), "colour",
         "unknown key \"colour\""},
        {"unknown_vertex_key", scene_with(kTarget, tri(R"({"position": [1, 1], "normal": [0, 0, 1]})")),
         "draws[0].vertices[0].normal", "unknown key \"normal\""},
        {"duplicate_top_key",
         R"({"format": "refraster-scene/1", "format": "refraster-scene/1", "target": {"width": 8, "height": 8}, "draws": []})",
         "format", "duplicate key \"format\""},
        {"duplicate_state_key", scene_with(kTarget, tri(v0, R"(, "state": {"cull": "back", "cull": "front"})")),
         "draws[0].state.cull", "duplicate key \"cull\""},
        {"width_wrong_type", scene_with(R"({"width": "8", "height": 8})", "[]"), "target.width",
         "expected an integer, got the string \"8\""},
        {"width_fraction", scene_with(R"({"width": 8.5, "height": 8})", "[]"), "target.width",
         "expected an integer, got 8.5"},
        {"target_100000", scene_with(R"({"width": 100000, "height": 100000})", "[]"), "target.width",
         "expected an integer in [1, 16384], got 100000"},
        {"target_area", scene_with(R"({"width": 16384, "height": 16384, "samples": 4})", "[]"),
         "target", "exceeds the limit of 67108864"},
        {"samples_2", scene_with(R"({"width": 8, "height": 8, "samples": 2})", "[]"),
         "target.samples", "expected 1 or 4"},
        {"unknown_color_format", scene_with(R"({"width": 8, "height": 8, "color": "rgb565"})", "[]"),
         "target.color", "expected one of rgba8, rgba32f"},
        {"number_1e400", scene_with(kTarget, tri(R"({"position": [1e400, 1]})")),
         "draws[0].vertices[0].position[0]", "number 1e400 is out of range"},
        {"number_overflows_float32", scene_with(kTarget, tri(R"({"position": [1, 1], "color": [1e39, 0, 0, 1]})")),
         "draws[0].vertices[0].color[0]", "does not fit in float32"},
        {"one_coordinate", scene_with(kTarget, tri(R"({"position": [1]})")),
         "draws[0].vertices[0].position", "expected [x, y], [x, y, z] or [x, y, z, w]"},
        {"clip_three_coordinates",
         scene_with(kTarget, R"([{"primitive": "points", "space": "clip", "vertices": [{"position": [0, 0, 0]}]}])"),
         "draws[0].vertices[0].position", "expected [x, y, z, w]"},
        {"window_w_zero", scene_with(kTarget, tri(R"({"position": [1, 1, 0, 0]})")),
         "draws[0].vertices[0].position[3]", "expected w > 0 in window space"},
        {"window_w_negative", scene_with(kTarget, tri(R"({"position": [1, 1, 0, -2]})")),
         "draws[0].vertices[0].position[3]", "expected w > 0 in window space"},
        {"color_three_components", scene_with(kTarget, tri(R"({"position": [1, 1], "color": [1, 0, 0]})")),
         "draws[0].vertices[0].color", "expected four numbers"},
        {"index_past_count", scene_with(kTarget, tri(v0, R"(, "indices": [0, 1, 3])")),
         "draws[0].indices[2]", "expected an integer in [0, 2], got 3"},
        {"index_negative", scene_with(kTarget, tri(v0, R"(, "indices": [0, -1, 2])")),
         "draws[0].indices[1]", "expected an integer in [0, 2], got -1"},
        {"index_fraction", scene_with(kTarget, tri(v0, R"(, "indices": [0, 1.5, 2])")),
         "draws[0].indices[1]", "expected an integer, got 1.5"},
        {"unknown_primitive", scene_with(kTarget, R"([{"primitive": "quads", "vertices": []}])"),
         "draws[0].primitive", "expected one of points, lines"},
        {"matrix_with_window", scene_with(kTarget, tri(v0, R"(, "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1])")),
         "draws[0].matrix", "allowed only with \"space\": \"clip\""},
        {"matrix_non_finite_result",
         scene_with(kTarget, R"([{"primitive": "points", "space": "clip", "matrix": [3e38,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "vertices": [{"position": [3e38, 0, 0, 1]}]}])"),
         "draws[0].vertices[0].position", "non-finite"},
        {"line_width_zero", scene_with(kTarget, tri(v0, R"(, "state": {"line_width": 0})")),
         "draws[0].state.line_width", "expected a number in [1, 255]"},
        {"depth_range_above_one", scene_with(kTarget, tri(v0, R"(, "state": {"depth_range": [0, 1.5]})")),
         "draws[0].state.depth_range[1]", "expected a number in [0, 1]"},
        {"viewport_width_zero", scene_with(kTarget, tri(v0, R"(, "state": {"viewport": [0, 0, 0, 8]})")),
         "draws[0].state.viewport[2]", "expected an integer in [1, 16384]"},
        {"viewport_origin_range", scene_with(kTarget, tri(v0, R"(, "state": {"viewport": [40000, 0, 8, 8]})")),
         "draws[0].state.viewport[0]", "expected an integer in [-32768, 32767]"},
        {"scissor_negative", scene_with(kTarget, tri(v0, R"(, "state": {"scissor": [0, 0, 4, -1]})")),
         "draws[0].state.scissor[3]", "expected an integer in [0, "},
        {"polygon_offset_missing_units", scene_with(kTarget, tri(v0, R"(, "state": {"polygon_offset": {"factor": 1}})")),
         "draws[0].state.polygon_offset", "missing required key \"units\""},
        {"depth_write_string", scene_with(kTarget, tri(v0, R"(, "state": {"depth_write": "yes"})")),
         "draws[0].state.depth_write", "expected true or false"},
        {"state_not_object", scene_with(kTarget, tri(v0, R"(, "state": [])")), "draws[0].state",
         "expected an object"},
        {"clear_depth_negative", scene_with(kTarget, "[]", R"("clear": {"depth": -0.5}, )"),
         "clear.depth", "expected a number in [0, 1]"},
        {"deep_nesting", scene_with(kTarget, "[]", R"("description": )" + std::string(100, '[') +
                                                     std::string(100, ']') + ", "),
         "", "nesting deeper than 64"},
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
    const auto file = dir.write("s.json", "{\n  \"format\": \"refraster-scene/1\",\n  \"target\": {\"width\": 8,,}\n}");
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
    const auto r = testutil::run_cli({"render", file.string(), "-o", (dir.path() / "o.png").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, file.string() + ": cannot open: no such file\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "o.png"));
}

TEST(SceneFiles, Directory) {
    TempDir dir;
    const auto r = testutil::run_cli({"render", dir.path().string(), "-o", (dir.path() / "o.png").string()});
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
    const auto r = testutil::run_cli({"render", file.string(), "-o", (dir.path() / "o.png").string()});
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
        scene_with(kTarget, "[]", R"("requires": ["textures"], )"), "mem.json");
    EXPECT_EQ(s.unsupported_extensions, (std::vector<std::string>{"textures"}));
}

}  // namespace
