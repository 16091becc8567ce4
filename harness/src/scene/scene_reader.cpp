// Scene format v1 reader: a validating walk that turns the strict JSON layer's document
// (strict_json.hpp) into a SceneFile, naming the JSON path of the first offending value, and
// the work limits of SceneLimits (docs/limits.md).
#include <simdjson.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <system_error>

#include "harness/front_end.hpp"
#include "harness/scene.hpp"
#include "refraster/renderer.hpp"
#include "strict_json.hpp"

namespace harness {

namespace {

using namespace strict_json;

// Limits from scene format v1, section "Limits and remaining semantics".
constexpr std::int64_t kMaxTargetSide = 16384;
constexpr std::int64_t kMaxTargetSamplesArea = 67'108'864;
constexpr std::int64_t kViewportOriginMin = -32768;
constexpr std::int64_t kViewportOriginMax = 32767;
// The format bounds scissor sizes only below; this bound keeps x + width inside int32.
constexpr std::int64_t kScissorLimit = std::int64_t{1} << 30;

// The extension "textures": textures by name, texture coordinates and the draw state key
// "texture" (docs/scene-format.md).
constexpr std::string_view kTexturesExtension = "textures";
constexpr std::int64_t kMaxTextureSide = 4096;

// A key that only an extension listed in "requires" allows.
[[noreturn]] void refuse_extension_key(const Node& v, std::string_view key,
                                       std::string_view extension) {
    v.fail("the key \"" + std::string(key) + "\" belongs to the extension \"" +
           std::string(extension) + "\"; list it in \"requires\" to use it");
}

// What a draw may say about textures: whether "requires" lists "textures", and the textures
// the file defines.
struct TextureScope {
    bool allowed = false;
    const std::map<std::string, refraster::Texture>* defined = nullptr;
};

// The extension "polygons": the primitive "polygon" (GL_POLYGON) and the draw state key
// "fill_rule" (docs/scene-format.md).
constexpr std::string_view kPolygonsExtension = "polygons";

refraster::Rect read_rect(const Node& n, std::int64_t origin_lo, std::int64_t origin_hi,
                          std::int64_t size_lo, std::int64_t size_hi) {
    n.array_size(4, 4, "[x, y, width, height]");
    return {static_cast<std::int32_t>(n[0].integer(origin_lo, origin_hi)),
            static_cast<std::int32_t>(n[1].integer(origin_lo, origin_hi)),
            static_cast<std::int32_t>(n[2].integer(size_lo, size_hi)),
            static_cast<std::int32_t>(n[3].integer(size_lo, size_hi))};
}

std::array<float, 4> read_color(const Node& n) {
    n.array_size(4, 4, "four numbers [r, g, b, a]");
    return {n[0].f32(), n[1].f32(), n[2].f32(), n[3].f32()};
}

// A vertex's "texcoord": [s, t] (r = 0, q = 1) or [s, t, r, q], each number as a colour's.
std::array<float, 4> read_texcoord(const Node& n) {
    const std::size_t size = n.array_size(2, 4, "[s, t] or [s, t, r, q]");
    if (size == 3) n.fail("expected [s, t] or [s, t, r, q], got an array of 3");
    std::array<float, 4> t{0.0f, 0.0f, 0.0f, 1.0f};
    std::size_t k = 0;
    n.for_each([&](const Node& e) { t[k++] = e.f32(); });
    return t;
}

// The draw state key "texture": texture unit 0. `name` receives the texture's name.
refraster::TextureState read_texture_state(const Node& n,
                                           const std::map<std::string, refraster::Texture>& defined,
                                           std::string& name) {
    using namespace refraster;
    n.require_object({"name", "min_filter", "mag_filter", "wrap_s", "wrap_t", "border_color", "env",
                      "coord_replace", "point_coord_origin"});
    TextureState t;
    const Node name_node = n.at("name");
    const auto it = defined.find(name_node.string());
    if (it == defined.end()) {
        std::string known;
        std::size_t listed = 0;
        for (const auto& [k, _] : defined) {
            if (listed == 8) {
                known += ", ... (" + std::to_string(defined.size()) + " in all)";
                break;
            }
            known += (listed++ == 0 ? "" : ", ") + quoted_value(k);
        }
        name_node.fail("no texture named " + quoted_value(name_node.string_view()) +
                       (defined.empty() ? std::string("; the scene defines none (\"textures\")")
                                        : "; the scene defines " + known));
    }
    name = it->first;
    t.texture = static_cast<std::uint32_t>(std::distance(defined.begin(), it));
    if (auto v = n.get("min_filter")) {
        t.min_filter = v->choice<TextureFilter>(
            {{"nearest", TextureFilter::Nearest},
             {"linear", TextureFilter::Linear},
             {"nearest_mipmap_nearest", TextureFilter::NearestMipmapNearest},
             {"linear_mipmap_nearest", TextureFilter::LinearMipmapNearest},
             {"nearest_mipmap_linear", TextureFilter::NearestMipmapLinear},
             {"linear_mipmap_linear", TextureFilter::LinearMipmapLinear}});
        const Texture& tex = it->second;
        if (uses_mipmaps(t.min_filter) && tex.levels.size() == 1 && !tex.generate_mipmaps) {
            v->fail("the filter " + quoted_value(v->string_view()) +
                    " samples mipmaps, and the texture " + quoted_value(it->first) +
                    " has neither \"levels\" nor \"mipmaps\": \"generate\"");
        }
    }
    if (auto v = n.get("mag_filter")) {
        t.mag_filter = v->choice<TextureFilter>(
            {{"nearest", TextureFilter::Nearest}, {"linear", TextureFilter::Linear}});
    }
    const auto wrap = [](const Node& v) {
        return v.choice<TextureWrap>({{"repeat", TextureWrap::Repeat},
                                      {"clamp_to_edge", TextureWrap::ClampToEdge},
                                      {"mirrored_repeat", TextureWrap::MirroredRepeat},
                                      {"clamp_to_border", TextureWrap::ClampToBorder}});
    };
    if (auto v = n.get("wrap_s")) t.wrap_s = wrap(*v);
    if (auto v = n.get("wrap_t")) t.wrap_t = wrap(*v);
    if (auto v = n.get("border_color")) t.border_color = read_color(*v);
    if (auto v = n.get("env")) {
        t.env = v->choice<TextureEnv>(
            {{"modulate", TextureEnv::Modulate}, {"replace", TextureEnv::Replace}});
    }
    if (auto v = n.get("coord_replace")) t.coord_replace = v->boolean();
    if (auto v = n.get("point_coord_origin")) {
        t.point_coord_origin =
            v->choice<PointCoordOrigin>({{"upper_left", PointCoordOrigin::UpperLeft},
                                         {"lower_left", PointCoordOrigin::LowerLeft}});
    }
    return t;
}

// A draw's "state". `texture_name` receives the name of the texture it samples, if any.
refraster::DrawState read_state(const Node& n, const refraster::Target& target,
                                const TextureScope& textures, bool polygons,
                                std::string& texture_name) {
    using namespace refraster;
    DrawState s;
    s.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                  static_cast<std::int32_t>(target.height)};
    if (!textures.allowed && n.is_object()) {
        if (auto v = n.get("texture")) refuse_extension_key(*v, "texture", kTexturesExtension);
    }
    if (!polygons && n.is_object()) {
        if (auto v = n.get("fill_rule")) refuse_extension_key(*v, "fill_rule", kPolygonsExtension);
    }
    std::vector<std::string_view> keys{"viewport",     "depth_range",    "scissor",
                                       "cull",         "front_face",     "depth_test",
                                       "depth_write",  "shade",          "provoking_vertex",
                                       "polygon_mode", "polygon_offset", "line_width",
                                       "point_size",   "blend",          "multisample"};
    if (textures.allowed) keys.push_back("texture");
    if (polygons) keys.push_back("fill_rule");
    n.require_object(keys);
    if (auto v = n.get("viewport")) {
        s.viewport = read_rect(*v, kViewportOriginMin, kViewportOriginMax, 1, kMaxTargetSide);
    }
    if (auto v = n.get("depth_range")) {
        v->array_size(2, 2, "[near, far]");
        s.depth_near = (*v)[0].f32_in(0.0f, 1.0f);
        s.depth_far = (*v)[1].f32_in(0.0f, 1.0f);
    }
    if (auto v = n.get("scissor"); v && !v->is_null()) {
        s.scissor = read_rect(*v, -kScissorLimit, kScissorLimit, 0, kScissorLimit);
    }
    if (auto v = n.get("cull")) {
        s.cull = v->choice<CullMode>({{"none", CullMode::None},
                                      {"front", CullMode::Front},
                                      {"back", CullMode::Back},
                                      {"front_and_back", CullMode::FrontAndBack}});
    }
    if (auto v = n.get("front_face")) {
        s.front_face = v->choice<FrontFace>({{"ccw", FrontFace::Ccw}, {"cw", FrontFace::Cw}});
    }
    if (auto v = n.get("depth_test"); v && !v->is_null()) {
        s.depth_test = v->choice<CompareFunc>({{"never", CompareFunc::Never},
                                               {"less", CompareFunc::Less},
                                               {"equal", CompareFunc::Equal},
                                               {"lequal", CompareFunc::Lequal},
                                               {"greater", CompareFunc::Greater},
                                               {"notequal", CompareFunc::NotEqual},
                                               {"gequal", CompareFunc::Gequal},
                                               {"always", CompareFunc::Always}});
    }
    if (auto v = n.get("depth_write")) s.depth_write = v->boolean();
    if (auto v = n.get("shade")) {
        s.shade = v->choice<ShadeModel>({{"smooth", ShadeModel::Smooth},
                                         {"flat", ShadeModel::Flat},
                                         {"noperspective", ShadeModel::NoPerspective}});
    }
    if (auto v = n.get("provoking_vertex")) {
        s.provoking_vertex = v->choice<ProvokingVertex>(
            {{"last", ProvokingVertex::Last}, {"first", ProvokingVertex::First}});
    }
    if (auto v = n.get("polygon_mode")) {
        s.polygon_mode = v->choice<PolygonMode>({{"fill", PolygonMode::Fill},
                                                 {"line", PolygonMode::Line},
                                                 {"point", PolygonMode::Point}});
    }
    if (auto v = n.get("polygon_offset"); v && !v->is_null()) {
        v->require_object({"factor", "units"});
        s.polygon_offset = PolygonOffset{v->at("factor").f32(), v->at("units").f32()};
    }
    // Any width and size in (0, 255]: GL clamps what is below 1 to the implementation's
    // ALIASED_LINE_WIDTH_RANGE and POINT_SIZE_RANGE (1..255 in llvmpipe), so they draw as 1.
    if (auto v = n.get("line_width")) s.line_width = v->f32_above(0.0f, 255.0f);
    if (auto v = n.get("point_size")) s.point_size = v->f32_above(0.0f, 255.0f);
    if (auto v = n.get("blend"); v && !v->is_null()) {
        s.blend =
            v->choice<BlendPreset>({{"alpha", BlendPreset::Alpha}, {"add", BlendPreset::Add}});
    }
    // GL_MULTISAMPLE; an addition to format v1, allowed without "requires".
    if (auto v = n.get("multisample")) s.multisample = v->boolean();
    if (textures.allowed) {
        if (auto v = n.get("texture"); v && !v->is_null()) {
            s.texture = read_texture_state(*v, *textures.defined, texture_name);
        }
    }
    if (polygons) {
        if (auto v = n.get("fill_rule"); v && !v->is_null()) {
            s.fill_rule = v->choice<FillRule>(
                {{"evenodd", FillRule::EvenOdd}, {"nonzero", FillRule::NonZero}});
        }
    }
    return s;
}

// What the draws read so far ask for, against SceneLimits.
struct WorkSoFar {
    const SceneLimits& limits;
    std::uint64_t vertices = 0;
    std::uint64_t indices = 0;
    std::uint64_t primitives = 0;

    // Adds `count` to `total`; refuses at `where` when that passes `limit`.
    static void add(const Node& where, std::uint64_t& total, std::uint64_t count,
                    std::uint64_t limit, const char* what) {
        total += count;
        if (total > limit) {
            where.fail("this brings the scene to " + std::to_string(total) + " " + what +
                       ", over the limit of " + std::to_string(limit) + " (docs/limits.md)");
        }
    }
};

// Base64 (RFC 4648, section 4: A-Z a-z 0-9 + /, padded with '=' to a multiple of four
// characters) of the "vertex_arrays" extension, decoded strictly: no whitespace, no other
// alphabet, padding only at the end and its unused bits zero, so that one byte string has
// one spelling. Refusals name the string's path and the character's offset.
constexpr std::uint8_t kNotBase64 = 0x80;
constexpr auto kBase64Values = [] {
    std::array<std::uint8_t, 256> t{};
    t.fill(kNotBase64);
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (std::uint8_t i = 0; i < 64; ++i) t[static_cast<unsigned char>(alphabet[i])] = i;
    return t;
}();

std::string describe_character(std::string_view s, std::size_t at) {
    const auto u = static_cast<unsigned char>(s[at]);
    if (u >= 0x80) {
        char buf[16];
        std::snprintf(buf, sizeof buf, "byte 0x%02X", u);
        return buf;
    }
    return quoted_value(s.substr(at, 1));
}

// The bytes `s` decodes to when it is well formed: 3 a group of four characters, less the
// padding; 0 for a length that is no multiple of 4.
std::size_t base64_decoded_size(std::string_view s) {
    if (s.size() % 4 != 0) return 0;
    std::size_t pad = 0;
    if (!s.empty() && s.back() == '=') pad = s[s.size() - 2] == '=' ? 2 : 1;
    return s.size() / 4 * 3 - pad;
}

// Decodes `s` into `out`, which has room for s.size() / 4 * 3 bytes; returns the bytes written.
std::size_t decode_base64_into(const Node& n, std::string_view s, std::uint8_t* out) {
    if (s.size() % 4 != 0) {
        n.fail("base64 text of " + std::to_string(s.size()) +
               " characters; expected a multiple of 4 (padded with '=')");
    }
    std::size_t pad = 0;
    if (!s.empty() && s.back() == '=') pad = s[s.size() - 2] == '=' ? 2 : 1;
    const std::size_t body = s.size() - pad;
    const auto* in = reinterpret_cast<const unsigned char*>(s.data());
    const auto bad_character = [&](std::size_t from, std::size_t to) {
        for (std::size_t k = from; k < to; ++k) {
            if (kBase64Values[in[k]] == kNotBase64) {
                n.fail("character " + std::to_string(k) + " (" + describe_character(s, k) + ")" +
                       (s[k] == '=' ? " is padding before the end" : " is not base64"));
            }
        }
    };
    // Whole groups of four characters, then the last one with its padding.
    const std::size_t whole = pad == 0 ? s.size() : s.size() - 4;
    std::size_t o = 0;
    for (std::size_t i = 0; i < whole; i += 4, o += 3) {
        const std::uint8_t a = kBase64Values[in[i]];
        const std::uint8_t b = kBase64Values[in[i + 1]];
        const std::uint8_t c = kBase64Values[in[i + 2]];
        const std::uint8_t d = kBase64Values[in[i + 3]];
        if (((a | b | c | d) & kNotBase64) != 0) bad_character(i, i + 4);
        const std::uint32_t v =
            (std::uint32_t{a} << 18) | (std::uint32_t{b} << 12) | (std::uint32_t{c} << 6) | d;
        out[o] = static_cast<std::uint8_t>(v >> 16);
        out[o + 1] = static_cast<std::uint8_t>(v >> 8);
        out[o + 2] = static_cast<std::uint8_t>(v);
    }
    if (pad != 0) {
        bad_character(whole, body);
        std::uint32_t v = 0;
        for (std::size_t k = whole; k < body; ++k) v = (v << 6) | kBase64Values[in[k]];
        const std::size_t bytes = 3 - pad;
        const std::uint32_t unused_bits = pad == 2 ? 4 : 2;
        if ((v & ((1u << unused_bits) - 1)) != 0) {
            n.fail(
                "the bits below the last byte, before the padding, are not zero (base64 "
                "has one spelling of each byte string)");
        }
        v >>= unused_bits;
        for (std::size_t k = 0; k < bytes; ++k) {
            out[o + k] = static_cast<std::uint8_t>(v >> (8 * (bytes - 1 - k)));
        }
        o += bytes;
    }
    return o;
}

std::vector<std::uint8_t> decode_base64(const Node& n, std::string_view s) {
    std::vector<std::uint8_t> out(s.size() / 4 * 3);
    out.resize(decode_base64_into(n, s, out.data()));
    return out;
}

std::uint32_t little_endian_u32(const std::uint8_t* p) {
    return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
           (std::uint32_t{p[3]} << 24);
}

// The extension "vertex_arrays": a draw's vertices as one flat array per attribute.
constexpr std::string_view kVertexArraysExtension = "vertex_arrays";

// One attribute of "vertex_arrays" ({"components": N, "values": [...]} or {"components": N,
// "float32_base64": "..."}): count x components float32 values, vertex after vertex. Every
// value is checked as a number of a plain vertex is: rounded once to float32 and finite; in
// window space with four components, w > 0 as well.
struct AttributeArray {
    std::uint32_t components = 0;
    std::vector<float> values;
};

enum class AttributeKind : std::uint8_t { Position, Color, Texcoord };

AttributeArray read_attribute(const Node& a, std::size_t count, AttributeKind kind,
                              VertexSpace space) {
    const bool is_position = kind == AttributeKind::Position;
    AttributeArray out;
    a.require_object({"components", "values", "float32_base64"});
    {
        const Node c = a.at("components");
        if (kind == AttributeKind::Texcoord) {
            const auto n = c.integer(std::numeric_limits<std::int64_t>::min(),
                                     std::numeric_limits<std::int64_t>::max());
            if (n != 2 && n != 4) {
                c.fail("expected 2 ([s, t]) or 4 ([s, t, r, q]), got " + number_text(c.value()));
            }
            out.components = static_cast<std::uint32_t>(n);
        } else if (!is_position) {
            if (c.integer(std::numeric_limits<std::int64_t>::min(),
                          std::numeric_limits<std::int64_t>::max()) != 4) {
                c.fail("expected 4 ([r, g, b, a]), got " + number_text(c.value()));
            }
            out.components = 4;
        } else if (space == VertexSpace::Clip) {
            if (c.integer(std::numeric_limits<std::int64_t>::min(),
                          std::numeric_limits<std::int64_t>::max()) != 4) {
                c.fail("expected 4 ([x, y, z, w], space \"clip\"), got " + number_text(c.value()));
            }
            out.components = 4;
        } else {
            out.components = static_cast<std::uint32_t>(c.integer(2, 4));
        }
    }
    const bool window_w = is_position && space == VertexSpace::Window && out.components == 4;
    const auto values = a.get("values");
    const auto base64 = a.get("float32_base64");
    if (values && base64) {
        base64->fail("give either \"values\" or \"float32_base64\", not both");
    }
    if (!values && !base64) a.fail("missing required key \"values\" (or \"float32_base64\")");
    // count is at most the vertex limit and components at most 4: no overflow.
    const std::size_t total = count * out.components;
    out.values.resize(total);
    if (values) {
        const std::string what = std::to_string(total) + " numbers (count " +
                                 std::to_string(count) + " x " + std::to_string(out.components) +
                                 " components)";
        values->array_size(total, total, what.c_str());
        float* dst = out.values.data();
        // Numbers finite in float32 (and w > 0) in one loop; at a fault, the loop below reads
        // the array again to refuse it with its path.
        bool fast = true;
        for (const dom::element e : as_array(values->value())) {
            double d = 0;
            if (e.get_double().get(d) != simdjson::SUCCESS) {
                fast = false;
                break;
            }
            const float f = static_cast<float>(d);
            if (!std::isfinite(f) ||
                (window_w && (dst - out.values.data()) % 4 == 3 && !(f > 0.0f))) {
                fast = false;
                break;
            }
            *dst++ = f;
        }
        if (fast) return out;
        dst = out.values.data();
        values->for_each([&](const Node& e) {
            const float f = e.f32();
            if (window_w && (dst - out.values.data()) % 4 == 3 && !(f > 0.0f)) {
                e.fail("expected w > 0 in window space, got " + number_text(e.value()));
            }
            *dst++ = f;
        });
        return out;
    }
    const std::string_view text = base64->string_view();
    if (base64_decoded_size(text) != total * 4) {
        // The refusal: a fault of the text itself first, else the size.
        const std::vector<std::uint8_t> bytes = decode_base64(*base64, text);
        base64->fail("decodes to " + std::to_string(bytes.size()) + " bytes, expected " +
                     std::to_string(total * 4) + " (count " + std::to_string(count) + " x " +
                     std::to_string(out.components) + " components x 4 bytes)");
    }
    // Straight into the values (room for whole groups: the last may be padded), then read as
    // little-endian float32 in place.
    out.values.resize((text.size() / 4 * 3 + 3) / 4);
    auto* const bytes = reinterpret_cast<std::uint8_t*>(out.values.data());
    decode_base64_into(*base64, text, bytes);
    out.values.resize(total);
    for (std::size_t k = 0; k < total; ++k) {
        const float f = std::bit_cast<float>(little_endian_u32(bytes + 4 * k));
        const bool w = window_w && k % 4 == 3;
        if (!std::isfinite(f) || (w && !(f > 0.0f))) {
            const std::string where = "value " + std::to_string(k) + " (vertex " +
                                      std::to_string(k / out.components) + ", component " +
                                      std::to_string(k % out.components) + ")";
            if (std::isnan(f)) base64->fail(where + " is NaN; expected finite float32 values");
            if (std::isinf(f)) {
                base64->fail(where + " is infinite; expected finite float32 values");
            }
            base64->fail(where + ": expected w > 0 in window space, got " +
                         number_text(static_cast<double>(f)));
        }
        out.values[k] = f;
    }
    return out;
}

// A draw's "vertex_arrays": the same SceneVertex list the plain "vertices" would give.
// `textures`: "requires" lists "textures", which allows the attribute "texcoord".
void read_vertex_arrays(const Node& va, SceneDraw& d, WorkSoFar& work, bool textures) {
    if (!textures && va.is_object()) {
        if (auto v = va.get("texcoord")) refuse_extension_key(*v, "texcoord", kTexturesExtension);
    }
    if (textures) {
        va.require_object({"count", "position", "color", "texcoord"});
    } else {
        va.require_object({"count", "position", "color"});
    }
    const auto count = static_cast<std::size_t>(
        va.at("count").integer(0, std::numeric_limits<std::uint32_t>::max()));
    // Before anything of that size is allocated.
    WorkSoFar::add(va, work.vertices, count, work.limits.max_vertices, "vertices");
    const AttributeArray position =
        read_attribute(va.at("position"), count, AttributeKind::Position, d.space);
    std::optional<AttributeArray> color;
    if (auto c = va.get("color")) color = read_attribute(*c, count, AttributeKind::Color, d.space);
    std::optional<AttributeArray> texcoord;
    if (auto t = textures ? va.get("texcoord") : std::nullopt) {
        texcoord = read_attribute(*t, count, AttributeKind::Texcoord, d.space);
    }
    d.vertices.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        SceneVertex sv;
        sv.position_size = position.components;
        const float* p = position.values.data() + i * position.components;
        std::copy(p, p + position.components, sv.position.begin());
        if (color) std::copy_n(color->values.data() + i * 4, 4, sv.color.begin());
        if (texcoord) {
            const std::uint32_t n = texcoord->components;
            std::copy_n(texcoord->values.data() + i * n, n, sv.texcoord.begin());
        }
        d.vertices.push_back(sv);
    }
}

// "indices": {"uint32_base64": "..."} under "vertex_arrays": little-endian uint32 values.
std::vector<std::uint32_t> read_index_base64(const Node& n, std::size_t count, WorkSoFar& work) {
    n.require_object({"uint32_base64"});
    const Node s = n.at("uint32_base64");
    const std::vector<std::uint8_t> bytes = decode_base64(s, s.string_view());
    if (bytes.size() % 4 != 0) {
        s.fail("decodes to " + std::to_string(bytes.size()) +
               " bytes, not a whole number of 4-byte uint32 indices");
    }
    const std::size_t ni = bytes.size() / 4;
    WorkSoFar::add(n, work.indices, ni, work.limits.max_indices, "indices");
    std::vector<std::uint32_t> idx(ni);
    for (std::size_t i = 0; i < ni; ++i) {
        idx[i] = little_endian_u32(bytes.data() + 4 * i);
        if (count == 0) s.fail("index " + std::to_string(i) + " into an empty vertex list");
        if (idx[i] >= count) {
            s.fail("index " + std::to_string(i) + ": expected an integer in [0, " +
                   std::to_string(count - 1) + "], got " + std::to_string(idx[i]));
        }
    }
    return idx;
}

// A plain vertex, {"position": [...], "color": [...]} (and "texcoord" with the extension
// "textures"), read by the general path: every fault refused with its path.
void read_vertex(const Node& vn, VertexSpace space, SceneVertex& sv, bool textures) {
    if (!textures && vn.is_object()) {
        if (auto v = vn.get("texcoord")) refuse_extension_key(*v, "texcoord", kTexturesExtension);
    }
    if (textures) {
        vn.require_object({"position", "color", "texcoord"});
    } else {
        vn.require_object({"position", "color"});
    }
    const Node p = vn.at("position");
    if (space == VertexSpace::Clip) {
        p.array_size(4, 4, "[x, y, z, w] (space \"clip\")");
    } else {
        p.array_size(2, 4, "[x, y], [x, y, z] or [x, y, z, w] (space \"window\")");
    }
    std::uint32_t c = 0;
    p.for_each([&](const Node& e) {
        sv.position[c] = e.f32();
        if (c == 3 && space == VertexSpace::Window && !(sv.position[3] > 0.0f)) {
            e.fail("expected w > 0 in window space, got " + number_text(e.value()));
        }
        ++c;
    });
    sv.position_size = c;
    if (auto col = vn.get("color")) sv.color = read_color(*col);
    if (auto t = textures ? vn.get("texcoord") : std::nullopt) sv.texcoord = read_texcoord(*t);
}

// Between `min` and `max` numbers, each finite once rounded to float32, into `out`; false for
// anything else.
bool read_floats_fast(dom::element e, std::size_t min, std::size_t max, float* out,
                      std::size_t& n) {
    dom::array a;
    if (e.get_array().get(a) != simdjson::SUCCESS) return false;
    std::size_t k = 0;
    for (const dom::element x : a) {
        double d = 0;
        if (k == max || x.get_double().get(d) != simdjson::SUCCESS) return false;
        const float f = static_cast<float>(d);
        if (!std::isfinite(f)) return false;
        out[k++] = f;
    }
    n = k;
    return k >= min;
}

// The common shape of a plain vertex, {"position": [...], "color": [r, g, b, a]} (any key
// first, the colour optional; with `textures` an optional "texcoord" too), read in one pass over
// its keys: the same values as read_vertex. False for anything else, which read_vertex then
// takes from the start, to accept or to refuse with its path. On success adds the vertex's
// containers to `containers`; the caller has checked that their nesting is allowed.
bool read_vertex_fast(dom::element e, VertexSpace space, SceneVertex& sv, std::uint64_t& containers,
                      bool textures) {
    dom::object o;
    if (e.get_object().get(o) != simdjson::SUCCESS) return false;
    bool position = false;
    bool color = false;
    bool texcoord = false;
    for (const dom::key_value_pair kv : o) {
        std::size_t n = 0;
        if (kv.key == "position" && !position) {
            position = true;
            const std::size_t min = space == VertexSpace::Clip ? 4 : 2;
            if (!read_floats_fast(kv.value, min, 4, sv.position.data(), n)) return false;
            if (n == 4 && space == VertexSpace::Window && !(sv.position[3] > 0.0f)) return false;
            sv.position_size = static_cast<std::uint32_t>(n);
        } else if (kv.key == "color" && !color) {
            color = true;
            if (!read_floats_fast(kv.value, 4, 4, sv.color.data(), n)) return false;
        } else if (kv.key == "texcoord" && textures && !texcoord) {
            texcoord = true;
            if (!read_floats_fast(kv.value, 2, 4, sv.texcoord.data(), n) || n == 3) return false;
        } else {
            return false;
        }
    }
    if (!position) return false;
    containers += 2u + (color ? 1u : 0u) + (texcoord ? 1u : 0u);
    return true;
}

SceneDraw read_draw(const Node& n, const refraster::Target& target, WorkSoFar& work,
                    bool vertex_arrays_allowed, const TextureScope& textures, bool polygons) {
    using namespace refraster;
    SceneDraw d;
    if (!vertex_arrays_allowed && n.is_object()) {
        if (auto v = n.get("vertex_arrays")) {
            refuse_extension_key(*v, "vertex_arrays", kVertexArraysExtension);
        }
    }
    if (vertex_arrays_allowed) {
        n.require_object(
            {"primitive", "space", "matrix", "vertices", "vertex_arrays", "indices", "state"});
    } else {
        n.require_object({"primitive", "space", "matrix", "vertices", "indices", "state"});
    }
    const Node primitive = n.at("primitive");
    if (!polygons && primitive.is_string() && primitive.string_view() == "polygon") {
        primitive.fail(
            "the primitive \"polygon\" belongs to the extension \"polygons\"; list it in "
            "\"requires\" to use it");
    }
    // Format v1's primitives, and the extension's "polygon" last: offered only with it.
    static constexpr std::array<std::pair<std::string_view, PrimitiveType>, 8> kPrimitives{{
        {"points", PrimitiveType::Points},
        {"lines", PrimitiveType::Lines},
        {"line_strip", PrimitiveType::LineStrip},
        {"line_loop", PrimitiveType::LineLoop},
        {"triangles", PrimitiveType::Triangles},
        {"triangle_strip", PrimitiveType::TriangleStrip},
        {"triangle_fan", PrimitiveType::TriangleFan},
        {"polygon", PrimitiveType::Polygon},
    }};
    d.primitive = primitive.choice(std::span<const std::pair<std::string_view, PrimitiveType>>(
        kPrimitives.data(), polygons ? kPrimitives.size() : kPrimitives.size() - 1));
    if (auto v = n.get("space")) {
        d.space =
            v->choice<VertexSpace>({{"window", VertexSpace::Window}, {"clip", VertexSpace::Clip}});
    }
    if (auto v = n.get("matrix")) {
        if (d.space != VertexSpace::Clip) {
            v->fail("\"matrix\" is allowed only with \"space\": \"clip\"");
        }
        v->array_size(16, 16, "16 numbers (column-major)");
        std::array<float, 16> m{};
        std::size_t i = 0;
        v->for_each([&](const Node& e) { m[i++] = e.f32(); });
        d.matrix = m;
    }
    const auto arrays = vertex_arrays_allowed ? n.get("vertex_arrays") : std::nullopt;
    if (arrays) {
        if (n.get("vertices")) {
            arrays->fail("give either \"vertices\" or \"vertex_arrays\", not both");
        }
        d.from_vertex_arrays = true;
        read_vertex_arrays(*arrays, d, work, textures.allowed);
    } else {
        if (vertex_arrays_allowed && !n.get("vertices")) {
            n.fail("missing required key \"vertices\" (or \"vertex_arrays\")");
        }
        const Node verts = n.at("vertices");
        const std::size_t count =
            verts.array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of vertices");
        WorkSoFar::add(verts, work.vertices, count, work.limits.max_vertices, "vertices");
        d.vertices.reserve(count);
        // The fast path takes a vertex's object and its two arrays, one and two levels below
        // the list, only where that nesting is allowed.
        const bool fast = verts.depth() + 2 < work.limits.max_nesting_depth;
        std::size_t i = 0;
        for (const dom::element e : as_array(verts.value())) {
            SceneVertex sv;
            if (!fast ||
                !read_vertex_fast(e, d.space, sv, verts.context().containers, textures.allowed)) {
                sv = SceneVertex{};
                read_vertex(Node(e, verts, i), d.space, sv, textures.allowed);
            }
            d.vertices.push_back(sv);
            ++i;
        }
    }
    const std::size_t count = d.vertices.size();
    if (auto v = n.get("indices")) {
        if (vertex_arrays_allowed && v->is_object()) {
            d.indices = read_index_base64(*v, count, work);
        } else {
            const std::size_t ni =
                v->array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of indices");
            WorkSoFar::add(*v, work.indices, ni, work.limits.max_indices, "indices");
            std::vector<std::uint32_t> idx(ni);
            std::size_t i = 0;
            v->for_each([&](const Node& e) {
                if (count == 0) e.fail("index into an empty vertex list");
                idx[i++] =
                    static_cast<std::uint32_t>(e.integer(0, static_cast<std::int64_t>(count) - 1));
            });
            d.indices = std::move(idx);
        }
    }
    // Indices may repeat a vertex any number of times: the primitives are what costs.
    const std::size_t elements = d.indices ? d.indices->size() : d.vertices.size();
    WorkSoFar::add(n, work.primitives, refraster::primitive_count(d.primitive, elements),
                   work.limits.max_primitives, "primitives");
    if (auto v = n.get("state")) {
        d.state = read_state(*v, target, textures, polygons, d.texture);
        if (d.state.fill_rule) {
            // A fill rule lights the region of one polygon whatever its orientation: it needs
            // the primitive "polygon", polygon mode fill and no culling (docs/scene-format.md,
            // "Fill rules").
            const Node rule = v->at("fill_rule");
            if (d.primitive != PrimitiveType::Polygon) {
                rule.fail("a fill rule applies to the primitive \"polygon\" only, not to \"" +
                          std::string(refraster::to_string(d.primitive)) + "\"");
            }
            if (d.state.polygon_mode != PolygonMode::Fill) {
                rule.fail("a fill rule fills the polygon; it needs \"polygon_mode\": \"fill\"");
            }
            if (d.state.cull != CullMode::None) {
                rule.fail(
                    "a fill rule fills the polygon whatever its orientation; it needs "
                    "\"cull\": \"none\"");
            }
        }
    } else {
        d.state.viewport = {0, 0, static_cast<std::int32_t>(target.width),
                            static_cast<std::int32_t>(target.height)};
    }
    return d;
}

// The extensions this reader implements. "multisample": the draw state key "multisample"
// (GL_MULTISAMPLE) on 4x targets; the key is part of format v1 too, and a file may still list
// the name to say that it relies on it. "vertex_arrays": a draw's vertices as flat arrays per
// attribute, and indices as base64 (docs/scene-format.md); the loader turns them into the same
// vertices as the plain form, so every renderer draws them. "textures": textures by name,
// texture coordinates and each draw's texture unit state, which the draw list carries.
// "polygons": the primitive "polygon" and the draw state key "fill_rule".
bool is_implemented_extension(std::string_view name) {
    return name == "multisample" || name == kVertexArraysExtension || name == kTexturesExtension ||
           name == kPolygonsExtension;
}

// The texel bytes of the textures read so far, against SceneLimits::max_texel_bytes.
struct TexelBudget {
    const SceneLimits& limits;
    std::uint64_t bytes = 0;

    void add(const Node& where, std::uint64_t n) {
        bytes += n;
        if (bytes > limits.max_texel_bytes) {
            where.fail("this brings the scene's textures to " + std::to_string(bytes) +
                       " bytes of texels, over the limit of " +
                       std::to_string(limits.max_texel_bytes) + " (docs/limits.md)");
        }
    }
};

std::string size_text(std::uint32_t width, std::uint32_t height) {
    return std::to_string(width) + " x " + std::to_string(height);
}

// One image of a texture: its base (`level` 0) or level `level` of "levels", which must be
// exactly max(1, base_width >> level) x max(1, base_height >> level). Either "width", "height"
// and "data" (base64 of width x height RGBA8 texels, rows bottom to top), or "file" (a PNG,
// relative to `base_dir`) with "width" and "height" optional and then checked.
refraster::TextureImage read_texture_image(const Node& n, std::uint32_t level,
                                           std::uint32_t base_width, std::uint32_t base_height,
                                           const std::filesystem::path& base_dir,
                                           TexelBudget& budget) {
    const auto data = n.get("data");
    const auto file = n.get("file");
    if (data && file) file->fail("give either \"data\" or \"file\", not both");
    if (!data && !file) n.fail("missing required key \"data\" (or \"file\")");
    const std::uint32_t want_width = level == 0 ? 0 : std::max(1u, base_width >> level);
    const std::uint32_t want_height = level == 0 ? 0 : std::max(1u, base_height >> level);
    const auto level_size = [&] {
        return "level " + std::to_string(level) + " of a " + size_text(base_width, base_height) +
               " texture is " + size_text(want_width, want_height) + " (max(1, size >> " +
               std::to_string(level) + "))";
    };
    const auto read_side = [&](std::string_view key, std::uint32_t want) {
        const auto v = data ? std::optional<Node>(n.at(key)) : n.get(key);
        if (!v) return std::optional<std::uint32_t>();
        const auto side = static_cast<std::uint32_t>(v->integer(1, kMaxTextureSide));
        if (level != 0 && side != want) {
            v->fail(level_size() + "; got " + std::string(key) + " " + std::to_string(side));
        }
        return std::optional<std::uint32_t>(side);
    };
    const std::optional<std::uint32_t> width = read_side("width", want_width);
    const std::optional<std::uint32_t> height = read_side("height", want_height);
    refraster::TextureImage image;
    if (data) {
        image.width = *width;
        image.height = *height;
        const std::uint64_t bytes = std::uint64_t{image.width} * image.height * 4;
        budget.add(n, bytes);
        const std::string_view text = data->string_view();
        if (base64_decoded_size(text) != bytes) {
            // The refusal: a fault of the text itself first, else the size.
            const std::vector<std::uint8_t> decoded = decode_base64(*data, text);
            data->fail("decodes to " + std::to_string(decoded.size()) + " bytes, expected " +
                       std::to_string(bytes) + " (width " + std::to_string(image.width) +
                       " x height " + std::to_string(image.height) + " x 4 bytes of RGBA8 texels)");
        }
        // Room for whole groups of the text; the padding leaves the last one short.
        image.rgba.resize(text.size() / 4 * 3);
        decode_base64_into(*data, text, image.rgba.data());
        image.rgba.resize(static_cast<std::size_t>(bytes));
        return image;
    }
    const std::string written = file->string();
    if (written.empty()) file->fail("expected the path of a PNG file, got an empty string");
    const std::filesystem::path path = base_dir / written;
    const std::string shown = escape_for_message(path.string());
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status))
        file->fail("cannot read " + shown + ": no such file");
    if (!std::filesystem::is_regular_file(status)) {
        file->fail("cannot read " + shown + ": not a regular file");
    }
    const TextureFileReader reader = texture_file_reader();
    if (reader == nullptr) {
        file->fail("cannot read " + shown +
                   ": this program reads no image files (it is built without harness_image_io); "
                   "give the texels as \"data\"");
    }
    bool checked = false;
    const auto check_size = [&](std::uint32_t w, std::uint32_t h) {
        checked = true;
        if (w < 1 || h < 1 || w > kMaxTextureSide || h > kMaxTextureSide) {
            file->fail(shown + " is " + size_text(w, h) +
                       " pixels; a texture is 1 to 4096 pixels a side");
        }
        if (width && w != *width) {
            file->fail(shown + " is " + size_text(w, h) + " pixels, but \"width\" is " +
                       std::to_string(*width));
        }
        if (height && h != *height) {
            file->fail(shown + " is " + size_text(w, h) + " pixels, but \"height\" is " +
                       std::to_string(*height));
        }
        if (level != 0 && (w != want_width || h != want_height)) {
            file->fail(level_size() + "; " + shown + " is " + size_text(w, h));
        }
        budget.add(n, std::uint64_t{w} * h * 4);
    };
    try {
        image = reader(path, check_size);
    } catch (const SceneError&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw;  // running out of memory: main reports it (exit 3)
    } catch (const std::exception& e) {
        file->fail(escape_for_message(e.what()));
    }
    if (!checked) check_size(image.width, image.height);
    if (image.rgba.size() != std::size_t{image.width} * image.height * 4) {
        file->fail(shown + ": the image reader returned " + std::to_string(image.rgba.size()) +
                   " bytes for " + size_text(image.width, image.height) + " texels");
    }
    return image;
}

// One texture: its base image, then "levels" (the given mipmap levels 1, 2, ...) or "mipmaps":
// "generate".
refraster::Texture read_texture(const Node& n, const std::filesystem::path& base_dir,
                                TexelBudget& budget) {
    n.require_object({"width", "height", "data", "file", "levels", "mipmaps"});
    refraster::Texture t;
    t.levels.push_back(read_texture_image(n, 0, 0, 0, base_dir, budget));
    const std::uint32_t width = t.levels[0].width;
    const std::uint32_t height = t.levels[0].height;
    // The levels below the base, down to 1 x 1.
    std::uint32_t below = 0;
    for (std::uint32_t m = std::max(width, height); m > 1; m >>= 1) ++below;
    const auto levels = n.get("levels");
    const auto mipmaps = n.get("mipmaps");
    if (levels && mipmaps) mipmaps->fail("give either \"levels\" or \"mipmaps\", not both");
    if (levels) {
        if (below == 0) {
            levels->fail("a 1 x 1 texture has no levels below its base; leave out \"levels\"");
        }
        const std::string what = "an array of 1 to " + std::to_string(below) +
                                 " levels (levels 1 to " + std::to_string(below) + " of a " +
                                 size_text(width, height) + " texture, down to 1 x 1)";
        levels->array_size(1, below, what.c_str());
        std::uint32_t level = 1;
        levels->for_each([&](const Node& e) {
            e.require_object({"width", "height", "data", "file"});
            t.levels.push_back(read_texture_image(e, level++, width, height, base_dir, budget));
        });
    }
    if (mipmaps) {
        t.generate_mipmaps = mipmaps->choice<bool>({{"generate", true}});
        // The levels glGenerateMipmap makes count too: every renderer holds them.
        std::uint64_t bytes = 0;
        for (std::uint32_t l = 1; l <= below; ++l) {
            bytes += std::uint64_t{std::max(1u, width >> l)} * std::max(1u, height >> l) * 4;
        }
        budget.add(*mipmaps, bytes);
    }
    return t;
}

// The top-level "textures": {"NAME": {...}, ...}.
std::map<std::string, refraster::Texture> read_textures(const Node& n,
                                                        const std::filesystem::path& base_dir,
                                                        const SceneLimits& limits) {
    const std::size_t count = n.members("an object of textures by name");
    if (count > limits.max_textures) {
        n.fail(std::to_string(count) + " textures exceed the limit of " +
               std::to_string(limits.max_textures) + " textures a scene (docs/limits.md)");
    }
    TexelBudget budget{limits};
    std::map<std::string, refraster::Texture> out;
    n.for_each_member([&](std::string_view name, const Node& t) {
        out.emplace(std::string(name), read_texture(t, base_dir, budget));
    });
    return out;
}

// Whether the root's "requires" lists `name`, looked at before anything is checked: which keys
// the root may hold depends on it. read_scene checks "requires" itself afterwards.
bool requires_lists(const Node& root, std::string_view name) {
    if (!root.is_object()) return false;
    const auto r = root.get("requires");
    dom::array a;
    if (!r || r->value().get_array().get(a) != simdjson::SUCCESS) return false;
    for (const dom::element e : a) {
        std::string_view s;
        if (e.get_string().get(s) == simdjson::SUCCESS && s == name) return true;
    }
    return false;
}

std::atomic<TextureFileReader> g_texture_file_reader{nullptr};

}  // namespace

namespace {

SceneFile read_scene(const Node& root, const SceneLimits& limits) {
    using namespace refraster;
    const bool textures_allowed = requires_lists(root, kTexturesExtension);
    if (!textures_allowed && root.is_object()) {
        if (auto v = root.get("textures")) {
            refuse_extension_key(*v, "textures", kTexturesExtension);
        }
    }
    if (textures_allowed) {
        root.require_object({"format", "name", "description", "requires", "target", "clear",
                             "expect", "textures", "draws"});
    } else {
        root.require_object(
            {"format", "name", "description", "requires", "target", "clear", "expect", "draws"});
    }
    SceneFile s;
    const Node format = root.at("format");
    if (format.string_view() != kSceneFormatV1) {
        format.fail(std::string("expected \"") + kSceneFormatV1 + "\", got " +
                    describe(format.value()));
    }
    if (auto v = root.get("name")) s.name = v->string();
    if (auto v = root.get("description")) s.description = v->string();
    if (auto v = root.get("requires")) {
        v->array_size(0, 64, "an array of extension names");
        v->for_each([&](const Node& e) { s.requires_extensions.push_back(e.string()); });
    }
    const bool vertex_arrays_allowed =
        std::find(s.requires_extensions.begin(), s.requires_extensions.end(),
                  kVertexArraysExtension) != s.requires_extensions.end();

    const Node t = root.at("target");
    t.require_object({"width", "height", "color", "depth", "samples"});
    s.target.width = static_cast<std::uint32_t>(t.at("width").integer(1, kMaxTargetSide));
    s.target.height = static_cast<std::uint32_t>(t.at("height").integer(1, kMaxTargetSide));
    if (auto v = t.get("color")) {
        s.target.color = v->choice<ColorFormat>(
            {{"rgba8", ColorFormat::Rgba8}, {"rgba32f", ColorFormat::Rgba32f}});
    }
    if (auto v = t.get("depth")) {
        s.target.depth = v->choice<DepthFormat>({{"none", DepthFormat::None},
                                                 {"z16", DepthFormat::Z16},
                                                 {"z24", DepthFormat::Z24},
                                                 {"z32f", DepthFormat::Z32f}});
    }
    if (auto v = t.get("samples")) {
        const auto n = v->integer(1, 4);
        if (n != 1 && n != 4) v->fail("expected 1 or 4, got " + number_text(v->value()));
        s.target.samples = static_cast<std::uint32_t>(n);
    }
    const std::uint64_t area = std::uint64_t{s.target.width} * s.target.height * s.target.samples;
    if (area > limits.max_target_pixels) {
        t.fail("width x height x samples = " + std::to_string(area) + " exceeds the limit of " +
               std::to_string(limits.max_target_pixels));
    }

    if (auto c = root.get("clear")) {
        c->require_object({"color", "depth"});
        if (auto v = c->get("color")) s.clear.color = read_color(*v);
        if (auto v = c->get("depth")) s.clear.depth = v->f32_in(0.0f, 1.0f);
    }
    if (auto e = root.get("expect")) {
        e->require_object({"color_tolerance", "max_mismatched_pixels"});
        if (auto v = e->get("color_tolerance")) {
            s.expect.color_tolerance =
                static_cast<std::uint32_t>(v->integer(0, std::numeric_limits<std::int32_t>::max()));
        }
        if (auto v = e->get("max_mismatched_pixels")) {
            s.expect.max_mismatched_pixels =
                static_cast<std::uint64_t>(v->integer(0, kMaxTargetSamplesArea));
        }
    }

    if (auto v = textures_allowed ? root.get("textures") : std::nullopt) {
        // Relative file names start from the scene file's directory.
        s.textures =
            read_textures(*v, std::filesystem::path(root.context().file).parent_path(), limits);
    }
    const TextureScope textures{textures_allowed, &s.textures};
    const bool polygons_allowed =
        std::find(s.requires_extensions.begin(), s.requires_extensions.end(), kPolygonsExtension) !=
        s.requires_extensions.end();

    const Node draws = root.at("draws");
    const std::size_t nd =
        draws.array_size(0, std::numeric_limits<std::uint32_t>::max(), "an array of draws");
    if (nd > limits.max_draws) {
        draws.fail(std::to_string(nd) + " draws exceed the limit of " +
                   std::to_string(limits.max_draws) + " draws a scene (docs/limits.md)");
    }
    WorkSoFar work{limits};
    s.draws.reserve(nd);
    draws.for_each([&](const Node& d) {
        s.draws.push_back(
            read_draw(d, s.target, work, vertex_arrays_allowed, textures, polygons_allowed));
    });
    return s;
}

void check_file_size(std::uintmax_t size, const std::string& file_label,
                     const SceneLimits& limits) {
    if (size > limits.max_file_bytes) {
        throw SceneError(file_label, "",
                         "file of " + std::to_string(size) +
                             " bytes exceeds the scene size limit of " +
                             std::to_string(limits.max_file_bytes) + " bytes");
    }
}

// `padded`: SIMDJSON_PADDING readable bytes follow the text, so simdjson reads it in place.
SceneFile parse_scene_text(std::string_view text, bool padded, const std::string& file_label,
                           const SceneLimits& limits) {
    check_file_size(text.size(), file_label, limits);
    // One parser a thread, kept between loads: the pages of its buffers (about 4 bytes of
    // structural index and 8 of tape a byte of text, in part untouched) are faulted in once
    // rather than at every load of a large file.
    thread_local dom::parser parser;
    Document doc{parser, {}, {}, {}};
    parse_document(doc, text, padded, file_label, limits);
    // The walk checks the strict rules on what it reads. A strict fault takes precedence over
    // any other refusal, wherever it sits in the file: the strict parser names the first one.
    WalkContext context{file_label, limits};
    std::optional<SceneFile> scene;
    try {
        scene = read_scene(Node(doc.root, context), limits);
    } catch (const StrictFault&) {
        refuse_strictly(text, file_label, limits);
    } catch (const SceneError&) {
        if (!follows_strict_rules(doc.root, limits)) refuse_strictly(text, file_label, limits);
        throw;
    }
    // Brackets inside strings (or a container the walk did not take) make the counts differ:
    // then the scan checks the whole document.
    if (context.containers != doc.counts.containers && !follows_strict_rules(doc.root, limits)) {
        refuse_strictly(text, file_label, limits);
    }
    return std::move(*scene);
}

Scene finish_scene(SceneFile file, const std::string& file_label, const SceneLimits& limits) {
    Scene scene;
    scene.path = file_label;
    scene.file = std::move(file);
    scene.draw_list = run_front_end(scene.file, file_label);
    // The fragment estimate needs clip-space positions, so it follows the front end; nothing
    // has been drawn yet.
    std::uint64_t fragments = 0;
    for (std::size_t d = 0; d < scene.draw_list.draws.size(); ++d) {
        fragments += estimate_work(scene.draw_list.draws[d], scene.draw_list.target).fragments;
        if (fragments > limits.max_fragments) {
            throw SceneError(file_label, "draws[" + std::to_string(d) + "]",
                             "this brings the scene's estimated fragments to " +
                                 std::to_string(fragments) + ", over the limit of " +
                                 std::to_string(limits.max_fragments) + " (docs/limits.md)");
        }
    }
    // Required extensions this reader does not implement make the scene NotSupported.
    for (const auto& e : scene.file.requires_extensions) {
        if (!is_implemented_extension(e)) scene.unsupported_extensions.push_back(e);
    }
    return scene;
}

}  // namespace

void set_texture_file_reader(TextureFileReader reader) {
    g_texture_file_reader.store(reader);
}

TextureFileReader texture_file_reader() {
    return g_texture_file_reader.load();
}

SceneFile parse_scene(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits) {
    return parse_scene_text(text, false, file_label, limits);
}

Scene load_scene_text(std::string_view text, const std::string& file_label,
                      const SceneLimits& limits) {
    return finish_scene(parse_scene_text(text, false, file_label, limits), file_label, limits);
}

Scene load_scene(const std::filesystem::path& path, const SceneLimits& limits) {
    const std::string label = path.string();
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) {
        throw SceneError(label, "", "cannot open: no such file");
    }
    if (std::filesystem::is_directory(status)) {
        throw SceneError(label, "", "is a directory, expected a scene file");
    }
    if (!std::filesystem::is_regular_file(status)) {
        throw SceneError(label, "", "is not a regular file");
    }
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) throw SceneError(label, "", "cannot read its size: " + ec.message());
    // Checked again on the text; here so that a huge file is not read at all.
    check_file_size(size, label, limits);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(label, "", "cannot open for reading");
    // Read straight into a buffer with simdjson's padding after the text, so that the parser
    // needs no copy of it; left uninitialized, as the read fills it.
    const auto n = static_cast<std::size_t>(size);
    auto buffer = std::make_unique_for_overwrite<char[]>(n + simdjson::SIMDJSON_PADDING);
    std::fill_n(buffer.get() + n, simdjson::SIMDJSON_PADDING, '\0');
    in.read(buffer.get(), static_cast<std::streamsize>(n));
    if (static_cast<std::uintmax_t>(in.gcount()) != size) {
        throw SceneError(label, "", "read failed");
    }
    SceneFile file = parse_scene_text(std::string_view(buffer.get(), n), true, label, limits);
    // The text is not needed any more: freed before the front end's draw list is built, while
    // the parser keeps its buffers for the next load.
    buffer.reset();
    Scene s = finish_scene(std::move(file), label, limits);
    s.path = path;
    return s;
}

}  // namespace harness
