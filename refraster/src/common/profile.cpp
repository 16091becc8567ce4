#include "refraster/profile.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <initializer_list>

namespace refraster {

Profile llvmpipe_22_3_profile() {
    return Profile{};
}

Profile gl_exact_profile() {
    Profile p;
    p.name = "gl-exact";
    p.model = CoverageModel::Exact;
    // Not used by the exact model; kept at llvmpipe's values so that a profile file stays
    // meaningful when its coverage model is switched.
    p.quirks.draw_pipeline_cull = false;
    p.quirks.nine_vertex_quirk = false;
    p.quirks.wrapping_arithmetic = false;
    return p;
}

Profile softpipe_22_3_profile() {
    Profile p;
    p.name = "softpipe-22.3";
    p.model = CoverageModel::Scanline;
    // No snapping: the subpixel parameters are llvmpipe's, unused by the scanline model.
    // softpipe's tie rule in an FBO (sp_setup.c: spans [ceil-truncated left, right), rows from
    // ceilf(y - 0.5)): right edges and bottom edges own their centres.
    p.gl.tie_rule = TieRule::RightBottom;
    // softpipe's draw module is the C one (sp_context.c: draw_create_no_llvm): the viewport
    // transform is x * (1/w) * scale + translate, unfused (draw_cliptest_tmp.h).
    p.gl.viewport_fma = FmaMode::Off;
    p.gl.depth_rounding = Rounding::Truncate;  // sp_quad_depth_test.c convert_quad_depth
    p.gl.line_rule = LineRule::Bresenham;
    p.gl.point_rule = PointRule::TwoTriangles;
    p.quirks.nine_vertex_quirk = false;
    p.quirks.wrapping_arithmetic = false;
    return p;
}

std::vector<std::string> builtin_profile_names() {
    return {"llvmpipe-22.3", "softpipe-22.3", "gl-exact"};
}

Profile builtin_profile(const std::string& name) {
    if (name == "llvmpipe-22.3") return llvmpipe_22_3_profile();
    if (name == "gl-exact") return gl_exact_profile();
    if (name == "softpipe-22.3") return softpipe_22_3_profile();
    throw ProfileError("unknown profile \"" + name +
                       "\" (built in: llvmpipe-22.3, softpipe-22.3, gl-exact)");
}

std::string to_string(TieRule r) {
    switch (r) {
        case TieRule::LeftBottom:
            return "left-bottom";
        case TieRule::LeftTop:
            return "left-top";
        case TieRule::RightBottom:
            return "right-bottom";
        case TieRule::RightTop:
            return "right-top";
        case TieRule::None:
            return "none";
        case TieRule::All:
            return "all";
    }
    return "?";
}

std::string to_string(SnapRounding r) {
    switch (r) {
        case SnapRounding::NearestEven:
            return "nearest-even";
        case SnapRounding::HalfAwayFromZero:
            return "half-away";
        case SnapRounding::Truncate:
            return "truncate";
    }
    return "?";
}

std::string to_string(Rounding r) {
    return r == Rounding::Nearest ? "nearest" : "truncate";
}
std::string to_string(LineRule r) {
    return r == LineRule::Parallelogram ? "parallelogram" : "bresenham";
}
std::string to_string(PointRule r) {
    return r == PointRule::Square ? "square" : "two-triangles";
}

namespace {

std::string to_string(ClearPrecision c) {
    return c == ClearPrecision::Double ? "double" : "float";
}

std::string to_string(CoverageModel c) {
    switch (c) {
        case CoverageModel::Snapped:
            return "snapped";
        case CoverageModel::Exact:
            return "exact";
        case CoverageModel::Scanline:
            return "scanline";
    }
    return "?";
}
std::string to_string(FmaMode m) {
    return m == FmaMode::Auto ? "auto" : m == FmaMode::On ? "on" : "off";
}
std::string to_string(Clipping c) {
    return c == Clipping::ViewVolume ? "view-volume" : "guard-band";
}
}  // namespace

std::string to_string(TextureRho r) {
    return r == TextureRho::Exact ? "exact" : "approx";
}
std::string to_string(MipBlend b) {
    return b == MipBlend::Linear ? "linear" : "brilinear";
}
std::string to_string(TextureFiltering f) {
    return f == TextureFiltering::FixedPoint ? "fixed-point" : "float";
}

namespace {

std::string to_string(PointLineClipping c) {
    return c == PointLineClipping::Vertices ? "vertices" : "pixels";
}
std::string bool_text(bool b) {
    return b ? "true" : "false";
}

std::string float_text(float f) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, f);
    return std::string(buf, r.ptr);
}

[[noreturn]] void bad(const std::string& key, const std::string& value,
                      const std::string& expected) {
    throw ProfileError("profile parameter " + key + "=" + value + ": expected " + expected);
}

template <class E>
E pick(const std::string& key, const std::string& value,
       std::initializer_list<std::pair<const char*, E>> options) {
    std::string list;
    for (const auto& [n, e] : options) {
        if (value == n) return e;
        list += (list.empty() ? "" : ", ") + std::string(n);
    }
    bad(key, value, "one of " + list);
}

bool parse_bool(const std::string& key, const std::string& value) {
    return pick<bool>(key, value, {{"true", true}, {"false", false}});
}

int parse_int(const std::string& key, const std::string& value, int lo, int hi) {
    int v = 0;
    const auto r = std::from_chars(value.data(), value.data() + value.size(), v);
    if (r.ec != std::errc() || r.ptr != value.data() + value.size() || v < lo || v > hi) {
        bad(key, value, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    return v;
}

float parse_float(const std::string& key, const std::string& value) {
    float v = 0;
    const auto r = std::from_chars(value.data(), value.data() + value.size(), v);
    if (r.ec != std::errc() || r.ptr != value.data() + value.size() || !(v >= 0.0f && v < 1.0f)) {
        bad(key, value, "a number in [0, 1)");
    }
    return v;
}

// A power of two 2^lo to 2^hi, written as text: "1", "2", "0.5", "0.0625".
float parse_power_of_two(const std::string& key, const std::string& value, int lo, int hi) {
    float v = 0;
    const auto r = std::from_chars(value.data(), value.data() + value.size(), v);
    int e = 0;
    const bool power = r.ec == std::errc() && r.ptr == value.data() + value.size() && v > 0.0f &&
                       std::frexp(v, &e) == 0.5f && e - 1 >= lo && e - 1 <= hi;
    if (!power) {
        bad(key, value,
            "a power of two from " + float_text(std::ldexp(1.0f, lo)) + " to " +
                float_text(std::ldexp(1.0f, hi)));
    }
    return v;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> profile_parameters(const Profile& p) {
    return {
        {"name", p.name},
        {"coverage", to_string(p.model)},
        {"subpixel_bits", std::to_string(p.gl.subpixel_bits)},
        {"snap_rounding", to_string(p.gl.snap_rounding)},
        {"pixel_center_offset", float_text(p.gl.pixel_center_offset)},
        {"tie_rule", to_string(p.gl.tie_rule)},
        {"clipping", to_string(p.gl.clipping)},
        {"point_line_clipping", to_string(p.gl.point_line_clipping)},
        {"viewport_fma", to_string(p.gl.viewport_fma)},
        {"flush_denormals", bool_text(p.gl.flush_denormals)},
        {"depth_rounding", to_string(p.gl.depth_rounding)},
        {"color_rounding", to_string(p.gl.color_rounding)},
        {"depth_clear", to_string(p.gl.depth_clear)},
        {"line_rule", to_string(p.gl.line_rule)},
        {"point_rule", to_string(p.gl.point_rule)},
        {"offset_units_scale", float_text(p.gl.offset_units_scale)},
        {"texture_rho", to_string(p.gl.texture_rho)},
        {"texture_mip_blend", to_string(p.gl.texture_mip_blend)},
        {"texture_filtering", to_string(p.gl.texture_filtering)},
        {"draw_pipeline_cull", bool_text(p.quirks.draw_pipeline_cull)},
        {"draw_segment_vertices", std::to_string(p.quirks.draw_segment_vertices)},
        {"nine_vertex_quirk", bool_text(p.quirks.nine_vertex_quirk)},
        {"wrapping_arithmetic", bool_text(p.quirks.wrapping_arithmetic)},
        {"draw_offset_nan_to_zero", bool_text(p.quirks.draw_offset_nan_to_zero)},
        {"fill_clear_writes_tiles", bool_text(p.quirks.fill_clear_writes_tiles)},
    };
}

void set_profile_parameter(Profile& p, const std::string& key, const std::string& value) {
    if (key == "name") {
        if (value.empty()) bad(key, value, "a non-empty name");
        p.name = value;
    } else if (key == "coverage") {
        p.model = pick<CoverageModel>(key, value,
                                      {{"snapped", CoverageModel::Snapped},
                                       {"exact", CoverageModel::Exact},
                                       {"scanline", CoverageModel::Scanline}});
    } else if (key == "subpixel_bits") {
        // 8 bits is llvmpipe's FIXED_ORDER; the edge-function budget in setup.cpp holds up to 8.
        p.gl.subpixel_bits = parse_int(key, value, 1, 8);
    } else if (key == "snap_rounding") {
        p.gl.snap_rounding = pick<SnapRounding>(key, value,
                                                {{"nearest-even", SnapRounding::NearestEven},
                                                 {"half-away", SnapRounding::HalfAwayFromZero},
                                                 {"truncate", SnapRounding::Truncate}});
    } else if (key == "pixel_center_offset") {
        p.gl.pixel_center_offset = parse_float(key, value);
    } else if (key == "tie_rule") {
        p.gl.tie_rule = pick<TieRule>(key, value,
                                      {{"left-bottom", TieRule::LeftBottom},
                                       {"left-top", TieRule::LeftTop},
                                       {"right-bottom", TieRule::RightBottom},
                                       {"right-top", TieRule::RightTop},
                                       {"none", TieRule::None},
                                       {"all", TieRule::All}});
    } else if (key == "clipping") {
        p.gl.clipping = pick<Clipping>(
            key, value,
            {{"view-volume", Clipping::ViewVolume}, {"guard-band", Clipping::GuardBand}});
    } else if (key == "point_line_clipping") {
        p.gl.point_line_clipping = pick<PointLineClipping>(
            key, value,
            {{"vertices", PointLineClipping::Vertices}, {"pixels", PointLineClipping::Pixels}});
    } else if (key == "viewport_fma") {
        p.gl.viewport_fma = pick<FmaMode>(
            key, value, {{"auto", FmaMode::Auto}, {"on", FmaMode::On}, {"off", FmaMode::Off}});
    } else if (key == "flush_denormals") {
        p.gl.flush_denormals = parse_bool(key, value);
    } else if (key == "depth_rounding" || key == "color_rounding") {
        (key == "depth_rounding" ? p.gl.depth_rounding : p.gl.color_rounding) = pick<Rounding>(
            key, value, {{"nearest", Rounding::Nearest}, {"truncate", Rounding::Truncate}});
    } else if (key == "depth_clear") {
        p.gl.depth_clear = pick<ClearPrecision>(
            key, value, {{"double", ClearPrecision::Double}, {"float", ClearPrecision::Float}});
    } else if (key == "line_rule") {
        p.gl.line_rule = pick<LineRule>(
            key, value,
            {{"parallelogram", LineRule::Parallelogram}, {"bresenham", LineRule::Bresenham}});
    } else if (key == "point_rule") {
        p.gl.point_rule = pick<PointRule>(
            key, value,
            {{"square", PointRule::Square}, {"two-triangles", PointRule::TwoTriangles}});
    } else if (key == "offset_units_scale") {
        p.gl.offset_units_scale = parse_power_of_two(key, value, -4, 4);
    } else if (key == "texture_rho") {
        p.gl.texture_rho = pick<TextureRho>(
            key, value, {{"exact", TextureRho::Exact}, {"approx", TextureRho::Approx}});
    } else if (key == "texture_mip_blend") {
        p.gl.texture_mip_blend = pick<MipBlend>(
            key, value, {{"linear", MipBlend::Linear}, {"brilinear", MipBlend::Brilinear}});
    } else if (key == "texture_filtering") {
        p.gl.texture_filtering = pick<TextureFiltering>(
            key, value,
            {{"fixed-point", TextureFiltering::FixedPoint}, {"float", TextureFiltering::Float}});
    } else if (key == "draw_pipeline_cull") {
        p.quirks.draw_pipeline_cull = parse_bool(key, value);
    } else if (key == "draw_segment_vertices") {
        p.quirks.draw_segment_vertices = parse_int(key, value, 3, 1 << 20);
    } else if (key == "nine_vertex_quirk") {
        p.quirks.nine_vertex_quirk = parse_bool(key, value);
    } else if (key == "wrapping_arithmetic") {
        p.quirks.wrapping_arithmetic = parse_bool(key, value);
    } else if (key == "draw_offset_nan_to_zero") {
        p.quirks.draw_offset_nan_to_zero = parse_bool(key, value);
    } else if (key == "fill_clear_writes_tiles") {
        p.quirks.fill_clear_writes_tiles = parse_bool(key, value);
    } else {
        std::string keys;
        for (const auto& [k, _] : profile_parameters(Profile{}))
            keys += (keys.empty() ? "" : ", ") + k;
        throw ProfileError("unknown profile parameter \"" + key + "\" (known: " + keys + ")");
    }
}

std::optional<std::string> unread_parameter(const Profile& p, const std::string& key) {
    const auto is = [&](std::initializer_list<const char*> keys) {
        return std::any_of(keys.begin(), keys.end(), [&](const char* k) { return key == k; });
    };
    switch (p.model) {
        case CoverageModel::Snapped:
            // softpipe's tile cache: no such cache in the snapped model (softpipe_model.cpp).
            if (key == "fill_clear_writes_tiles")
                return "the snapped model keeps no softpipe tile cache";
            // setup.cpp, setup_triangle: the wrapping path exists for llvmpipe's own 24.8 grid.
            if (key == "wrapping_arithmetic" &&
                (p.gl.subpixel_bits != 8 || p.gl.snap_rounding != SnapRounding::NearestEven))
                return "the snapped model wraps only on llvmpipe's own grid (subpixel_bits=8, "
                       "snap_rounding=nearest-even)";
            return std::nullopt;
        case CoverageModel::Scanline: {
            // softpipe's triangles use float window coordinates (scanline_setup.cpp); its own
            // lines and points likewise. Only draws routed to llvmpipe's rules snap.
            const bool snapped_route =
                p.gl.line_rule == LineRule::Parallelogram || p.gl.point_rule == PointRule::Square;
            if (is({"snap_rounding", "nine_vertex_quirk", "wrapping_arithmetic"}))
                return "the scanline model does not snap and has none of llvmpipe's setup quirks";
            if (is({"subpixel_bits", "pixel_center_offset", "tie_rule", "texture_rho",
                    "texture_mip_blend", "texture_filtering"}) &&
                !snapped_route)
                return "the scanline model draws from float window coordinates; it reads " + key +
                       " only for lines or points drawn by llvmpipe's rules (line_rule="
                       "parallelogram or point_rule=square)";
            return std::nullopt;
        }
        case CoverageModel::Exact:
            if (is({"name", "coverage", "flush_denormals", "depth_clear", "offset_units_scale"}))
                return std::nullopt;
            if (key == "tie_rule") {
                if (p.gl.tie_rule == TieRule::None || p.gl.tie_rule == TieRule::All)
                    return "the exact model's ownership test has no tie_rule=" +
                           to_string(p.gl.tie_rule);
                return std::nullopt;
            }
            return "the exact model has no clipper, snapping, conversion rounding, line or point "
                   "rules or driver quirks";
    }
    return std::nullopt;
}

}  // namespace refraster
