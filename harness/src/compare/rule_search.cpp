// rule_search.cpp: the one list of rule variations (rule_search.hpp).
#include "harness/rule_search.hpp"

#include <algorithm>
#include <functional>

#include "harness/profile_io.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

using refraster::CoverageModel;
using refraster::DrawList;
using refraster::PolygonMode;
using refraster::PrimitiveType;
using refraster::Profile;

// What a scene must draw for a parameter to show.
enum class Needs : std::uint8_t {
    Anything,
    Lines,          // a line (a line primitive or polygon mode line)
    Points,         // a point (a point primitive or polygon mode point)
    LinesOrPoints,  // either
    Offset,         // a polygon offset
    ModuleOffset,   // a polygon offset the draw module applies
    FillBlend,      // a blended draw at or after a draw with a fill rule
    Textures,       // a textured draw
};

// One searched profile parameter: its values, what explain calls it, and GL's word on it.
struct Parameter {
    const char* key;
    const char* rule;     // explain's name of the rule
    const char* freedom;  // the freedom GL grants, with its section
    std::vector<std::string> values;
    // Values that break a GL rule, each with the rule it breaks (after every freedom).
    std::vector<std::pair<std::string, std::string>> violations;
    Needs needs = Needs::Anything;
};

// In the order the GL verdict names a freedom when several reproduce a pixel: coverage, then
// the line and point rules, then arithmetic, then the draw module's decisions.
const std::vector<Parameter>& parameters() {
    static const std::vector<Parameter> table{
        {"subpixel_bits",
         "snapping",
         "sub-pixel precision (14.6.1: GL_SUBPIXEL_BITS, at least 4)",
         {"4", "5", "6", "7", "8"},
         {}},
        {"snap_rounding",
         "snapping",
         "sub-pixel precision (14.6.1: how window coordinates round to the sub-pixel grid)",
         {"nearest-even", "half-away", "truncate"},
         {}},
        {"tie_rule",
         "tie rule",
         "tie rule (14.6.1: any rule that gives a centre on a shared edge exactly one owner)",
         {"left-bottom", "left-top", "right-bottom", "right-top"},
         {{"none", "hole on a shared edge (no owner for a centre on it; 14.6.1)"},
          {"all", "double hit on a shared edge (two owners for a centre on it; 14.6.1)"}}},
        {"point_line_clipping",
         "clipper",
         "point and line clipping policy (13.7 by vertices, or by pixels as Vulkan does)",
         {"vertices", "pixels"},
         {},
         Needs::LinesOrPoints},
        {"clipping",
         "clipper",
         "clipping or guard band (13.7: clipping may be done by a guard band)",
         {"view-volume", "guard-band"},
         {}},
        {"line_rule",
         "line rule",
         "line rasterisation within the diamond-exit tolerance (14.5.1)",
         {"parallelogram", "bresenham"},
         {},
         Needs::Lines},
        {"point_rule",
         "point rule",
         "point rasterisation (14.4)",
         {"square", "two-triangles"},
         {},
         Needs::Points},
        {"viewport_fma",
         "fused arithmetic",
         "interpolation precision (2.3.4.1: operations to about 1 part in 10^5)",
         {"on", "off"},
         {}},
        {"depth_rounding",
         "depth rounding",
         "depth conversion precision (2.3.5)",
         {"nearest", "truncate"},
         {}},
        {"color_rounding",
         "colour rounding",
         "colour conversion precision (2.3.5)",
         {"nearest", "truncate"},
         {}},
        {"depth_clear",
         "depth clear",
         "depth conversion precision (2.3.5, of the clear value)",
         {"double", "float"},
         {}},
        {"offset_units_scale",
         "polygon offset r",
         "polygon offset's minimum resolvable difference r (14.6.5)",
         {"0.25", "0.5", "1", "2", "4"},
         {},
         Needs::Offset},
        {"texture_rho",
         "texture LOD",
         "texture LOD's scale factor rho approximated (8.14.1: between the largest partial "
         "derivative and the sum of their magnitudes)",
         {"exact", "approx"},
         {},
         Needs::Textures},
        {"texture_mip_blend",
         "mip blend",
         "trilinear filtering blending its two levels by frac(lambda) (8.14.3)",
         {"linear"},
         {{"brilinear",
           "texture LOD outside 8.14.1's bounds (brilinear filtering: lambda taken within a "
           "quarter level of the true one, 8.14.3)"}},
         Needs::Textures},
        {"texture_filtering",
         "texture filtering",
         "filtering weights at the implementation's precision (8.14.2, 2.3.4.1)",
         {"fixed-point", "float"},
         {},
         Needs::Textures},
        {"flush_denormals",
         "denormals",
         "denormalized values flushed to zero (2.3.4.1)",
         {"true", "false"},
         {}},
        {"draw_pipeline_cull",
         "cull",
         "facing decided at the implementation's precision (14.6.1, 2.3.4.1)",
         {"true", "false"},
         {}},
        {"wrapping_arithmetic",
         "integer widths",
         "results of positions beyond the implementation's range (2.3.4.1)",
         {"true", "false"},
         {}},
        {"draw_offset_nan_to_zero",
         "NaN depth from polygon offset",
         "unspecified result of a NaN depth (2.3.4.1: a zero-area triangle's polygon offset)",
         {"true", "false"},
         {},
         Needs::ModuleOffset},
        {"fill_clear_writes_tiles",
         "tile write-back",
         "colour precision kept between draws (2.3.5)",
         {"true", "false"},
         {},
         Needs::FillBlend},
        {"nine_vertex_quirk",
         "nine-vertex analysis",
         "every triangle of a draw rasterised (14.6.1)",
         {"false"},
         {{"true", "triangles of a draw dropped (14.6.1: every triangle is rasterised)"}}},
    };
    return table;
}

bool draws_lines(const DrawList& dl) {
    return std::any_of(dl.draws.begin(), dl.draws.end(),
                       [](const refraster::Draw& d) { return d.rasterizes_lines(); });
}

bool draws_points(const DrawList& dl) {
    return std::any_of(dl.draws.begin(), dl.draws.end(),
                       [](const refraster::Draw& d) { return d.rasterizes_points(); });
}

// Whether some draw has a polygon offset the draw module applies (polygon mode line or point,
// or any filled triangle under the scanline model), where a NaN offset can arise.
bool draw_module_offsets(const DrawList& dl, const Profile& p) {
    return std::any_of(dl.draws.begin(), dl.draws.end(), [&](const refraster::Draw& d) {
        return d.state.polygon_offset &&
               (d.state.polygon_mode != PolygonMode::Fill || p.model == CoverageModel::Scanline);
    });
}

// Whether a blended draw comes at or after a draw with a fill rule, where the write-back of
// softpipe's colour tiles (the clear colour's included) can show.
bool fill_rules_blend(const DrawList& dl) {
    bool fill = false;
    for (const auto& d : dl.draws) {
        fill = fill || d.state.fill_rule.has_value();
        if (fill && d.state.blend != refraster::BlendPreset::None) return true;
    }
    return false;
}

bool shows(Needs n, const DrawList& dl, const Profile& p) {
    switch (n) {
        case Needs::Anything:
            return true;
        case Needs::Lines:
            return draws_lines(dl);
        case Needs::Points:
            return draws_points(dl);
        case Needs::LinesOrPoints:
            return draws_lines(dl) || draws_points(dl);
        case Needs::Offset:
            return std::any_of(dl.draws.begin(), dl.draws.end(), [](const refraster::Draw& d) {
                return d.state.polygon_offset.has_value();
            });
        case Needs::ModuleOffset:
            return draw_module_offsets(dl, p);
        case Needs::FillBlend:
            return fill_rules_blend(dl);
        case Needs::Textures:
            return std::any_of(dl.draws.begin(), dl.draws.end(), [](const refraster::Draw& d) {
                return d.state.texture.has_value();
            });
    }
    return false;
}

// The value a parameter has in effect: viewport_fma=auto is on or off on this CPU.
std::string effective_value(const Profile& p, const std::string& key) {
    for (const auto& [k, v] : refraster::profile_parameters(p)) {
        if (k != key) continue;
        if (key == "viewport_fma" && v == "auto") return refraster::host_has_fma() ? "on" : "off";
        return v;
    }
    return "";
}

}  // namespace

// The scene with GL_MULTISAMPLE disabled ignored (every draw multisampled), or nothing when no
// draw of a 4x target disables it.
std::shared_ptr<const Scene> multisample_enable_ignored(const Scene& scene) {
    if (scene.draw_list.target.samples < 2) return nullptr;
    auto out = std::make_shared<Scene>(scene);
    bool any = false;
    for (auto& d : out->draw_list.draws) {
        any = any || !d.state.multisample;
        d.state.multisample = true;
    }
    return any ? out : nullptr;
}

// The scene with edge flags ignored: each GL_POLYGON outlined or drawn as points (polygon mode
// line or point, no fill rule) drawn as the triangles it is split into, whose internal edges
// then show; nothing when no draw is such a polygon. The triangles keep the polygon's split
// (refraster/src/stages/assembly.cpp: a fan around element 0, each triangle's vertices in the
// order the provoking-vertex convention gives, so that element 0 provokes, as a polygon's first
// vertex does), since the order of a triangle's edges decides which colour a shared end pixel
// keeps.
std::shared_ptr<const Scene> edge_flags_ignored(const Scene& scene) {
    auto out = std::make_shared<Scene>(scene);
    bool any = false;
    for (auto& d : out->draw_list.draws) {
        if (d.primitive != PrimitiveType::Polygon || d.state.fill_rule ||
            d.state.polygon_mode == PolygonMode::Fill)
            continue;
        any = true;
        const bool first = d.state.provoking_vertex == refraster::ProvokingVertex::First;
        std::vector<std::uint32_t> indices;
        for (std::size_t k = 0; k + 2 < d.element_count(); ++k) {
            const std::uint32_t v0 = d.element(0);
            const std::uint32_t a = d.element(k + 1);
            const std::uint32_t b = d.element(k + 2);
            if (first) {
                indices.insert(indices.end(), {v0, a, b});
            } else {
                indices.insert(indices.end(), {a, b, v0});
            }
        }
        d.primitive = PrimitiveType::Triangles;
        d.indices = std::move(indices);
    }
    return any ? out : nullptr;
}

std::vector<RuleVariation> rule_variations(const Profile& p, const Scene& scene) {
    const DrawList& dl = scene.draw_list;
    std::vector<RuleVariation> freedoms, violations;
    const auto add = [&](std::vector<RuleVariation>& into, const Parameter& par,
                         const std::string& value, bool legal, const std::string& gl,
                         const Profile& from) {
        if (from == p && effective_value(p, par.key) == value) return;
        Profile v = from;
        refraster::set_profile_parameter(v, par.key, value);
        if (refraster::unread_parameter(v, par.key)) return;
        if (profile_rules(v) == profile_rules(p)) return;
        into.push_back({par.rule, std::string(par.key) + "=" + value, legal, gl, v, nullptr});
    };
    // The single-owner requirement is broken on a snapped rule set: the profile's own, or
    // llvmpipe's where the profile's model has no such rule.
    const Profile snapped_base =
        p.model == CoverageModel::Snapped ? p : refraster::llvmpipe_22_3_profile();
    for (const auto& par : parameters()) {
        if (!shows(par.needs, dl, p)) continue;
        for (const auto& value : par.values) add(freedoms, par, value, true, par.freedom, p);
        for (const auto& [value, broken] : par.violations) {
            const bool owner_rule = std::string(par.key) == "tie_rule";
            add(violations, par, value, false, broken, owner_rule ? snapped_base : p);
        }
    }
    for (const auto& name : {"llvmpipe-22.3", "softpipe-22.3"}) {
        const Profile b = refraster::builtin_profile(name);
        if (profile_rules(b) != profile_rules(p)) {
            freedoms.push_back({"another implementation", name, true,
                                "another conforming implementation's rules", b, nullptr});
        }
    }
    // Requirements of the draw state, broken by ignoring it.
    if (auto s = multisample_enable_ignored(scene)) {
        violations.push_back({"multisample enable", "multisample enable ignored", false,
                              "GL_MULTISAMPLE disabled is ignored (14.3.1: single-sample "
                              "rasterization when it is off)",
                              p, std::move(s)});
    }
    if (auto s = edge_flags_ignored(scene)) {
        violations.push_back({"edge flags", "edge flags ignored", false,
                              "edge flags ignored: a polygon's internal edges are drawn (14.6.4, "
                              "polygon mode)",
                              p, std::move(s)});
    }
    freedoms.insert(freedoms.end(), violations.begin(), violations.end());
    return freedoms;
}

std::vector<std::string> search_values(const std::string& key) {
    for (const auto& par : parameters()) {
        if (par.key != key) continue;
        auto out = par.values;
        for (const auto& v : par.violations) out.push_back(v.first);
        return out;
    }
    return {};
}

std::string gl_standing(const std::string& key, const std::string& value) {
    for (const auto& par : parameters()) {
        if (par.key != key) continue;
        for (const auto& [v, broken] : par.violations)
            if (v == value) return "violation: " + broken;
        return std::string("legal: ") + par.freedom;
    }
    return "";
}

}  // namespace harness
