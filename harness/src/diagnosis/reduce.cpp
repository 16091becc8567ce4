#include "harness/reduce.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <ostream>
#include <stdexcept>

#include "harness/compare.hpp"
#include "harness/explain.hpp"
#include "harness/front_end.hpp"
#include "harness/scene_text.hpp"
#include "refraster/assembly.hpp"
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

// The primitives of a draw as vertex lists in the order the driver assembles them
// (refraster/assembly.hpp), so that a list primitive with those vertices rasterizes
// identically.
std::vector<std::vector<SceneVertex>> primitives_of(const SceneDraw& d) {
    const std::size_t n = d.indices ? d.indices->size() : d.vertices.size();
    const auto v = [&](std::size_t i) { return d.vertices[d.indices ? (*d.indices)[i] : i]; };
    const bool first = d.state.provoking_vertex == refraster::ProvokingVertex::First;
    std::vector<std::vector<SceneVertex>> out;
    if (d.primitive == refraster::PrimitiveType::Polygon) {
        // One polygon: its triangles drawn apart would lose its outline (polygon modes) and its
        // region (fill rules), so it stays whole.
        auto& prim = out.emplace_back();
        for (std::size_t i = 0; i < n; ++i) prim.push_back(v(i));
        return out;
    }
    for (const auto& elements : refraster::assemble_primitives(d.primitive, n, first)) {
        auto& prim = out.emplace_back();
        for (const auto e : elements) prim.push_back(v(e));
    }
    return out;
}

refraster::PrimitiveType list_type(refraster::PrimitiveType p) {
    using refraster::PrimitiveType;
    switch (p) {
        case PrimitiveType::Points:
            return PrimitiveType::Points;
        case PrimitiveType::Lines:
        case PrimitiveType::LineStrip:
        case PrimitiveType::LineLoop:
            return PrimitiveType::Lines;
        case PrimitiveType::Polygon:
            return PrimitiveType::Polygon;
        default:
            return PrimitiveType::Triangles;
    }
}

// The working form: every draw's primitives, each removable on its own.
struct Piece {
    std::size_t draw;
    std::vector<SceneVertex> vertices;
};

SceneFile assemble(const SceneFile& base, const std::vector<Piece>& pieces) {
    SceneFile s = base;
    s.draws.clear();
    std::size_t current = SIZE_MAX;
    for (const auto& p : pieces) {
        if (p.draw != current) {
            SceneDraw d = base.draws[p.draw];
            d.primitive = list_type(d.primitive);
            d.vertices.clear();
            d.indices.reset();
            s.draws.push_back(d);
            current = p.draw;
        }
        auto& v = s.draws.back().vertices;
        v.insert(v.end(), p.vertices.begin(), p.vertices.end());
    }
    return s;
}

class Oracle {
  public:
    Oracle(const refraster::Profile& p, Backend& b, const std::string& label,
           const MismatchToKeep& keep)
        : profile_(p), backend_(b), label_(label), keep_(keep) {}

    // The mismatch signature, "class: rule", or "" when the scene has no mismatch of the kind
    // kept (or cannot be rendered).
    std::string signature(const SceneFile& f) {
        ++renders;
        Scene scene;
        scene.path = label_;
        scene.file = f;
        try {
            scene.draw_list = run_front_end(f, label_);
        } catch (const SceneError&) {
            return "";
        }
        try {
            Explainer ex(scene, profile_, &backend_);
            const auto& ref = ex.reference_image();
            std::optional<std::array<int, 2>> at = keep_.pixel;
            if (at) {
                const auto i = ref.index(static_cast<std::uint32_t>((*at)[0]),
                                         static_cast<std::uint32_t>((*at)[1]));
                if (ex.classifier()->at(i).cls == PixelClass::Equal) return "";
            } else {
                // The pixel of largest difference (colour first, then depth), of the kept class.
                std::pair<std::uint64_t, std::uint64_t> worst{0, 0};
                for (std::uint32_t y = 0; y < ref.height; ++y) {
                    for (std::uint32_t x = 0; x < ref.width; ++x) {
                        const auto px = ex.classifier()->at(ref.index(x, y));
                        if (px.cls == PixelClass::Equal || !of_class(px.cls)) continue;
                        const std::pair<std::uint64_t, std::uint64_t> d{px.color_difference,
                                                                        px.depth_difference};
                        if (!at || d > worst) {
                            worst = d;
                            at = std::array<int, 2>{static_cast<int>(x), static_cast<int>(y)};
                        }
                    }
                }
                if (!at) return "";
            }
            const auto e = ex.explain((*at)[0], (*at)[1]);
            if (!keep_.difference.empty() && e.difference != keep_.difference) return "";
            return e.difference + ": " + e.rule;
        } catch (const std::runtime_error&) {
            return "";
        }
    }
    int renders = 0;

  private:
    bool of_class(PixelClass c) const {
        if (keep_.difference.empty()) return true;
        const bool coverage =
            c == PixelClass::Missing || c == PixelClass::Extra || c == PixelClass::Coverage;
        return keep_.difference == "coverage" ? coverage
               : keep_.difference == "colour" ? c == PixelClass::ColorOnly
                                              : c == PixelClass::DepthOnly;
    }

    const refraster::Profile& profile_;
    Backend& backend_;
    std::string label_;
    MismatchToKeep keep_;
};

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

ReduceResult reduce_scene(const SceneFile& scene, const std::string& label,
                          const refraster::Profile& profile, Backend& backend, std::ostream& log,
                          const MismatchToKeep& keep) {
    Oracle oracle(profile, backend, label, keep);
    ReduceResult r;
    r.signature = oracle.signature(scene);
    if (r.signature.empty()) {
        throw std::runtime_error(label +
                                 (keep.pixel || !keep.difference.empty()
                                      ? ": no mismatch of the kind asked for; nothing to reduce"
                                      : ": the scene matches the backend; nothing to reduce"));
    }
    log << "signature: a " << r.signature << " mismatch"
        << "\n";

    std::vector<Piece> pieces;
    for (std::size_t d = 0; d < scene.draws.size(); ++d) {
        for (auto& p : primitives_of(scene.draws[d])) pieces.push_back({d, std::move(p)});
    }
    r.primitives_before = pieces.size();
    const auto holds = [&](const std::vector<Piece>& ps) {
        return !ps.empty() && oracle.signature(assemble(scene, ps)) == r.signature;
    };
    if (!holds(pieces)) {
        throw std::runtime_error(label +
                                 ": the signature changes when draws become lists of primitives");
    }
    log << "step 0: " << pieces.size() << " primitives in " << scene.draws.size() << " draws\n";

    // ddmin over primitives: try dropping each of n chunks, then keeping only one chunk.
    std::size_t n = 2;
    int step = 0;
    while (pieces.size() >= 2) {
        const std::size_t chunk = (pieces.size() + n - 1) / n;
        bool reduced = false;
        for (std::size_t start = 0; start < pieces.size() && !reduced; start += chunk) {
            const std::size_t end = std::min(pieces.size(), start + chunk);
            std::vector<Piece> only(pieces.begin() + static_cast<std::ptrdiff_t>(start),
                                    pieces.begin() + static_cast<std::ptrdiff_t>(end));
            if (only.size() < pieces.size() && holds(only)) {
                pieces = std::move(only);
                n = 2;
                reduced = true;
                break;
            }
            std::vector<Piece> rest;
            rest.insert(rest.end(), pieces.begin(),
                        pieces.begin() + static_cast<std::ptrdiff_t>(start));
            rest.insert(rest.end(), pieces.begin() + static_cast<std::ptrdiff_t>(end),
                        pieces.end());
            if (holds(rest)) {
                pieces = std::move(rest);
                n = std::max<std::size_t>(n - 1, 2);
                reduced = true;
            }
        }
        if (reduced) {
            log << "step " << ++step << ": " << pieces.size() << " primitives\n" << std::flush;
            continue;
        }
        if (n >= pieces.size()) break;
        n = std::min(pieces.size(), n * 2);
    }

    // Coordinates to coarser binary grids, one vertex coordinate at a time.
    SceneFile best = assemble(scene, pieces);
    for (auto& d : best.draws) {
        for (auto& v : d.vertices) {
            for (std::uint32_t k = 0; k < v.position_size; ++k) {
                for (float grid : {1.0f, 0.5f, 0.25f, 1.0f / 16, 1.0f / 256}) {
                    const float old = v.position[k];
                    const float rounded = std::round(old / grid) * grid;
                    if (rounded == old) break;
                    v.position[k] = rounded;
                    if (oracle.signature(best) == r.signature) {
                        log << "step " << ++step << ": a coordinate " << old << " -> " << rounded
                            << "\n";
                        break;
                    }
                    v.position[k] = old;
                }
            }
        }
    }
    r.scene = best;
    r.primitives_after = pieces.size();
    r.renders = oracle.renders;
    log << "done: " << r.primitives_before << " -> " << r.primitives_after << " primitives in "
        << r.renders << " renders\n";
    return r;
}

}  // namespace harness
