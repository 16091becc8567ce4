// The published schema and the shipped scenes agree with the loader.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "harness/scene.hpp"
#include "harness/scene_text.hpp"
#include "test_util.hpp"

namespace {

using json = nlohmann::json;
const std::filesystem::path kSource = REFRASTER_SOURCE_DIR;

json schema() {
    return json::parse(testutil::read_text(kSource / "conformance/schema/scene.schema.json"));
}

std::string scene_with_state(const std::string& key, const json& value) {
    json s = {
        {"format", "refraster-scene/1"},
        {"target", {{"width", 4}, {"height", 4}}},
        {"draws",
         json::array(
             {{{"primitive", "points"}, {"vertices", json::array()}, {"state", {{key, value}}}}})}};
    return s.dump();
}

// Every enumerated state value the schema lists is accepted, and nothing else is.
TEST(SceneSchema, StateEnumsMatchTheLoader) {
    const json props =
        schema()["properties"]["draws"]["items"]["properties"]["state"]["properties"];
    int checked = 0;
    for (const auto& [key, spec] : props.items()) {
        if (!spec.contains("enum")) continue;
        for (const auto& v : spec["enum"]) {
            EXPECT_NO_THROW((void)harness::load_scene_text(scene_with_state(key, v), "m.json"))
                << key << " = " << v.dump();
            ++checked;
        }
        EXPECT_THROW(
            (void)harness::load_scene_text(scene_with_state(key, "no-such-value"), "m.json"),
            harness::SceneError)
            << key;
    }
    EXPECT_EQ(checked,
              26);  // cull 4, front_face 2, depth_test 9, shade 3, provoking 2, mode 3, blend 3
}

bool loads(const std::string& key, const json& value) {
    try {
        (void)harness::load_scene_text(scene_with_state(key, value), "m.json");
        return true;
    } catch (const harness::SceneError&) {
        return false;
    }
}

// Every boolean state key takes true and false and nothing else; every ranged number takes its
// bounds as the schema states them (an exclusive minimum refused, the next float32 above it
// accepted; the maximum accepted, the next float32 above it refused).
TEST(SceneSchema, StateBooleansAndRangesMatchTheLoader) {
    const json props =
        schema()["properties"]["draws"]["items"]["properties"]["state"]["properties"];
    std::vector<std::string> booleans;
    std::vector<std::string> ranges;
    for (const auto& [key, spec] : props.items()) {
        SCOPED_TRACE(key);
        const std::string type = spec.value("type", "");
        if (type == "boolean") {
            EXPECT_TRUE(loads(key, true));
            EXPECT_TRUE(loads(key, false));
            EXPECT_FALSE(loads(key, 1));
            EXPECT_FALSE(loads(key, "true"));
            EXPECT_FALSE(loads(key, nullptr));
            booleans.push_back(key);
        }
        if (type == "number" && spec.contains("maximum")) {
            const float hi = spec["maximum"].get<float>();
            EXPECT_TRUE(loads(key, hi));
            EXPECT_FALSE(loads(key, double{std::nextafter(hi, 1e30f)}));
            if (spec.contains("exclusiveMinimum")) {
                const float lo = spec["exclusiveMinimum"].get<float>();
                EXPECT_FALSE(loads(key, lo));
                EXPECT_TRUE(loads(key, double{std::nextafter(lo, hi)}));
                EXPECT_FALSE(loads(key, double{std::nextafter(lo, -1e30f)}));
            } else {
                ASSERT_TRUE(spec.contains("minimum"));
                const float lo = spec["minimum"].get<float>();
                EXPECT_TRUE(loads(key, lo));
                EXPECT_FALSE(loads(key, double{std::nextafter(lo, -1e30f)}));
            }
            ranges.push_back(key);
        }
    }
    EXPECT_EQ(booleans, (std::vector<std::string>{"depth_write", "multisample"}));
    EXPECT_EQ(ranges, (std::vector<std::string>{"line_width", "point_size"}));
    // The values 4x scenes use.
    EXPECT_TRUE(loads("line_width", 0.5));
    EXPECT_TRUE(loads("point_size", 0.7));
}

TEST(SceneSchema, PrimitivesMatchTheLoader) {
    const json prims = schema()["properties"]["draws"]["items"]["properties"]["primitive"]["enum"];
    ASSERT_EQ(prims.size(), 8u);  // format v1's seven and the extension polygons' "polygon"
    for (const auto& p : prims) {
        json s = {{"format", "refraster-scene/1"},
                  {"requires", json::array({"polygons"})},
                  {"target", {{"width", 4}, {"height", 4}}},
                  {"draws", json::array({{{"primitive", p}, {"vertices", json::array()}}})}};
        const auto scene = harness::load_scene_text(s.dump(), "m.json");
        EXPECT_EQ(refraster::to_string(scene.draw_list.draws[0].primitive), p.get<std::string>());
    }
}

// The extension "vertex_arrays" as the schema publishes it: the draw key and its attributes,
// their component ranges, and indices as base64; the loader accepts exactly those, and only
// when "requires" lists the extension.
TEST(SceneSchema, VertexArraysMatchTheLoader) {
    const json draw = schema()["properties"]["draws"]["items"];
    const json va = draw["properties"]["vertex_arrays"];
    EXPECT_EQ(va["required"], json::array({"count", "position"}));
    EXPECT_EQ(draw["oneOf"],
              json::parse(R"([{"required": ["vertices"]}, {"required": ["vertex_arrays"]}])"));
    const json pos = va["properties"]["position"]["properties"]["components"];
    const json col = va["properties"]["color"]["properties"]["components"];
    const auto scene = [](const json& arrays, bool listed) {
        json s = {{"format", "refraster-scene/1"},
                  {"target", {{"width", 4}, {"height", 4}}},
                  {"draws", json::array({{{"primitive", "points"}, {"vertex_arrays", arrays}}})}};
        if (listed) s["requires"] = json::array({"vertex_arrays"});
        return s.dump();
    };
    const auto loads_arrays = [&](int position_components, int color_components, bool listed) {
        json a = {{"count", 1},
                  {"position",
                   {{"components", position_components},
                    {"values",
                     std::vector<double>(static_cast<std::size_t>(position_components), 1.0)}}}};
        if (color_components != 0) {
            a["color"] = {
                {"components", color_components},
                {"values", std::vector<double>(static_cast<std::size_t>(color_components), 0.5)}};
        }
        try {
            (void)harness::load_scene_text(scene(a, listed), "va.json");
            return true;
        } catch (const harness::SceneError&) {
            return false;
        }
    };
    for (int n = 0; n <= 5; ++n) {
        SCOPED_TRACE(n);
        EXPECT_EQ(loads_arrays(n, 0, true),
                  n >= pos["minimum"].get<int>() && n <= pos["maximum"].get<int>());
        EXPECT_EQ(loads_arrays(2, n == 0 ? 1 : n, true),
                  n >= col["minimum"].get<int>() && n <= col["maximum"].get<int>());
    }
    EXPECT_FALSE(loads_arrays(2, 4, false));
    const json idx = draw["properties"]["indices"]["oneOf"][1];
    EXPECT_EQ(idx["required"], json::array({"uint32_base64"}));
}

// The extension "textures" as the schema publishes it: every enumerated value of a draw's
// "texture" loads and nothing else does, texture sides span the schema's range, and the keys
// load only when "requires" lists the extension.
TEST(SceneSchema, TexturesMatchTheLoader) {
    const json s = schema();
    const json state = s["properties"]["draws"]["items"]["properties"]["state"]["properties"]
                        ["texture"]["oneOf"][1];
    EXPECT_EQ(state["required"], json::array({"name"}));
    const json side = s["properties"]["textures"]["additionalProperties"]["properties"]["width"];
    const auto loads_texture = [](const json& texture_state, std::int64_t width, bool listed) {
        const json t = {
            {"width", width},
            {"height", 1},
            {"data",
             harness::base64_text(std::vector<std::uint8_t>(static_cast<std::size_t>(width) * 4))},
            {"mipmaps", "generate"}};
        json scene = {{"format", "refraster-scene/1"},
                      {"target", {{"width", 4}, {"height", 4}}},
                      {"textures", {{"t", t}}},
                      {"draws", json::array({{{"primitive", "points"},
                                              {"vertices", json::array()},
                                              {"state", {{"texture", texture_state}}}}})}};
        if (listed) scene["requires"] = json::array({"textures"});
        try {
            (void)harness::load_scene_text(scene.dump(), "t.json");
            return true;
        } catch (const harness::SceneError&) {
            return false;
        }
    };
    int checked = 0;
    for (const auto& [key, spec] : state["properties"].items()) {
        if (!spec.contains("enum")) continue;
        for (const auto& v : spec["enum"]) {
            EXPECT_TRUE(loads_texture({{"name", "t"}, {key, v}}, 1, true)) << key << " = " << v;
            ++checked;
        }
        EXPECT_FALSE(loads_texture({{"name", "t"}, {key, "no-such-value"}}, 1, true)) << key;
    }
    // min_filter 6, mag_filter 2, wrap_s 4, wrap_t 4, env 2, point_coord_origin 2
    EXPECT_EQ(checked, 20);
    // The boolean coord_replace: both values load, a number does not.
    EXPECT_EQ(state["properties"]["coord_replace"]["type"], "boolean");
    EXPECT_TRUE(loads_texture({{"name", "t"}, {"coord_replace", true}}, 1, true));
    EXPECT_TRUE(loads_texture({{"name", "t"}, {"coord_replace", false}}, 1, true));
    EXPECT_FALSE(loads_texture({{"name", "t"}, {"coord_replace", 1}}, 1, true));
    const std::int64_t lo = side["minimum"].get<std::int64_t>();
    const std::int64_t hi = side["maximum"].get<std::int64_t>();
    EXPECT_TRUE(loads_texture({{"name", "t"}}, lo, true));
    EXPECT_TRUE(loads_texture({{"name", "t"}}, hi, true));
    EXPECT_FALSE(loads_texture({{"name", "t"}}, lo - 1, true));
    EXPECT_FALSE(loads_texture({{"name", "t"}}, hi + 1, true));
    EXPECT_FALSE(loads_texture({{"name", "t"}}, 1, false));
    EXPECT_TRUE(loads_texture(nullptr, 1, true));
}

// The extension "polygons" as the schema publishes it: the primitive "polygon" and every fill
// rule load when "requires" lists the extension and are refused, naming it, when it does not.
TEST(SceneSchema, PolygonsMatchTheLoader) {
    const json s = schema();
    const json draw = s["properties"]["draws"]["items"]["properties"];
    const json primitives = draw["primitive"]["enum"];
    EXPECT_NE(std::find(primitives.begin(), primitives.end(), "polygon"), primitives.end());
    const json rules = draw["state"]["properties"]["fill_rule"]["oneOf"][1]["enum"];
    const auto polygon_scene = [](const json& rule, bool listed) {
        json scene = {{"format", "refraster-scene/1"},
                      {"target", {{"width", 4}, {"height", 4}}},
                      {"draws", json::array({{{"primitive", "polygon"},
                                              {"vertices", json::array()},
                                              {"state", {{"fill_rule", rule}}}}})}};
        if (listed) scene["requires"] = json::array({"polygons"});
        return scene.dump();
    };
    int checked = 0;
    for (const auto& rule : rules) {
        EXPECT_NO_THROW((void)harness::load_scene_text(polygon_scene(rule, true), "p.json"))
            << rule;
        ++checked;
    }
    EXPECT_EQ(checked, 2);
    EXPECT_NO_THROW((void)harness::load_scene_text(polygon_scene(nullptr, true), "p.json"));
    EXPECT_THROW((void)harness::load_scene_text(polygon_scene("winding", true), "p.json"),
                 harness::SceneError);
    try {
        (void)harness::load_scene_text(polygon_scene(nullptr, false), "p.json");
        ADD_FAILURE() << "a polygon without the extension loaded";
    } catch (const harness::SceneError& e) {
        EXPECT_EQ(e.json_path(), "draws[0].primitive");
        EXPECT_NE(std::string(e.what()).find("\"polygons\""), std::string::npos) << e.what();
    }
}

// Every shipped scene loads, describes itself, and is named by its dotted path.
TEST(ShippedScenes, LoadDescribeAndNameByPath) {
    const auto root = kSource / "conformance/scenes";
    int n = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
        if (e.path().extension() != ".json") continue;
        SCOPED_TRACE(e.path().string());
        const auto s = harness::load_scene(e.path());
        EXPECT_FALSE(s.file.description.empty());
        auto rel = std::filesystem::relative(e.path(), root).replace_extension("").string();
        for (auto& c : rel) c = c == '/' ? '.' : c;
        EXPECT_EQ(s.file.name, rel);
        ++n;
    }
    EXPECT_GE(n, 8);
}

}  // namespace
