// The extension "vertex_arrays": a scene written with flat or base64 attribute arrays loads to
// the same draw list, byte for byte, as the same scene written with plain vertices (so every
// backend and the worker protocol see the same floats), and every fault in the compact form is
// refused with the path of the value (and the offset inside a base64 string).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>

#include "backends/wire.hpp"
#include "harness/backend.hpp"
#include "harness/front_end.hpp"
#include "harness/scene.hpp"
#include "harness/scene_text.hpp"
#include "test_util.hpp"

namespace {

using harness::SceneError;
using harness::VertexForm;

// A scene of `n` random triangles per draw: window space with 2, 3 and 4 coordinates, clip
// space without and with a matrix, some indexed. Values are float32 of every magnitude the
// front end keeps finite.
harness::SceneFile random_scene(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    const auto real = [&](float lo, float hi) {
        return lo + (hi - lo) * static_cast<float>(rng() % 1'000'003) / 1'000'003.0f;
    };
    harness::SceneFile s;
    s.target.width = 64;
    s.target.height = 48;
    s.target.depth = refraster::DepthFormat::Z24;
    const auto add_draw = [&](harness::VertexSpace space, std::uint32_t size, bool matrix,
                              bool indexed) {
        harness::SceneDraw d;
        d.space = space;
        d.primitive = refraster::PrimitiveType::Triangles;
        d.state.viewport = {0, 0, 64, 48};
        if (matrix) {
            std::array<float, 16> m{};
            for (auto& x : m) x = real(-2, 2);
            d.matrix = m;
        }
        for (int i = 0; i < 30; ++i) {
            harness::SceneVertex v;
            v.position_size = size;
            for (std::uint32_t k = 0; k < size; ++k) {
                v.position[k] = space == harness::VertexSpace::Window ? real(-10, 74) : real(-2, 2);
            }
            if (size == 4) v.position[3] = real(0.25f, 3);
            if (rng() % 3 != 0) v.color = {real(0, 1), real(-1, 2), real(0, 1), real(0, 1)};
            d.vertices.push_back(v);
        }
        if (indexed) {
            std::vector<std::uint32_t> idx;
            for (int i = 0; i < 45; ++i) idx.push_back(static_cast<std::uint32_t>(rng() % 30));
            d.indices = idx;
        }
        s.draws.push_back(d);
    };
    add_draw(harness::VertexSpace::Window, 2, false, false);
    add_draw(harness::VertexSpace::Window, 3, false, true);
    add_draw(harness::VertexSpace::Window, 4, false, false);
    add_draw(harness::VertexSpace::Clip, 4, false, true);
    add_draw(harness::VertexSpace::Clip, 4, true, false);
    add_draw(harness::VertexSpace::Clip, 4, true, true);
    return s;
}

TEST(VertexArrays, EveryFormGivesTheSameDrawListByteForByte) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        const auto file = random_scene(seed);
        const auto plain =
            harness::load_scene_text(harness::scene_json_text(file, VertexForm::Plain), "p.json");
        const auto in_memory = harness::run_front_end(file, "memory");
        EXPECT_EQ(plain.draw_list, in_memory);
        const auto plain_bytes = harness::wire::encode_draw_list(plain.draw_list);
        for (const VertexForm form : {VertexForm::Values, VertexForm::Base64}) {
            const std::string text = harness::scene_json_text(file, form);
            ASSERT_NE(text.find("\"vertex_arrays\": {"), std::string::npos);
            const auto compact = harness::load_scene_text(text, "c.json");
            EXPECT_TRUE(compact.unsupported_extensions.empty());
            EXPECT_EQ(compact.draw_list, plain.draw_list) << "seed " << seed;
            // Floats as bit patterns: the bytes the GL workers receive.
            EXPECT_EQ(harness::wire::encode_draw_list(compact.draw_list), plain_bytes)
                << "seed " << seed;
            for (std::size_t d = 0; d < file.draws.size(); ++d) {
                EXPECT_TRUE(compact.file.draws[d].from_vertex_arrays);
                EXPECT_EQ(compact.file.draws[d].indices, file.draws[d].indices);
            }
        }
    }
}

TEST(VertexArrays, RendersLikeThePlainFormThroughTheReference) {
    const auto file = random_scene(7);
    harness::BackendOptions o;
    o.kind = harness::BackendKind::Ref;
    const auto backend = harness::make_backend(o);
    const auto plain = backend->render(
        harness::load_scene_text(harness::scene_json_text(file, VertexForm::Plain), "p.json"));
    const auto compact = backend->render(
        harness::load_scene_text(harness::scene_json_text(file, VertexForm::Base64), "c.json"));
    ASSERT_EQ(plain.status, harness::RenderStatus::Ok);
    ASSERT_EQ(compact.status, harness::RenderStatus::Ok);
    EXPECT_EQ(plain.image.color8, compact.image.color8);
    EXPECT_EQ(plain.image.depth, compact.image.depth);
    // The scene draws something, so the comparison is not of two empty images.
    EXPECT_NE(std::count(plain.image.color8.begin(), plain.image.color8.end(), 0),
              static_cast<std::ptrdiff_t>(plain.image.color8.size()));
}

// A scene of one draw given as `draw` (a JSON object), with "requires": ["vertex_arrays"].
std::string compact_scene(const std::string& draw, bool listed = true) {
    return std::string(R"({"format": "refraster-scene/1", )") +
           (listed ? R"("requires": ["vertex_arrays"], )" : "") +
           R"("target": {"width": 8, "height": 8}, "draws": [)" + draw + "]}";
}
std::string triangle(const std::string& position, const std::string& extra = "") {
    return R"({"primitive": "triangles", "vertex_arrays": {"count": 3, "position": )" + position +
           extra + "}}";
}

// base64 of float32 values, little-endian.
std::string b64(const std::vector<float>& values) {
    harness::SceneFile s;
    s.target.width = 8;
    s.target.height = 8;
    harness::SceneDraw d;
    d.state.viewport = {0, 0, 8, 8};
    // Borrow the writer: a draw of values.size() / 4 clip-space vertices.
    for (std::size_t i = 0; i + 4 <= values.size(); i += 4) {
        harness::SceneVertex v;
        v.position_size = 4;
        std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(i), 4, v.position.begin());
        d.vertices.push_back(v);
    }
    d.space = harness::VertexSpace::Clip;
    s.draws.push_back(d);
    const std::string text = harness::scene_json_text(s, VertexForm::Base64);
    const auto at = text.find("\"float32_base64\": \"") + 19;
    return text.substr(at, text.find('"', at) - at);
}

struct Refusal {
    std::string name;
    std::string text;
    std::string path;
    std::string detail;
};
void PrintTo(const Refusal& r, std::ostream* os) {
    *os << r.name;
}

std::vector<Refusal> refusals() {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    // Three clip-space vertices: twelve floats.
    const std::vector<float> ok(12, 0.5f);
    auto with = [&](std::size_t k, float v) {
        auto x = ok;
        x[k] = v;
        return x;
    };
    const std::string good = b64(ok);  // 48 bytes: 64 characters, no padding
    const std::string p = R"({"components": 4, "float32_base64": ")";
    const std::string clip = R"({"primitive": "triangles", "space": "clip", "vertex_arrays": )";
    const auto clip_draw = [&](const std::string& position) {
        return clip + R"({"count": 3, "position": )" + position + "}}";
    };
    return {
        {"not_listed_in_requires",
         compact_scene(triangle(R"({"components": 2, "values": [1, 1, 6, 1, 1, 6]})"), false),
         "draws[0].vertex_arrays", "belongs to the extension \"vertex_arrays\""},
        {"indices_object_not_listed",
         compact_scene(
             R"({"primitive": "points", "vertices": [], "indices": {"uint32_base64": ""}})", false),
         "draws[0].indices", "expected an array of indices, got an object"},
        {"both_vertices_and_arrays",
         compact_scene(
             R"({"primitive": "points", "vertices": [], "vertex_arrays": {"count": 0, "position": {"components": 2, "values": []}}})"),
         "draws[0].vertex_arrays", "not both"},
        {"neither", compact_scene(R"({"primitive": "points"})"), "draws[0]",
         "missing required key \"vertices\" (or \"vertex_arrays\")"},
        {"missing_count",
         compact_scene(
             R"({"primitive": "points", "vertex_arrays": {"position": {"components": 2, "values": []}}})"),
         "draws[0].vertex_arrays", "missing required key \"count\""},
        {"unknown_attribute",
         compact_scene(triangle(R"({"components": 2, "values": [1, 1, 6, 1, 1, 6]})",
                                R"(, "normal": {"components": 3, "values": []})")),
         "draws[0].vertex_arrays.normal", "unknown key \"normal\""},
        {"values_value_out_of_float32",
         compact_scene(triangle(R"({"components": 2, "values": [1, 1, 6, 1e39, 1, 6]})")),
         "draws[0].vertex_arrays.position.values[3]", "does not fit in float32"},
        {"values_not_a_number",
         compact_scene(triangle(R"({"components": 2, "values": [1, 1, 6, "1", 1, 6]})")),
         "draws[0].vertex_arrays.position.values[3]", "expected a number"},
        {"values_count_mismatch",
         compact_scene(triangle(R"({"components": 2, "values": [1, 1, 6, 1, 1]})")),
         "draws[0].vertex_arrays.position.values",
         "expected 6 numbers (count 3 x 2 components), got an array of 5"},
        {"values_window_w_zero",
         compact_scene(
             triangle(R"({"components": 4, "values": [1, 1, 0, 1, 6, 1, 0, 0, 1, 6, 0, 1]})")),
         "draws[0].vertex_arrays.position.values[7]", "expected w > 0 in window space, got 0"},
        {"components_one", compact_scene(triangle(R"({"components": 1, "values": [1, 1, 6]})")),
         "draws[0].vertex_arrays.position.components", "expected an integer in [2, 4], got 1"},
        {"clip_components_three", compact_scene(clip_draw(R"({"components": 3, "values": []})")),
         "draws[0].vertex_arrays.position.components", "expected 4"},
        {"color_components_three",
         compact_scene(triangle(R"({"components": 2, "values": [1, 1, 6, 1, 1, 6]})",
                                R"(, "color": {"components": 3, "values": []})")),
         "draws[0].vertex_arrays.color.components", "expected 4 ([r, g, b, a]), got 3"},
        {"values_and_base64", compact_scene(clip_draw(p + good + R"(", "values": []})")),
         "draws[0].vertex_arrays.position.float32_base64", "not both"},
        {"base64_length_not_multiple_of_four",
         compact_scene(clip_draw(p + good.substr(0, 63) + R"("})")),
         "draws[0].vertex_arrays.position.float32_base64",
         "base64 text of 63 characters; expected a multiple of 4"},
        {"base64_bad_character",
         compact_scene(clip_draw(p + good.substr(0, 10) + "*" + good.substr(11) + R"("})")),
         "draws[0].vertex_arrays.position.float32_base64", "character 10 (\"*\") is not base64"},
        {"base64_padding_inside",
         compact_scene(clip_draw(p + good.substr(0, 10) + "=" + good.substr(11) + R"("})")),
         "draws[0].vertex_arrays.position.float32_base64",
         "character 10 (\"=\") is padding before the end"},
        {"base64_padding_bits_not_zero", compact_scene(clip_draw(p + good + R"(AB==")" + "}")),
         "draws[0].vertex_arrays.position.float32_base64", "are not zero"},
        {"base64_whitespace",
         compact_scene(clip_draw(p + good.substr(0, 60) + " " + good.substr(61) + R"("})")),
         "draws[0].vertex_arrays.position.float32_base64", "character 60 (\" \") is not base64"},
        {"base64_wrong_byte_count", compact_scene(clip_draw(p + good + R"(AA==")" + "}")),
         "draws[0].vertex_arrays.position.float32_base64",
         "decodes to 49 bytes, expected 48 (count 3 x 4 components x 4 bytes)"},
        {"base64_count_mismatch",
         compact_scene(clip + R"({"count": 2, "position": )" + p + good + R"("}}})"),
         "draws[0].vertex_arrays.position.float32_base64",
         "decodes to 48 bytes, expected 32 (count 2 x 4 components x 4 bytes)"},
        {"base64_nan", compact_scene(clip_draw(p + b64(with(9, nan)) + R"("})")),
         "draws[0].vertex_arrays.position.float32_base64",
         "value 9 (vertex 2, component 1) is NaN"},
        {"base64_infinity", compact_scene(clip_draw(p + b64(with(4, -inf)) + R"("})")),
         "draws[0].vertex_arrays.position.float32_base64",
         "value 4 (vertex 1, component 0) is infinite"},
        {"base64_window_w_negative", compact_scene(triangle(p + b64(with(7, -2.0f)) + R"("})")),
         "draws[0].vertex_arrays.position.float32_base64",
         "value 7 (vertex 1, component 3): expected w > 0 in window space, got -2"},
        {"front_end_non_finite",
         compact_scene(
             R"({"primitive": "points", "space": "clip", "matrix": [3e38,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], "vertex_arrays": {"count": 2, "position": {"components": 4, "values": [0, 0, 0, 1, 3e38, 0, 0, 1]}}})"),
         "draws[0].vertex_arrays.position", "vertex 1: clip coordinate 0 comes out non-finite"},
    };
}

class VertexArraysRefusal : public ::testing::TestWithParam<Refusal> {};

TEST_P(VertexArraysRefusal, NamesThePath) {
    const Refusal& r = GetParam();
    try {
        (void)harness::load_scene_text(r.text, "v.json");
        FAIL() << "accepted: " << r.text;
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.json_path(), r.path) << what;
        EXPECT_NE(e.detail().find(r.detail), std::string::npos) << what;
        EXPECT_EQ(what.rfind("v.json: " + r.path + ": ", 0), 0u) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

INSTANTIATE_TEST_SUITE_P(All, VertexArraysRefusal, ::testing::ValuesIn(refusals()),
                         [](const auto& p) { return p.param.name; });

// Indices as base64 uint32: the same draw list as the plain array; each refusal names the
// string and the index.
TEST(VertexArrays, Base64Indices) {
    const std::string verts =
        R"("vertex_arrays": {"count": 3, "position": {"components": 2, "values": [1, 1, 6, 1, 1, 6]}})";
    const auto load = [&](const std::string& indices) {
        return harness::load_scene_text(compact_scene(R"({"primitive": "triangles", )" + verts +
                                                      R"(, "indices": )" + indices + "}"),
                                        "i.json");
    };
    // 2, 1, 0 as little-endian uint32.
    const auto a = load(R"({"uint32_base64": "AgAAAAEAAAAAAAAA"})");
    const auto b = load("[2, 1, 0]");
    EXPECT_EQ(a.draw_list, b.draw_list);
    EXPECT_EQ(*a.file.draws[0].indices, (std::vector<std::uint32_t>{2, 1, 0}));
    const auto refused = [&](const std::string& indices, const std::string& detail) {
        try {
            (void)load(indices);
            ADD_FAILURE() << indices;
        } catch (const SceneError& e) {
            EXPECT_EQ(e.json_path(), "draws[0].indices.uint32_base64") << e.what();
            EXPECT_NE(e.detail().find(detail), std::string::npos) << e.what();
        }
    };
    refused(R"({"uint32_base64": "AgAAAAEAAAADAAAA"})",
            "index 2: expected an integer in [0, 2], got 3");
    refused(R"({"uint32_base64": "AgAAAAEA"})",
            "decodes to 6 bytes, not a whole number of 4-byte uint32 indices");
    refused(R"({"uint32_base64": "AgAAAAEAAAAAAAA"})", "expected a multiple of 4");
}

// A scene of 100,000 triangles written to a file in each form loads to the draw list the
// front end makes of the same scene in memory.
TEST(VertexArrays, BigSceneFromAFileEqualsTheSceneInMemory) {
    const auto scene = harness::many_triangles_scene(100'000, 3);
    const auto expected = harness::run_front_end(scene, "memory");
    testutil::TempDir dir("big-scene");
    for (const VertexForm form : {VertexForm::Plain, VertexForm::Values, VertexForm::Base64}) {
        const auto path = dir.write("big.json", harness::scene_json_text(scene, form));
        const auto loaded = harness::load_scene(path);
        EXPECT_EQ(loaded.draw_list.draws.at(0).vertices.size(), 300'000u);
        EXPECT_TRUE(loaded.draw_list == expected) << static_cast<int>(form);
    }
}

}  // namespace
