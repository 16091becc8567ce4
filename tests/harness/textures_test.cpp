// The extension "textures": textures by name (base64 texels or PNG files, given mipmap levels or
// glGenerateMipmap), texture coordinates in both vertex forms, and each draw's texture state;
// what the front end makes of them, how scenes written back load again, and how every fault is
// refused with the path of the value.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "harness/front_end.hpp"
#include "harness/image_io.hpp"
#include "harness/reduce.hpp"
#include "harness/scene.hpp"
#include "harness/scene_text.hpp"
#include "test_util.hpp"

namespace {

using harness::SceneError;
using json = nlohmann::json;
using testutil::TempDir;

// w x h RGBA8 texels whose bytes tell them apart: texel i is (i, 2i, 3i, 255 - i) mod 256,
// plus `seed`.
std::vector<std::uint8_t> texels(std::uint32_t w, std::uint32_t h, std::uint8_t seed = 0) {
    std::vector<std::uint8_t> t(std::size_t{w} * h * 4);
    for (std::size_t i = 0; i < std::size_t{w} * h; ++i) {
        t[i * 4 + 0] = static_cast<std::uint8_t>(i + seed);
        t[i * 4 + 1] = static_cast<std::uint8_t>(2 * i + seed);
        t[i * 4 + 2] = static_cast<std::uint8_t>(3 * i + seed);
        t[i * 4 + 3] = static_cast<std::uint8_t>(255 - i - seed);
    }
    return t;
}

json image_json(std::uint32_t w, std::uint32_t h, std::uint8_t seed = 0) {
    return {{"width", w}, {"height", h}, {"data", harness::base64_text(texels(w, h, seed))}};
}

// A scene that requires "textures" (unless `requires_list` says otherwise), defines
// `textures` and draws one triangle with `state` (and the given texture coordinates).
json scene_json(const json& textures, const json& state,
                const json& requires_list = json::array({"textures"})) {
    json s = {{"format", "refraster-scene/1"},
              {"name", "t"},
              {"requires", requires_list},
              {"target", {{"width", 8}, {"height", 8}}}};
    if (!textures.is_null()) s["textures"] = textures;
    json vertices = json::array();
    vertices.push_back({{"position", {1, 1}}, {"texcoord", {0, 0}}});
    vertices.push_back({{"position", {7, 1}}, {"texcoord", {1, 0, 0.5, 2}}});
    vertices.push_back({{"position", {1, 7}}, {"color", {1, 0, 0, 1}}});
    json draw = {{"primitive", "triangles"}, {"vertices", vertices}};
    if (!state.is_null()) draw["state"] = state;
    s["draws"] = json::array({draw});
    return s;
}

harness::Scene load(const json& j, const std::string& label = "tex.json",
                    const harness::SceneLimits& limits = {}) {
    return harness::load_scene_text(j.dump(), label, limits);
}

// The refusal of `j`: its JSON path and detail. Fails the test when `j` loads.
SceneError refusal(const json& j, const std::string& label = "tex.json",
                   const harness::SceneLimits& limits = {}) {
    try {
        (void)load(j, label, limits);
    } catch (const SceneError& e) {
        // One line, starting with the file.
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).rfind(label + ": ", 0), 0u) << e.what();
        return e;
    }
    ADD_FAILURE() << "loaded: " << j.dump();
    return SceneError(label, "", "");
}

#define EXPECT_REFUSED(j, path_, detail_)                                     \
    do {                                                                      \
        const SceneError e_ = refusal(j);                                     \
        EXPECT_EQ(e_.json_path(), path_) << e_.what();                        \
        EXPECT_NE(e_.detail().find(detail_), std::string::npos) << e_.what(); \
    } while (false)

// The one refusal of every texture file that cannot be used, whatever the reason.
std::string unusable(const std::string& written) {
    return "\"" + written +
           "\" cannot be used as a texture (a PNG file under the scene's folder or "
           "--texture-root; docs/scene-format.md)";
}

// ---- PNG files written byte by byte (grey, grey and alpha, RGB, bit depths the writer of
// image_io.hpp does not make): zlib's stored blocks, no compression.

std::uint32_t crc32(const std::uint8_t* p, std::size_t n, std::uint32_t crc = 0) {
    crc = ~crc;
    for (std::size_t i = 0; i < n; ++i) {
        crc ^= p[i];
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

void put_u32_be(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}

void put_chunk(std::vector<std::uint8_t>& out, const char* type,
               const std::vector<std::uint8_t>& data) {
    put_u32_be(out, static_cast<std::uint32_t>(data.size()));
    std::vector<std::uint8_t> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    out.insert(out.end(), body.begin(), body.end());
    put_u32_be(out, crc32(body.data(), body.size()));
}

using Chunks = std::vector<std::pair<std::string, std::vector<std::uint8_t>>>;

// A PNG of `rows` (file order: top row first), each row's bytes without the filter byte, with
// the chunks `before_idat` (PLTE, tRNS) between IHDR and IDAT.
std::string png_bytes(std::uint32_t w, std::uint32_t h, std::uint8_t depth, std::uint8_t color_type,
                      const std::vector<std::vector<std::uint8_t>>& rows,
                      const Chunks& before_idat = {}) {
    std::vector<std::uint8_t> raw;
    for (const auto& r : rows) {
        raw.push_back(0);  // filter: none
        raw.insert(raw.end(), r.begin(), r.end());
    }
    std::vector<std::uint8_t> z = {0x78, 0x01};
    for (std::size_t at = 0;;) {
        const std::size_t n = std::min<std::size_t>(raw.size() - at, 65535);
        const bool last = at + n == raw.size();
        z.push_back(last ? 1 : 0);
        z.push_back(static_cast<std::uint8_t>(n));
        z.push_back(static_cast<std::uint8_t>(n >> 8));
        z.push_back(static_cast<std::uint8_t>(~n));
        z.push_back(static_cast<std::uint8_t>(~n >> 8));
        z.insert(z.end(), raw.begin() + static_cast<std::ptrdiff_t>(at),
                 raw.begin() + static_cast<std::ptrdiff_t>(at + n));
        at += n;
        if (last) break;
    }
    std::uint32_t a = 1;
    std::uint32_t b = 0;
    for (const std::uint8_t c : raw) {
        a = (a + c) % 65521;
        b = (b + a) % 65521;
    }
    put_u32_be(z, (b << 16) | a);
    std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<std::uint8_t> ihdr;
    put_u32_be(ihdr, w);
    put_u32_be(ihdr, h);
    ihdr.insert(ihdr.end(), {depth, color_type, 0, 0, 0});
    put_chunk(out, "IHDR", ihdr);
    for (const auto& [type, data] : before_idat) put_chunk(out, type.c_str(), data);
    put_chunk(out, "IDAT", z);
    put_chunk(out, "IEND", {});
    return {out.begin(), out.end()};
}

// ---- valid scenes

TEST(Textures, DataTexturesReachTheDrawListInNameOrder) {
    json t = {{"zebra", image_json(2, 1, 7)}, {"apple", image_json(3, 2)}};
    const auto s = load(scene_json(t, {{"texture",
                                        {{"name", "zebra"},
                                         {"min_filter", "nearest"},
                                         {"mag_filter", "nearest"},
                                         {"wrap_s", "clamp_to_border"},
                                         {"wrap_t", "mirrored_repeat"},
                                         {"border_color", {0.25, 0.5, 0.75, 1}},
                                         {"env", "replace"}}}}));
    EXPECT_TRUE(s.unsupported_extensions.empty());
    ASSERT_EQ(s.file.textures.size(), 2u);
    const auto& apple = s.file.textures.at("apple");
    ASSERT_EQ(apple.levels.size(), 1u);
    EXPECT_EQ(apple.levels[0].width, 3u);
    EXPECT_EQ(apple.levels[0].height, 2u);
    EXPECT_EQ(apple.levels[0].rgba, texels(3, 2));
    EXPECT_FALSE(apple.generate_mipmaps);
    // Name order: apple is 0, zebra 1.
    ASSERT_EQ(s.draw_list.textures.size(), 2u);
    EXPECT_EQ(s.draw_list.textures[0], apple);
    EXPECT_EQ(s.draw_list.textures[1].levels[0].rgba, texels(2, 1, 7));
    const auto& d = s.draw_list.draws[0];
    EXPECT_EQ(s.file.draws[0].texture, "zebra");
    ASSERT_TRUE(d.state.texture.has_value());
    const refraster::TextureState expected{1,
                                           refraster::TextureFilter::Nearest,
                                           refraster::TextureFilter::Nearest,
                                           refraster::TextureWrap::ClampToBorder,
                                           refraster::TextureWrap::MirroredRepeat,
                                           {0.25f, 0.5f, 0.75f, 1.0f},
                                           refraster::TextureEnv::Replace};
    EXPECT_EQ(*d.state.texture, expected);
    // Record layout [x y z w | r g b a | s t r q].
    EXPECT_EQ(d.vertices.attributes,
              (std::vector<refraster::AttributeDesc>{{"color", 4}, {"texcoord", 4}}));
    ASSERT_EQ(d.vertices.stride(), 12u);
    const auto v0 = d.vertices.vertex(0);
    const auto v1 = d.vertices.vertex(1);
    const auto v2 = d.vertices.vertex(2);
    EXPECT_EQ(std::vector<float>(v0.begin() + 4, v0.end()),
              (std::vector<float>{1, 1, 1, 1, 0, 0, 0, 1}));
    EXPECT_EQ(std::vector<float>(v1.begin() + 8, v1.end()), (std::vector<float>{1, 0, 0.5f, 2}));
    EXPECT_EQ(std::vector<float>(v2.begin() + 4, v2.end()),
              (std::vector<float>{1, 0, 0, 1, 0, 0, 0, 1}));
}

TEST(Textures, PointSpriteKeysLoadAndRoundTrip) {
    json j = scene_json(
        {{"t", image_json(2, 2)}},
        {{"texture",
          {{"name", "t"}, {"coord_replace", true}, {"point_coord_origin", "lower_left"}}}});
    j["draws"][0]["primitive"] = "points";
    const auto s = load(j);
    const auto& d = s.draw_list.draws[0];
    ASSERT_TRUE(d.state.texture.has_value());
    EXPECT_TRUE(d.state.texture->coord_replace);
    EXPECT_EQ(d.state.texture->point_coord_origin, refraster::PointCoordOrigin::LowerLeft);
    EXPECT_TRUE(d.samples_point_coords());
    // Written back, only what differs from the defaults appears, and it loads the same.
    const std::string written = harness::scene_to_json(s.file);
    const auto w = json::parse(written);
    EXPECT_EQ(w["draws"][0]["state"]["texture"]["coord_replace"], true);
    EXPECT_EQ(w["draws"][0]["state"]["texture"]["point_coord_origin"], "lower_left");
    EXPECT_EQ(harness::load_scene_text(written, "again.json").draw_list, s.draw_list);
    // Triangles ignore it unless polygon mode point turns them into points.
    refraster::Draw tri = d;
    tri.primitive = refraster::PrimitiveType::Triangles;
    EXPECT_FALSE(tri.samples_point_coords());
    tri.state.polygon_mode = refraster::PolygonMode::Point;
    EXPECT_TRUE(tri.samples_point_coords());
    tri.primitive = refraster::PrimitiveType::LineStrip;
    EXPECT_FALSE(tri.samples_point_coords());
    const auto plain = harness::scene_to_json(
        load(scene_json({{"t", image_json(1, 1)}}, {{"texture", {{"name", "t"}}}})).file);
    EXPECT_EQ(json::parse(plain)["draws"][0]["state"]["texture"].count("coord_replace"), 0u);
}

TEST(Textures, StateDefaults) {
    const auto s = load(scene_json({{"t", image_json(1, 1)}}, {{"texture", {{"name", "t"}}}}));
    const refraster::TextureState defaults;
    EXPECT_EQ(*s.draw_list.draws[0].state.texture, defaults);
    EXPECT_EQ(defaults.min_filter, refraster::TextureFilter::Linear);
    EXPECT_EQ(defaults.mag_filter, refraster::TextureFilter::Linear);
    EXPECT_EQ(defaults.wrap_s, refraster::TextureWrap::Repeat);
    EXPECT_EQ(defaults.wrap_t, refraster::TextureWrap::Repeat);
    EXPECT_EQ(defaults.border_color, (std::array<float, 4>{0, 0, 0, 0}));
    EXPECT_EQ(defaults.env, refraster::TextureEnv::Modulate);
    EXPECT_FALSE(defaults.coord_replace);
    EXPECT_EQ(defaults.point_coord_origin, refraster::PointCoordOrigin::UpperLeft);
    // "texture": null is no texture, as "polygon_offset": null is no offset.
    const auto n = load(scene_json({{"t", image_json(1, 1)}}, {{"texture", nullptr}}));
    EXPECT_FALSE(n.draw_list.draws[0].state.texture.has_value());
    EXPECT_EQ(n.draw_list.draws[0].vertices.stride(), 8u);
}

// A draw without a texture keeps the layout of format v1 exactly ("color" alone), texture
// coordinates or not, and a scene without the extension has no textures at all.
TEST(Textures, DrawsWithoutATextureKeepTheColourLayout) {
    const auto s = load(scene_json({{"t", image_json(2, 2)}}, nullptr));
    const auto& d = s.draw_list.draws[0];
    EXPECT_FALSE(d.state.texture.has_value());
    EXPECT_EQ(d.vertices.attributes, (std::vector<refraster::AttributeDesc>{{"color", 4}}));
    EXPECT_EQ(d.vertices.data.size(), 3u * 8u);
    EXPECT_EQ(s.draw_list.textures.size(), 1u);  // defined, not used: still in the list

    json plain = scene_json(nullptr, nullptr, json::array());
    for (auto& v : plain["draws"][0]["vertices"]) v.erase("texcoord");
    const auto p = load(plain);
    EXPECT_TRUE(p.draw_list.textures.empty());
    EXPECT_EQ(p.draw_list.draws[0].vertices.attributes,
              (std::vector<refraster::AttributeDesc>{{"color", 4}}));
    // The same draw list as before the extension: built by hand in format v1's layout.
    refraster::DrawList expected;
    expected.target.width = 8;
    expected.target.height = 8;
    refraster::Draw draw;
    draw.state.viewport = {0, 0, 8, 8};
    draw.vertices.attributes = {{"color", 4}};
    // Window z 0 is ndc z -1 with the depth range [0, 1].
    draw.vertices.data = {-0.75f, -0.75f, -1, 1, 1, 1, 1, 1,  //
                          0.75f,  -0.75f, -1, 1, 1, 1, 1, 1,  //
                          -0.75f, 0.75f,  -1, 1, 1, 0, 0, 1};
    expected.draws.push_back(draw);
    EXPECT_EQ(p.draw_list, expected);
}

TEST(Textures, GivenLevelsAndGeneratedMipmaps) {
    json t = {{"given",
               {{"width", 8},
                {"height", 2},
                {"data", image_json(8, 2)["data"]},
                {"levels", {image_json(4, 1, 1), image_json(2, 1, 2)}}}},
              {"made",
               {{"width", 4},
                {"height", 4},
                {"data", image_json(4, 4)["data"]},
                {"mipmaps", "generate"}}}};
    const auto s = load(
        scene_json(t, {{"texture", {{"name", "given"}, {"min_filter", "linear_mipmap_linear"}}}}));
    const auto& given = s.file.textures.at("given");
    ASSERT_EQ(given.levels.size(), 3u);  // fewer than the full chain (8x2, 4x1, 2x1, 1x1)
    EXPECT_EQ(given.levels[1].width, 4u);
    EXPECT_EQ(given.levels[1].height, 1u);
    EXPECT_EQ(given.levels[1].rgba, texels(4, 1, 1));
    EXPECT_EQ(given.levels[2].rgba, texels(2, 1, 2));
    EXPECT_FALSE(given.generate_mipmaps);
    const auto& made = s.file.textures.at("made");
    EXPECT_EQ(made.levels.size(), 1u);
    EXPECT_TRUE(made.generate_mipmaps);
    EXPECT_EQ(s.draw_list.draws[0].state.texture->texture, 0u);
    EXPECT_EQ(s.draw_list.draws[0].state.texture->min_filter,
              refraster::TextureFilter::LinearMipmapLinear);
    // Every mipmap filter is accepted with generated mipmaps.
    for (const char* f : {"nearest_mipmap_nearest", "linear_mipmap_nearest",
                          "nearest_mipmap_linear", "linear_mipmap_linear"}) {
        EXPECT_NO_THROW(
            (void)load(scene_json(t, {{"texture", {{"name", "made"}, {"min_filter", f}}}})))
            << f;
    }
}

TEST(Textures, TexcoordsOfTwoAndFourComponents) {
    const auto s = load(scene_json({{"t", image_json(1, 1)}}, nullptr));
    const auto& v = s.file.draws[0].vertices;
    EXPECT_EQ(v[0].texcoord, (std::array<float, 4>{0, 0, 0, 1}));
    EXPECT_EQ(v[1].texcoord, (std::array<float, 4>{1, 0, 0.5f, 2}));
    EXPECT_EQ(v[2].texcoord, (std::array<float, 4>{0, 0, 0, 1}));  // the default
    // Each number a double rounded once to float32.
    json j = scene_json(nullptr, nullptr);
    j["draws"][0]["vertices"][0]["texcoord"] = {0.1, 1e-50};
    const auto r = load(j);
    EXPECT_EQ(r.file.draws[0].vertices[0].texcoord, (std::array<float, 4>{0.1f, 0.0f, 0, 1}));
}

// "vertex_arrays" with a "texcoord" attribute of 2 or 4 components, as values or base64, loads
// to the draw list of the plain form, byte for byte.
TEST(Textures, VertexArraysTexcoordsMatchThePlainForm) {
    harness::SceneFile f;
    f.target.width = 16;
    f.target.height = 16;
    f.textures["t"] = refraster::Texture{{refraster::TextureImage{2, 2, texels(2, 2)}}, true};
    for (int k = 0; k < 2; ++k) {
        harness::SceneDraw d;
        d.state.viewport = {0, 0, 16, 16};
        d.state.texture = refraster::TextureState{};
        d.state.texture->min_filter = refraster::TextureFilter::NearestMipmapLinear;
        d.texture = "t";
        for (int i = 0; i < 6; ++i) {
            harness::SceneVertex v;
            v.position_size = 2;
            v.position = {static_cast<float>(i * 2), static_cast<float>(i % 3 * 5), 0, 1};
            v.texcoord = {0.125f * static_cast<float>(i), -0.5f, 0, 1};
            if (k == 1) v.texcoord[3] = 1.5f;  // four components
            d.vertices.push_back(v);
        }
        f.draws.push_back(d);
    }
    const auto plain =
        harness::load_scene_text(harness::scene_json_text(f, harness::VertexForm::Plain), "p.json");
    EXPECT_EQ(plain.draw_list, harness::run_front_end(f, "memory"));
    for (const auto form : {harness::VertexForm::Values, harness::VertexForm::Base64}) {
        const std::string text = harness::scene_json_text(f, form);
        const auto j = json::parse(text);
        EXPECT_EQ(j["requires"], json::array({"textures", "vertex_arrays"}));
        EXPECT_EQ(j["draws"][0]["vertex_arrays"]["texcoord"]["components"], 2);
        EXPECT_EQ(j["draws"][1]["vertex_arrays"]["texcoord"]["components"], 4);
        const auto compact = harness::load_scene_text(text, "c.json");
        EXPECT_EQ(compact.draw_list, plain.draw_list);
        EXPECT_EQ(compact.file.draws[1].vertices[5].texcoord,
                  (std::array<float, 4>{0.625f, -0.5f, 0, 1.5f}));
    }
}

// scene_to_json (reduce) writes textures, texture coordinates and the texture state: the scene
// loads again into the same file and the same draw list. "textures" joins "requires" when the
// scene uses the extension without listing it.
TEST(Textures, SceneToJsonRoundTrip) {
    json t = {{"a",
               {{"width", 4},
                {"height", 2},
                {"data", image_json(4, 2)["data"]},
                {"levels", {image_json(2, 1, 3)}}}},
              {"b",
               {{"width", 1},
                {"height", 1},
                {"data", image_json(1, 1)["data"]},
                {"mipmaps", "generate"}}}};
    json j = scene_json(t, {{"texture",
                             {{"name", "a"},
                              {"min_filter", "nearest_mipmap_nearest"},
                              {"wrap_t", "clamp_to_edge"},
                              {"border_color", {-0.0, 0, 2, 0}}}}});
    j["draws"][0]["vertices"][2]["texcoord"] = {-0.0, 0, 0, 1};  // not the default, bitwise
    const auto first = load(j);
    for (const bool listed : {true, false}) {
        harness::SceneFile f = first.file;
        if (!listed) f.requires_extensions.clear();
        const std::string written = harness::scene_to_json(f);
        const auto again = harness::load_scene_text(written, "again.json");
        EXPECT_EQ(again.draw_list, first.draw_list);
        EXPECT_EQ(again.file.textures, first.file.textures);
        EXPECT_EQ(again.file.draws[0].texture, "a");
        EXPECT_EQ(again.file.requires_extensions, std::vector<std::string>{"textures"});
        EXPECT_TRUE(std::signbit(again.file.draws[0].vertices[2].texcoord[0]));
        EXPECT_TRUE(std::signbit(again.draw_list.draws[0].state.texture->border_color[0]));
        const auto w = json::parse(written);
        EXPECT_EQ(w["textures"]["b"]["mipmaps"], "generate");
        EXPECT_EQ(w["draws"][0]["vertices"][0].count("texcoord"), 0u);  // the default
        EXPECT_EQ(w["draws"][0]["vertices"][1]["texcoord"].size(), 4u);
        EXPECT_EQ(w["draws"][0]["state"]["texture"].count("mag_filter"), 0u);
    }
}

// A PNG file, read relative to the scene file's directory: the file's top row is the texture's
// last. RGBA as written by the harness's image writer; grey, grey and alpha, RGB and palette
// images expanded to RGBA.
TEST(Textures, PngFilesRelativeToTheScene) {
    TempDir dir("textures");
    refraster::Framebuffer fb(3, 2, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None);
    const auto rgba = texels(3, 2);  // rows bottom to top, as the texture wants them
    std::copy(rgba.begin(), rgba.end(), fb.color8.begin());
    std::filesystem::create_directories(dir.path() / "img");
    harness::write_color_image(fb, dir.path() / "img" / "rgba.png");
    // File rows top first: the top row (2, 3) and the bottom one (0, 1).
    dir.write("img/grey.png", png_bytes(2, 2, 8, 0, {{2, 3}, {0, 1}}));
    dir.write("img/grey_alpha.png", png_bytes(1, 2, 8, 4, {{9, 10}, {7, 8}}));
    dir.write("img/rgb.png", png_bytes(1, 2, 8, 2, {{4, 5, 6}, {1, 2, 3}}));
    json t = {{"rgba", {{"file", "img/rgba.png"}}},
              {"sized", {{"file", "img/rgba.png"}, {"width", 3}, {"height", 2}}},
              {"grey", {{"file", "img/grey.png"}}},
              {"grey_alpha", {{"file", "img/grey_alpha.png"}}},
              {"rgb", {{"file", "img/rgb.png"}}},
              {"levels",
               {{"width", 4},
                {"height", 4},
                {"data", image_json(4, 4)["data"]},
                {"levels", {{{"file", "img/grey.png"}}}}}}};
    const auto path = dir.write("scene.json", scene_json(t, nullptr).dump());
    const auto s = harness::load_scene(path);
    EXPECT_EQ(s.file.textures.at("rgba").levels[0].rgba, texels(3, 2));
    EXPECT_EQ(s.file.textures.at("sized").levels[0].rgba, texels(3, 2));
    EXPECT_EQ(s.file.textures.at("grey").levels[0].rgba,
              (std::vector<std::uint8_t>{0, 0, 0, 255, 1, 1, 1, 255, 2, 2, 2, 255, 3, 3, 3, 255}));
    EXPECT_EQ(s.file.textures.at("grey_alpha").levels[0].rgba,
              (std::vector<std::uint8_t>{7, 7, 7, 8, 9, 9, 9, 10}));
    EXPECT_EQ(s.file.textures.at("rgb").levels[0].rgba,
              (std::vector<std::uint8_t>{1, 2, 3, 255, 4, 5, 6, 255}));
    EXPECT_EQ(s.file.textures.at("levels").levels[1].rgba,
              s.file.textures.at("grey").levels[0].rgba);
    // The file's texels, written back as data, load the same.
    const auto again = harness::load_scene_text(harness::scene_to_json(s.file), "again.json");
    EXPECT_EQ(again.draw_list, s.draw_list);
    // The CLI reads it too, from another working directory.
    const auto r = testutil::run_cli({"check", path.string()});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("6 textures"), std::string::npos) << r.out;
}

// ---- refusals

TEST(TexturesRefusal, KeysNeedTheExtensionInRequires) {
    const json none = json::array();
    EXPECT_REFUSED(scene_json({{"t", image_json(1, 1)}}, nullptr, none), "textures",
                   "the key \"textures\" belongs to the extension \"textures\"; list it in "
                   "\"requires\" to use it");
    EXPECT_REFUSED(scene_json(nullptr, nullptr, none), "draws[0].vertices[0].texcoord",
                   "belongs to the extension \"textures\"");
    json state = scene_json(nullptr, {{"texture", {{"name", "t"}}}}, none);
    for (auto& v : state["draws"][0]["vertices"]) v.erase("texcoord");
    EXPECT_REFUSED(state, "draws[0].state.texture", "belongs to the extension \"textures\"");
    json va = {{"format", "refraster-scene/1"},
               {"requires", {"vertex_arrays"}},
               {"target", {{"width", 8}, {"height", 8}}},
               {"draws",
                {{{"primitive", "points"},
                  {"vertex_arrays",
                   {{"count", 1},
                    {"position", {{"components", 2}, {"values", {1, 1}}}},
                    {"texcoord", {{"components", 2}, {"values", {0, 0}}}}}}}}}};
    EXPECT_REFUSED(va, "draws[0].vertex_arrays.texcoord", "belongs to the extension \"textures\"");
    // With the extension the unknown-key message lists the extension's keys.
    va["requires"] = {"vertex_arrays", "textures"};
    EXPECT_NO_THROW((void)load(va));
    va["draws"][0]["vertex_arrays"]["texcoord"]["components"] = 3;
    EXPECT_REFUSED(va, "draws[0].vertex_arrays.texcoord.components",
                   "expected 2 ([s, t]) or 4 ([s, t, r, q]), got 3");
    va["draws"][0]["vertex_arrays"]["texcoord"] = {{"components", 4}, {"values", {0, 0, 0}}};
    EXPECT_REFUSED(va, "draws[0].vertex_arrays.texcoord.values",
                   "expected 4 numbers (count 1 x 4 components)");
}

TEST(TexturesRefusal, UnknownKeysAndBadValues) {
    const json one = {{"t", image_json(1, 1)}};
    json t = one;
    t["t"]["colour"] = 1;
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.colour",
                   "unknown key \"colour\" (allowed: width, height, data, file, levels, mipmaps)");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"name", "t"}, {"unit", 0}}}}),
                   "draws[0].state.texture.unit",
                   "(allowed: name, min_filter, mag_filter, wrap_s, wrap_t, border_color, env, "
                   "coord_replace, point_coord_origin)");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"min_filter", "linear"}}}}),
                   "draws[0].state.texture", "missing required key \"name\"");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"name", "t"}, {"wrap_s", "clamp"}}}}),
                   "draws[0].state.texture.wrap_s",
                   "expected one of repeat, clamp_to_edge, mirrored_repeat, clamp_to_border, got "
                   "\"clamp\"");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"name", "t"}, {"wrap_t", 1}}}}),
                   "draws[0].state.texture.wrap_t", "expected one of repeat");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"name", "t"}, {"min_filter", "bilinear"}}}}),
                   "draws[0].state.texture.min_filter",
                   "expected one of nearest, linear, nearest_mipmap_nearest, "
                   "linear_mipmap_nearest, nearest_mipmap_linear, linear_mipmap_linear, got "
                   "\"bilinear\"");
    EXPECT_REFUSED(
        scene_json(one, {{"texture", {{"name", "t"}, {"mag_filter", "linear_mipmap_linear"}}}}),
        "draws[0].state.texture.mag_filter", "expected one of nearest, linear, got");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"name", "t"}, {"env", "decal"}}}}),
                   "draws[0].state.texture.env",
                   "expected one of modulate, replace, got \"decal\"");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"name", "t"}, {"border_color", {0, 0, 0}}}}}),
                   "draws[0].state.texture.border_color", "four numbers [r, g, b, a]");
    EXPECT_REFUSED(scene_json(one, {{"texture", {{"name", "t"}, {"coord_replace", 1}}}}),
                   "draws[0].state.texture.coord_replace", "true or false");
    EXPECT_REFUSED(
        scene_json(one, {{"texture", {{"name", "t"}, {"point_coord_origin", "top_left"}}}}),
        "draws[0].state.texture.point_coord_origin",
        "expected one of upper_left, lower_left, got \"top_left\"");
    EXPECT_REFUSED(
        scene_json(one, {{"texture", {{"name", "t"}, {"border_color", {0, 0, 0, 1e39}}}}}),
        "draws[0].state.texture.border_color[3]", "does not fit in float32");
    t = one;
    t["t"]["mipmaps"] = "auto";
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.mipmaps", "expected one of generate");
    EXPECT_REFUSED(scene_json(json::array(), nullptr), "textures",
                   "expected an object of textures by name, got an array of 0");
    json tc = scene_json(one, nullptr);
    tc["draws"][0]["vertices"][0]["texcoord"] = {0, 0, 0};
    EXPECT_REFUSED(tc, "draws[0].vertices[0].texcoord",
                   "expected [s, t] or [s, t, r, q], got an array of 3");
    tc["draws"][0]["vertices"][0]["texcoord"] = json::array({0});
    EXPECT_REFUSED(tc, "draws[0].vertices[0].texcoord", "got an array of 1");
    tc["draws"][0]["vertices"][0]["texcoord"] = {0, 1e39};
    EXPECT_REFUSED(tc, "draws[0].vertices[0].texcoord[1]", "number 1e+39 does not fit in float32");
    tc["draws"][0]["vertices"][0]["texcoord"] = {0, "1"};
    EXPECT_REFUSED(tc, "draws[0].vertices[0].texcoord[1]", "expected a number");
}

TEST(TexturesRefusal, NamesAndMipmapFilters) {
    const json two = {{"a", image_json(2, 2)}, {"b", image_json(1, 1)}};
    EXPECT_REFUSED(scene_json(two, {{"texture", {{"name", "c"}}}}), "draws[0].state.texture.name",
                   "no texture named \"c\"; the scene defines \"a\", \"b\"");
    EXPECT_REFUSED(scene_json(nullptr, {{"texture", {{"name", "c"}}}}),
                   "draws[0].state.texture.name", "no texture named \"c\"; the scene defines none");
    EXPECT_REFUSED(
        scene_json(two, {{"texture", {{"name", "a"}, {"min_filter", "linear_mipmap_nearest"}}}}),
        "draws[0].state.texture.min_filter",
        "the filter \"linear_mipmap_nearest\" samples mipmaps, and the texture \"a\" has neither "
        "\"levels\" nor \"mipmaps\": \"generate\"");
    // A 1 x 1 texture too: it takes "mipmaps": "generate", never "levels".
    EXPECT_REFUSED(
        scene_json(two, {{"texture", {{"name", "b"}, {"min_filter", "nearest_mipmap_nearest"}}}}),
        "draws[0].state.texture.min_filter", "has neither");
    // The name in the second draw's path.
    json j = scene_json(two, {{"texture", {{"name", "a"}}}});
    j["draws"].push_back(j["draws"][0]);
    j["draws"][1]["state"]["texture"]["name"] = "A";
    EXPECT_REFUSED(j, "draws[1].state.texture.name", "no texture named \"A\"");
}

TEST(TexturesRefusal, SizesAndData) {
    json t = {{"t", image_json(2, 2)}};
    t["t"]["width"] = 3;
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.data",
                   "decodes to 16 bytes, expected 24 (width 3 x height 2 x 4 bytes of RGBA8 "
                   "texels)");
    t["t"]["width"] = 0;
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.width",
                   "expected an integer in [1, 4096], got 0");
    t["t"]["width"] = 4097;
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.width",
                   "expected an integer in [1, 4096], got 4097");
    t["t"]["width"] = 2;
    t["t"]["height"] = 1.5;
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.height", "expected an integer, got 1.5");
    t["t"].erase("height");
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t", "missing required key \"height\"");
    t = {{"t", image_json(2, 2)}};
    t["t"]["data"] = "AAAA*AAA";
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.data", "character 4 (\"*\") is not base64");
    t["t"]["data"] = "AAAAAAAAAAAAAAAAAAAAAB==";  // 16 bytes, the unused bits not zero
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.data", "are not zero");
    t["t"].erase("data");
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t",
                   "missing required key \"data\" (or \"file\")");
    t["t"]["data"] = image_json(2, 2)["data"];
    t["t"]["file"] = "x.png";
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.file",
                   "give either \"data\" or \"file\", not both");
}

TEST(TexturesRefusal, Levels) {
    const auto base = [](std::uint32_t w, std::uint32_t h) {
        json t = image_json(w, h);
        return t;
    };
    json t = {{"t", base(8, 4)}};
    t["t"]["levels"] = {image_json(4, 2), image_json(1, 1)};
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.levels[1].width",
                   "level 2 of a 8 x 4 texture is 2 x 1 (max(1, size >> 2)); got width 1");
    t["t"]["levels"] = {image_json(4, 3)};
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.levels[0].height",
                   "level 1 of a 8 x 4 texture is 4 x 2 (max(1, size >> 1)); got height 3");
    t["t"]["levels"] = {image_json(4, 2), image_json(2, 1), image_json(1, 1), image_json(1, 1)};
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.levels",
                   "expected an array of 1 to 3 levels (levels 1 to 3 of a 8 x 4 texture, down "
                   "to 1 x 1), got an array of 4");
    t["t"]["levels"] = json::array();
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.levels", "got an array of 0");
    t["t"]["levels"] = {image_json(4, 2)};
    t["t"]["levels"][0]["data"] = harness::base64_text(std::vector<std::uint8_t>(35));
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.levels[0].data",
                   "decodes to 35 bytes, expected 32");
    t["t"]["levels"] = {image_json(4, 2)};
    t["t"]["levels"][0]["mipmaps"] = "generate";
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.levels[0].mipmaps",
                   "unknown key \"mipmaps\" (allowed: width, height, data, file)");
    t["t"]["levels"] = {image_json(4, 2)};
    t["t"]["mipmaps"] = "generate";
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.mipmaps",
                   "give either \"levels\" or \"mipmaps\", not both");
    t = {{"t", base(1, 1)}};
    t["t"]["levels"] = {image_json(1, 1)};
    EXPECT_REFUSED(scene_json(t, nullptr), "textures.t.levels",
                   "a 1 x 1 texture has no levels below its base; leave out \"levels\"");
}

TEST(TexturesRefusal, Files) {
    TempDir dir("textures-bad");
    refraster::Framebuffer fb(4, 2, refraster::ColorFormat::Rgba8, refraster::DepthFormat::None);
    harness::write_color_image(fb, dir.path() / "four.png");
    refraster::Framebuffer big(4097, 1, refraster::ColorFormat::Rgba8,
                               refraster::DepthFormat::None);
    harness::write_color_image(big, dir.path() / "wide.png");
    dir.write("grey16.png", png_bytes(1, 1, 16, 0, {{0x12, 0x34}}));
    dir.write("grey1.png", png_bytes(8, 1, 1, 0, {{0xaa}}));
    dir.write("text.png", "not an image");
    refraster::Framebuffer f32(1, 1, refraster::ColorFormat::Rgba32f, refraster::DepthFormat::None);
    harness::write_color_image(f32, dir.path() / "float.exr");
    const std::string label = (dir.path() / "scene.json").string();
    const auto refused = [&](const json& texture, const std::string& path,
                             const std::string& detail) {
        const SceneError e = refusal(scene_json({{"t", texture}}, nullptr), label);
        EXPECT_EQ(e.json_path(), path) << e.what();
        EXPECT_NE(e.detail().find(detail), std::string::npos) << e.what();
    };
    const std::string d = dir.path().string() + "/";
    refused({{"file", "missing.png"}}, "textures.t.file", unusable("missing.png"));
    refused({{"file", "."}}, "textures.t.file", unusable("."));
    refused({{"file", ""}}, "textures.t.file", "expected the path of a PNG file");
    refused({{"file", "four.png"}, {"width", 2}}, "textures.t.file",
            d + "four.png is 4 x 2 pixels, but \"width\" is 2");
    refused({{"file", "four.png"}, {"height", 4}}, "textures.t.file",
            d + "four.png is 4 x 2 pixels, but \"height\" is 4");
    refused({{"file", "wide.png"}}, "textures.t.file",
            d + "wide.png is 4097 x 1 pixels; a texture is 1 to 4096 pixels a side");
    refused({{"file", "grey16.png"}}, "textures.t.file",
            d + "grey16.png: 16-bit channels; textures are read from PNGs of 8-bit channels");
    refused({{"file", "grey1.png"}}, "textures.t.file", "grey1.png: 1-bit channels");
    refused({{"file", "text.png"}}, "textures.t.file", unusable("text.png"));
    refused({{"file", "float.exr"}}, "textures.t.file", unusable("float.exr"));
    json level = {{"width", 8}, {"height", 4}, {"data", image_json(8, 4)["data"]}};
    level["levels"] = {{{"file", "four.png"}}, {{"file", "missing.png"}}};
    refused(level, "textures.t.levels[1].file", unusable("missing.png"));
    level["levels"] = {{{"file", "four.png"}}, {{"file", "four.png"}}};
    refused(level, "textures.t.levels[1].file",
            "level 2 of a 8 x 4 texture is 2 x 1 (max(1, size >> 2)); " + d + "four.png is 4 x 2");
    level["levels"] = {{{"file", "four.png"}, {"width", 4}, {"height", 2}}};
    EXPECT_NO_THROW((void)load(scene_json({{"t", level}}, nullptr), label));
    // Through the CLI: exit code 2, one line naming the scene file and the path.
    const auto scene =
        dir.write("scene.json", scene_json({{"t", {{"file", "missing.png"}}}}, nullptr).dump());
    const auto r = testutil::run_cli(
        {"render", scene.string(), "--backend", "ref", "-o", (dir.path() / "out.png").string()});
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.err, scene.string() + ": textures.t.file: " + unusable("missing.png") + "\n");
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "out.png"));
}

// ---- which files a scene may read (docs/scene-format.md, "Texture files")

// A 1 x 1 RGBA PNG whose texel is (r, 0, 0, 255).
std::string red_png(std::uint8_t r) {
    return png_bytes(1, 1, 8, 6, {{r, 0, 0, 255}});
}

// What the texture file `file` loads as in a scene labelled `label`: "texel R" (its red), or
// the refusal's detail (after its JSON path when that is not "textures.t.file").
std::string outcome(const std::string& file, const std::string& label,
                    const harness::SceneLimits& limits = {}) {
    try {
        const auto s = load(scene_json({{"t", {{"file", file}}}}, nullptr), label, limits);
        return "texel " + std::to_string(s.file.textures.at("t").levels[0].rgba[0]);
    } catch (const SceneError& e) {
        return e.json_path() == "textures.t.file" ? e.detail() : e.json_path() + ": " + e.detail();
    }
}

// A scene reads files whose real path lies under its folder's real path, however they are
// named; `..`, absolute paths and symlinks that lead elsewhere are refused exactly like a file
// that does not exist. A texture root widens the folder.
TEST(TextureFiles, OnlyUnderTheScenesFolderOrTheTextureRoot) {
    TempDir dir("texture-files");
    const auto top = dir.path();
    std::filesystem::create_directories(top / "scene" / "sub");
    std::filesystem::create_directories(top / "other");
    dir.write("outside.png", red_png(1));
    dir.write("scene/in.png", red_png(2));
    dir.write("scene/sub/deeper.png", red_png(3));
    dir.write("other/o.png", red_png(4));
    std::filesystem::create_symlink(top / "outside.png", top / "scene" / "link_out.png");
    std::filesystem::create_symlink("in.png", top / "scene" / "link_in.png");
    std::filesystem::create_symlink(top, top / "scene" / "up");  // a folder leading out
    const std::string label = (top / "scene" / "scene.json").string();
    EXPECT_EQ(outcome("in.png", label), "texel 2");
    EXPECT_EQ(outcome("sub/deeper.png", label), "texel 3");
    EXPECT_EQ(outcome("sub/../in.png", label), "texel 2");
    EXPECT_EQ(outcome("./link_in.png", label), "texel 2");
    EXPECT_EQ(outcome("up/scene/in.png", label), "texel 2");  // out and back in: inside
    EXPECT_EQ(outcome((top / "scene" / "in.png").string(), label), "texel 2");
    const std::vector<std::string> elsewhere = {"../outside.png",
                                                (top / "outside.png").string(),
                                                "link_out.png",
                                                "up/outside.png",
                                                "sub/../../outside.png",
                                                "../other/o.png",
                                                "/etc/passwd",
                                                "/dev/zero",
                                                "missing.png",
                                                "../missing.png",
                                                "sub",
                                                "/"};
    for (const auto& f : elsewhere) EXPECT_EQ(outcome(f, label), unusable(f)) << f;

    // The root widens the scene's folder; relative names still start from the scene's folder.
    harness::SceneLimits wide;
    wide.texture_root = top;
    EXPECT_EQ(outcome("../outside.png", label, wide), "texel 1");
    EXPECT_EQ(outcome((top / "outside.png").string(), label, wide), "texel 1");
    EXPECT_EQ(outcome("link_out.png", label, wide), "texel 1");
    EXPECT_EQ(outcome("../other/o.png", label, wide), "texel 4");
    EXPECT_EQ(outcome("in.png", label, wide), "texel 2");
    EXPECT_EQ(outcome("/etc/passwd", label, wide), unusable("/etc/passwd"));
    harness::SceneLimits other;
    other.texture_root = top / "other";
    EXPECT_EQ(outcome("../other/o.png", label, other), "texel 4");
    EXPECT_EQ(outcome("in.png", label, other), "texel 2");
    EXPECT_EQ(outcome("../outside.png", label, other), unusable("../outside.png"));
    // A root given through a symlink is its real path.
    std::filesystem::create_symlink(top / "other", top / "other_link");
    other.texture_root = top / "other_link";
    EXPECT_EQ(outcome("../other/o.png", label, other), "texel 4");
}

// Every file under the folder that cannot be used gets the same message, whatever the reason:
// the message never tells a missing file from one that exists.
TEST(TextureFiles, EveryUnusableFileGetsTheSameMessage) {
    TempDir dir("texture-unusable");
    std::filesystem::create_directories(dir.path() / "folder.png");
    ASSERT_EQ(::mkfifo((dir.path() / "fifo.png").c_str(), 0600), 0);
    dir.write("text.png", "not an image");
    dir.write("empty.png", "");
    refraster::Framebuffer f32(1, 1, refraster::ColorFormat::Rgba32f, refraster::DepthFormat::None);
    harness::write_color_image(f32, dir.path() / "float.exr");
    std::filesystem::copy_file(dir.path() / "float.exr", dir.path() / "exr_named.png");
    const std::string good = red_png(9);
    dir.write("signature_only.png", good.substr(0, 8));
    dir.write("cut.png", good.substr(0, good.size() - 20));  // inside IDAT
    // Headers PNG does not allow, with their right CRCs.
    dir.write("zero_width.png", png_bytes(0, 1, 8, 6, {{}}));
    dir.write("bad_type.png", png_bytes(1, 1, 8, 5, {{1, 2}}));
    dir.write("bad_depth.png", png_bytes(1, 1, 3, 6, {{1, 2, 3, 4}}));
    std::string bad_crc = good;
    bad_crc[29] = static_cast<char>(bad_crc[29] ^ 1);  // IHDR's CRC
    dir.write("bad_crc.png", bad_crc);
    std::string bad_zlib = good;
    bad_zlib[33 + 8] = 0x7f;  // IDAT's zlib header
    dir.write("bad_zlib.png", bad_zlib);
    dir.write("no_idat.png", good.substr(0, 33) + good.substr(good.size() - 12));
    // Index 2 of a palette of two.
    dir.write("past_palette.png",
              png_bytes(3, 1, 8, 3, {{0, 1, 2}}, {{"PLTE", {1, 2, 3, 4, 5, 6}}}));
    const std::string label = (dir.path() / "scene.json").string();
    for (const std::string f :
         {"missing.png", "folder.png", "fifo.png", "text.png", "empty.png", "float.exr",
          "exr_named.png", "signature_only.png", "cut.png", "zero_width.png", "bad_type.png",
          "bad_depth.png", "bad_crc.png", "bad_zlib.png", "no_idat.png", "past_palette.png"}) {
        EXPECT_EQ(outcome(f, label), unusable(f)) << f;
    }
    EXPECT_EQ(outcome("good.png", label), unusable("good.png"));
    dir.write("good.png", good);
    EXPECT_EQ(outcome("good.png", label), "texel 9");
    if (::geteuid() != 0) {  // root reads any file
        std::filesystem::permissions(dir.path() / "good.png", std::filesystem::perms::none);
        EXPECT_EQ(outcome("good.png", label), unusable("good.png"));
    }
}

// A scene held in a string reads under the folder of its label, the working directory when the
// label names none.
TEST(TextureFiles, SceneTextReadsUnderItsLabelsFolder) {
    TempDir dir("texture-text");
    std::filesystem::create_directories(dir.path() / "work");
    dir.write("outside.png", red_png(1));
    dir.write("work/in.png", red_png(2));
    EXPECT_EQ(outcome("in.png", (dir.path() / "work" / "s.json").string()), "texel 2");
    EXPECT_EQ(outcome("../outside.png", (dir.path() / "work" / "s.json").string()),
              unusable("../outside.png"));
    const auto cwd = std::filesystem::current_path();
    std::filesystem::current_path(dir.path() / "work");
    const std::string in = outcome("in.png", "tex.json");
    const std::string out = outcome("../outside.png", "tex.json");
    std::filesystem::current_path(cwd);
    EXPECT_EQ(in, "texel 2");
    EXPECT_EQ(out, unusable("../outside.png"));
}

// The header's size and channels, and the file's size, are checked before any decoder runs:
// a file whose pixels could not be decoded is refused for its size first.
TEST(TextureFiles, HeaderAndFileSizeBeforeDecoding) {
    TempDir dir("texture-header");
    const std::string label = (dir.path() / "scene.json").string();
    const std::string d = dir.path().string() + "/";
    // Headers followed by no image data at all.
    const std::string wide = png_bytes(4097, 1, 8, 6, {{0}});
    dir.write("wide.png", wide.substr(0, 33) + wide.substr(wide.size() - 12));
    EXPECT_EQ(outcome("wide.png", label),
              d + "wide.png is 4097 x 1 pixels; a texture is 1 to 4096 pixels a side");
    const std::string deep = png_bytes(1, 1, 16, 6, {{0}});
    dir.write("deep.png", deep.substr(0, 33) + deep.substr(deep.size() - 12));
    EXPECT_EQ(outcome("deep.png", label),
              d + "deep.png: 16-bit channels; textures are read from PNGs of 8-bit channels");
    harness::SceneLimits limits;
    limits.max_texel_bytes = 8;
    const std::string square = png_bytes(2, 2, 8, 6, {{0}});
    dir.write("square.png", square.substr(0, 33) + square.substr(square.size() - 12));
    EXPECT_EQ(
        outcome("square.png", label, limits),
        "textures.t: this brings the scene's textures to 16 bytes of texels, over the limit of 8 "
        "(docs/limits.md)");
    // The file's size: a PNG over the limit is refused before it is read; anything else is not
    // a PNG first.
    const std::string good = red_png(5);
    dir.write("good.png", good);
    dir.write("text.png", std::string(good.size() + 1, 'x'));
    limits = {};
    limits.max_texture_file_bytes = good.size();
    EXPECT_EQ(outcome("good.png", label, limits), "texel 5");
    limits.max_texture_file_bytes = good.size() - 1;
    EXPECT_EQ(outcome("good.png", label, limits),
              d + "good.png is a file of " + std::to_string(good.size()) +
                  " bytes, over the limit of " + std::to_string(good.size() - 1) +
                  " for a texture file (docs/limits.md)");
    EXPECT_EQ(outcome("text.png", label, limits), unusable("text.png"));
    EXPECT_EQ(harness::SceneLimits{}.max_texture_file_bytes, std::uint64_t{1} << 27);
}

// PNG transparency: tRNS makes RGB and grey pixels of its colour transparent and gives palette
// entries their alpha (255 past its end); the texels are what every backend uploads.
TEST(TextureFiles, TransparencyAsPngMeansIt) {
    TempDir dir("texture-trns");
    dir.write("rgb.png",
              png_bytes(3, 1, 8, 2, {{1, 2, 3, 4, 5, 6, 4, 5, 7}}, {{"tRNS", {0, 4, 0, 5, 0, 6}}}));
    dir.write("grey.png", png_bytes(2, 1, 8, 0, {{7, 9}}, {{"tRNS", {0, 9}}}));
    dir.write("palette.png",
              png_bytes(3, 1, 8, 3, {{0, 1, 2}},
                        {{"PLTE", {10, 11, 12, 20, 21, 22, 30, 31, 32}}, {"tRNS", {0, 128}}}));
    // Two bits an index, four pixels in one byte: 0, 1, 2, 3.
    dir.write("palette2.png",
              png_bytes(4, 1, 2, 3, {{0x1b}}, {{"PLTE", {1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4}}}));
    dir.write("rgb_plain.png", png_bytes(1, 1, 8, 2, {{4, 5, 6}}));
    const json t = {{"rgb", {{"file", "rgb.png"}}},
                    {"grey", {{"file", "grey.png"}}},
                    {"palette", {{"file", "palette.png"}}},
                    {"palette2", {{"file", "palette2.png"}}},
                    {"rgb_plain", {{"file", "rgb_plain.png"}}}};
    const auto s = load(scene_json(t, nullptr), (dir.path() / "scene.json").string());
    using Texels = std::vector<std::uint8_t>;
    EXPECT_EQ(s.file.textures.at("rgb").levels[0].rgba,
              (Texels{1, 2, 3, 255, 4, 5, 6, 0, 4, 5, 7, 255}));
    EXPECT_EQ(s.file.textures.at("grey").levels[0].rgba, (Texels{7, 7, 7, 255, 9, 9, 9, 0}));
    EXPECT_EQ(s.file.textures.at("palette").levels[0].rgba,
              (Texels{10, 11, 12, 0, 20, 21, 22, 128, 30, 31, 32, 255}));
    EXPECT_EQ(s.file.textures.at("palette2").levels[0].rgba,
              (Texels{1, 1, 1, 255, 2, 2, 2, 255, 3, 3, 3, 255, 4, 4, 4, 255}));
    EXPECT_EQ(s.file.textures.at("rgb_plain").levels[0].rgba, (Texels{4, 5, 6, 255}));
    // What the backends get: the draw list's texels, the same as the file's.
    EXPECT_EQ(s.draw_list.textures[s.draw_list.textures.size() - 1].levels[0].rgba,
              s.file.textures.at("rgb_plain").levels[0].rgba);
}

// libpng's own messages never reach stderr: the CLI prints the project's one line only.
TEST(TextureFiles, CliPrintsOneLineForAFileLibpngRefuses) {
    TempDir dir("texture-cli");
    const std::string good = red_png(9);
    dir.write("bad_ihdr.png", png_bytes(1, 1, 3, 6, {{1, 2, 3, 4}}));  // bit depth 3
    std::string bad_crc = good;
    bad_crc[29] = static_cast<char>(bad_crc[29] ^ 1);
    dir.write("bad_crc.png", bad_crc);
    std::string bad_zlib = good;
    bad_zlib[33 + 8] = 0x7f;
    dir.write("bad_zlib.png", bad_zlib);
    for (const std::string f : {"bad_ihdr.png", "bad_crc.png", "bad_zlib.png"}) {
        const auto scene =
            dir.write("scene.json", scene_json({{"t", {{"file", f}}}}, nullptr).dump());
        const auto r = testutil::run_cli({"check", scene.string()});
        EXPECT_EQ(r.exit_code, 2) << f;
        EXPECT_EQ(r.err, scene.string() + ": textures.t.file: " + unusable(f) + "\n") << f;
    }
}

TEST(TexturesRefusal, Limits) {
    harness::SceneLimits limits;
    limits.max_textures = 2;
    json t = {{"a", image_json(1, 1)}, {"b", image_json(1, 1)}};
    EXPECT_NO_THROW((void)load(scene_json(t, nullptr), "tex.json", limits));
    t["c"] = image_json(1, 1);
    SceneError e = refusal(scene_json(t, nullptr), "tex.json", limits);
    EXPECT_EQ(e.json_path(), "textures");
    EXPECT_EQ(e.detail(), "3 textures exceed the limit of 2 textures a scene (docs/limits.md)");

    limits = {};
    limits.max_texel_bytes = 100;
    t = {{"a", image_json(4, 4)}, {"b", image_json(2, 2)}};  // 64 + 16 bytes
    EXPECT_NO_THROW((void)load(scene_json(t, nullptr), "tex.json", limits));
    t["b"]["mipmaps"] = "generate";  // 4 more bytes (1 x 1)
    EXPECT_NO_THROW((void)load(scene_json(t, nullptr), "tex.json", limits));
    t["c"] = image_json(3, 2);
    e = refusal(scene_json(t, nullptr), "tex.json", limits);
    EXPECT_EQ(e.json_path(), "textures.c");
    EXPECT_EQ(e.detail(),
              "this brings the scene's textures to 108 bytes of texels, over the limit of 100 "
              "(docs/limits.md)");
    // Generated levels count where "mipmaps" asks for them.
    limits.max_texel_bytes = 80;
    t.erase("c");
    e = refusal(scene_json(t, nullptr), "tex.json", limits);
    EXPECT_EQ(e.json_path(), "textures.b.mipmaps");
    EXPECT_EQ(harness::SceneLimits{}.max_textures, 256u);
    EXPECT_EQ(harness::SceneLimits{}.max_texel_bytes, std::uint64_t{1} << 30);
}

}  // namespace
