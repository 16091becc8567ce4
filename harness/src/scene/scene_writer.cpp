// scene_writer.cpp: scene files written back as JSON, the loader's inverse (scene_writer.hpp).
#include "harness/scene_writer.hpp"

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>

#include "harness/scene_text.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

using ojson = nlohmann::ordered_json;

const char* name_of(refraster::CullMode c) {
    switch (c) {
        case refraster::CullMode::None:
            return "none";
        case refraster::CullMode::Front:
            return "front";
        case refraster::CullMode::Back:
            return "back";
        case refraster::CullMode::FrontAndBack:
            return "front_and_back";
    }
    return "none";
}

const char* name_of(refraster::CompareFunc f) {
    static const char* names[] = {"never",   "less",     "equal",  "lequal",
                                  "greater", "notequal", "gequal", "always"};
    return names[static_cast<int>(f)];
}

const char* name_of(refraster::TextureFilter f) {
    static const char* names[] = {"nearest",
                                  "linear",
                                  "nearest_mipmap_nearest",
                                  "linear_mipmap_nearest",
                                  "nearest_mipmap_linear",
                                  "linear_mipmap_linear"};
    return names[static_cast<int>(f)];
}

const char* name_of(refraster::TextureWrap w) {
    static const char* names[] = {"repeat", "clamp_to_edge", "mirrored_repeat", "clamp_to_border"};
    return names[static_cast<int>(w)];
}

// A draw's "texture" (extension "textures"): the name, then what differs from the defaults.
ojson texture_state_json(const refraster::TextureState& t, const std::string& name) {
    using namespace refraster;
    const TextureState d;
    ojson j = {{"name", name}};
    if (t.min_filter != d.min_filter) j["min_filter"] = name_of(t.min_filter);
    if (t.mag_filter != d.mag_filter) j["mag_filter"] = name_of(t.mag_filter);
    if (t.wrap_s != d.wrap_s) j["wrap_s"] = name_of(t.wrap_s);
    if (t.wrap_t != d.wrap_t) j["wrap_t"] = name_of(t.wrap_t);
    // Bit for bit: -0 is no default.
    if (std::memcmp(t.border_color.data(), d.border_color.data(), sizeof d.border_color) != 0) {
        j["border_color"] = t.border_color;
    }
    if (t.env != d.env) j["env"] = t.env == TextureEnv::Replace ? "replace" : "modulate";
    if (t.coord_replace != d.coord_replace) j["coord_replace"] = t.coord_replace;
    if (t.point_coord_origin != d.point_coord_origin) {
        j["point_coord_origin"] =
            t.point_coord_origin == PointCoordOrigin::LowerLeft ? "lower_left" : "upper_left";
    }
    return j;
}

// One image of a texture as "data": base64 of its RGBA8 texels, rows bottom to top.
ojson texture_image_json(const refraster::TextureImage& image) {
    return {{"width", image.width}, {"height", image.height}, {"data", base64_text(image.rgba)}};
}

ojson texture_json(const refraster::Texture& t) {
    ojson j = t.levels.empty() ? ojson::object() : texture_image_json(t.levels.front());
    if (t.levels.size() > 1) {
        ojson levels = ojson::array();
        for (std::size_t l = 1; l < t.levels.size(); ++l) {
            levels.push_back(texture_image_json(t.levels[l]));
        }
        j["levels"] = levels;
    }
    if (t.generate_mipmaps) j["mipmaps"] = "generate";
    return j;
}

ojson state_json(const refraster::DrawState& s, const refraster::Target& t,
                 const std::string& texture_name) {
    using namespace refraster;
    const DrawState d;
    ojson j = ojson::object();
    const Rect whole{0, 0, static_cast<std::int32_t>(t.width), static_cast<std::int32_t>(t.height)};
    if (!(s.viewport == whole))
        j["viewport"] = {s.viewport.x, s.viewport.y, s.viewport.width, s.viewport.height};
    if (s.depth_near != d.depth_near || s.depth_far != d.depth_far)
        j["depth_range"] = {s.depth_near, s.depth_far};
    if (s.scissor) j["scissor"] = {s.scissor->x, s.scissor->y, s.scissor->width, s.scissor->height};
    if (s.cull != d.cull) j["cull"] = name_of(s.cull);
    if (s.front_face != d.front_face) j["front_face"] = "cw";
    if (s.depth_test) j["depth_test"] = name_of(*s.depth_test);
    if (!s.depth_write) j["depth_write"] = false;
    if (s.shade != d.shade) j["shade"] = s.shade == ShadeModel::Flat ? "flat" : "noperspective";
    if (s.provoking_vertex != d.provoking_vertex) j["provoking_vertex"] = "first";
    if (s.polygon_mode != d.polygon_mode)
        j["polygon_mode"] = s.polygon_mode == PolygonMode::Line ? "line" : "point";
    if (s.polygon_offset)
        j["polygon_offset"] = {{"factor", s.polygon_offset->factor},
                               {"units", s.polygon_offset->units}};
    if (s.line_width != d.line_width) j["line_width"] = s.line_width;
    if (s.point_size != d.point_size) j["point_size"] = s.point_size;
    if (s.blend != d.blend) j["blend"] = s.blend == BlendPreset::Alpha ? "alpha" : "add";
    if (!s.multisample) j["multisample"] = false;
    if (s.texture) j["texture"] = texture_state_json(*s.texture, texture_name);
    if (s.fill_rule) j["fill_rule"] = std::string(to_string(*s.fill_rule));
    return j;
}

}  // namespace

bool uses_textures(const SceneFile& s) {
    if (!s.textures.empty()) return true;
    for (const auto& d : s.draws) {
        if (d.state.texture) return true;
        for (const auto& v : d.vertices) {
            if (!is_default_texcoord(v.texcoord)) return true;
        }
    }
    return false;
}

std::string scene_to_json(const SceneFile& s) {
    using namespace refraster;
    ojson j;
    j["format"] = kSceneFormatV1;
    if (!s.name.empty()) j["name"] = s.name;
    if (!s.description.empty()) j["description"] = s.description;
    std::vector<std::string> requires_extensions = s.requires_extensions;
    if (uses_textures(s) && std::find(requires_extensions.begin(), requires_extensions.end(),
                                      "textures") == requires_extensions.end()) {
        requires_extensions.emplace_back("textures");
    }
    if (!requires_extensions.empty()) j["requires"] = requires_extensions;
    ojson t = {{"width", s.target.width}, {"height", s.target.height}};
    if (s.target.color != ColorFormat::Rgba8) t["color"] = "rgba32f";
    if (s.target.depth != DepthFormat::None) t["depth"] = std::string(to_string(s.target.depth));
    if (s.target.samples != 1) t["samples"] = s.target.samples;
    j["target"] = t;
    j["clear"] = {{"color", s.clear.color}, {"depth", s.clear.depth}};
    if (s.expect.color_tolerance != 0 || s.expect.max_mismatched_pixels != 0) {
        j["expect"] = {{"color_tolerance", s.expect.color_tolerance},
                       {"max_mismatched_pixels", s.expect.max_mismatched_pixels}};
    }
    if (!s.textures.empty()) {
        ojson textures = ojson::object();
        for (const auto& [name, texture] : s.textures) textures[name] = texture_json(texture);
        j["textures"] = textures;
    }
    ojson draws = ojson::array();
    for (const auto& d : s.draws) {
        ojson dj;
        dj["primitive"] = std::string(to_string(d.primitive));
        if (d.space == VertexSpace::Clip) dj["space"] = "clip";
        if (d.matrix) dj["matrix"] = *d.matrix;
        ojson vs = ojson::array();
        for (const auto& v : d.vertices) {
            ojson p = ojson::array();
            for (std::uint32_t k = 0; k < v.position_size; ++k) p.push_back(v.position[k]);
            ojson vj = {{"position", p}, {"color", v.color}};
            if (is_two_component_texcoord(v.texcoord)) {
                if (!is_default_texcoord(v.texcoord)) {
                    vj["texcoord"] = {v.texcoord[0], v.texcoord[1]};
                }
            } else {
                vj["texcoord"] = v.texcoord;
            }
            vs.push_back(vj);
        }
        dj["vertices"] = vs;
        if (d.indices) dj["indices"] = *d.indices;
        if (auto st = state_json(d.state, s.target, d.texture); !st.empty()) dj["state"] = st;
        draws.push_back(dj);
    }
    j["draws"] = draws;
    return j.dump(1) + "\n";
}

}  // namespace harness
