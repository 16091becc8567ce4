// explain_report.cpp: an explanation as text and as JSON (explanation_text, explanation_json).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "explain_shared.hpp"
#include "harness/explain.hpp"
#include "harness/profile_io.hpp"
#include "refraster/renderer.hpp"

namespace harness {

using explain_detail::kSampleOffsets;
using explain_detail::same_color;
using explain_detail::where;

namespace explain_detail {

std::string color_text(const std::array<float, 4>& c, bool is8) {
    std::ostringstream o;
    for (std::size_t k = 0; k < 4; ++k) {
        o << (k ? "," : "");
        if (is8) {
            o << static_cast<int>(c[k]);
        } else {
            o << c[k];
        }
    }
    return o.str();
}

}  // namespace explain_detail

using explain_detail::color_text;

namespace {

// The resolve of one pixel's samples as glBlitFramebuffer computes it, step by step
// (refraster::resolve_samples: ((f0 + f1) + f2) + f3 in float, times 0.25, then stored).
std::string resolve_text(const std::vector<std::array<float, 4>>& samples, bool is8) {
    refraster::Framebuffer ms(1, 1,
                              is8 ? refraster::ColorFormat::Rgba8 : refraster::ColorFormat::Rgba32f,
                              refraster::DepthFormat::None, 4);
    for (std::size_t s = 0; s < 4 && s < samples.size(); ++s) {
        for (std::size_t c = 0; c < 4; ++c) {
            if (is8) {
                ms.color8[s * 4 + c] = static_cast<std::uint8_t>(samples[s][c]);
            } else {
                ms.color32f[s * 4 + c] = samples[s][c];
            }
        }
    }
    const auto out = refraster::resolve_samples(ms);
    std::ostringstream o;
    o.precision(9);
    o << "resolve (each sample" << (is8 ? " as byte * fl(1/255)" : "")
      << ", summed in sample order, times 0.25):\n";
    static const char* const kChannel = "RGBA";
    for (std::size_t c = 0; c < 4; ++c) {
        float sum = 0.0f;
        o << "  " << kChannel[c] << ": ";
        for (std::size_t s = 0; s < 4; ++s) {
            const float f = is8 ? static_cast<float>(ms.color8[s * 4 + c]) * (1.0f / 255.0f)
                                : ms.color32f[s * 4 + c];
            sum = s == 0 ? f : sum + f;
            o << (s == 0 ? "" : " + ") << f;
        }
        o << " = " << sum << ", times 0.25 = " << sum * 0.25f;
        if (is8) {
            o << " -> " << static_cast<int>(out.color8[c]);
        } else {
            o << " -> " << out.color32f[c];
        }
        o << "\n";
    }
    return o.str();
}

// What the sampler decided for a textured fragment (docs/precision.md, "Textures").
void write_texture_trace(std::ostream& o, const refraster::TextureTrace& t) {
    o << "    texture (" << (t.aos ? "8-bit path" : "float path") << "): s " << t.coord[0] << " t "
      << t.coord[1]
      << (t.point_coord ? " (point sprite coordinates: the fragment's place in its point)\n"
                        : " (after the division by q)\n");
    o << "      quad derivatives in base texels: ds/dx " << t.rho_terms[0] << " dt/dx "
      << t.rho_terms[1] << " ds/dy " << t.rho_terms[2] << " dt/dy " << t.rho_terms[3] << "; rho^2 "
      << t.rho2 << (t.minified ? " > 1: minified, min filter" : " <= 1 or no LOD: mag filter")
      << "\n";
    const bool two = t.level0 != t.level1;
    o << "      " << (t.linear ? "bilinear" : "nearest") << " in level " << t.level0;
    if (two) {
        o << " and level " << t.level1 << " (lod " << t.lod << ", weight " << t.level_weight;
        if (t.aos) o << ", 8-bit " << t.level_weight8 << "/256";
        o << ")";
    } else if (t.lod != 0.0f) {
        o << " (lod " << t.lod << ")";
    }
    o << "\n";
    for (std::size_t l = 0; l < (two ? 2u : 1u); ++l) {
        const auto& x = t.texels[l];
        const auto& b = t.border[l];
        o << "      level " << (l == 0 ? t.level0 : t.level1) << ": ";
        if (t.linear) {
            o << "texels x " << x[0] << ", " << x[1] << " y " << x[2] << ", " << x[3];
            if (t.aos) {
                o << ", weights " << t.weights[l][0] << "/256 along s, " << t.weights[l][1]
                  << "/256 along t: L(w, a, b) = a + ((w (b - a) + 128) >> 8), s first";
            } else {
                o << ", weights " << t.weights[l][0] << " along s, " << t.weights[l][1]
                  << " along t: fma(w, b - a, a), s first";
            }
            if (b[0] || b[1] || b[2] || b[3]) {
                o << "; border colour at";
                static const char* const kCorner[4] = {" (x0,y0)", " (x1,y0)", " (x0,y1)",
                                                       " (x1,y1)"};
                for (std::size_t k = 0; k < 4; ++k)
                    if (b[k]) o << kCorner[k];
            }
        } else {
            o << "texel (" << x[0] << ", " << x[2] << ")" << (b[0] ? ": border colour" : "");
        }
        o << "\n";
    }
    o << "      texel colour " << t.color[0] << ", " << t.color[1] << ", " << t.color[2] << ", "
      << t.color[3] << "\n";
}

nlohmann::ordered_json texture_trace_json(const refraster::TextureTrace& t) {
    nlohmann::ordered_json j{{"path", t.aos ? "8-bit" : "float"},
                             {"coord", t.coord},
                             {"point_coord", t.point_coord},
                             {"rho_terms", t.rho_terms},
                             {"rho2", t.rho2},
                             {"minified", t.minified},
                             {"lod", t.lod},
                             {"level0", t.level0},
                             {"level1", t.level1},
                             {"level_weight", t.level_weight},
                             {"level_weight8", t.level_weight8},
                             {"filter", t.linear ? "linear" : "nearest"},
                             {"texels", t.texels},
                             {"weights", t.weights},
                             {"border", t.border},
                             {"color", t.color}};
    return j;
}

}  // namespace

std::string explanation_text(const Explanation& e) {
    std::ostringstream o;
    const auto& t = e.trace;
    const bool is8 = e.reference_image.color_format == refraster::ColorFormat::Rgba8;
    o << "pixel (" << t.x << ", " << t.y << "), centre (" << t.x + 0.5 << ", " << t.y + 0.5 << ")";
    if (!e.reference_samples.empty()) {
        const auto k = static_cast<std::size_t>(t.sample);
        o << ", sample " << t.sample << " at (" << t.x + kSampleOffsets[k][0] << ", "
          << t.y + kSampleOffsets[k][1] << ")" << (e.sample < 0 ? " (the resolved pixel)" : "");
    }
    o << ", profile " << t.profile << "\n";
    o << "rules: " << profile_rules(e.profile) << "\n";
    if (t.primitives.empty()) o << "  no primitive reaches this pixel\n";
    for (const auto& p : t.primitives) {
        o << "\n"
          << where(p)
          << (p.multisample ? (p.covered ? ": covers the sample" : ": does not cover the sample")
                            : (p.covered ? ": covers the pixel" : ": does not cover the pixel"))
          << "\n";
        for (std::size_t i = 0; i < p.clip.size(); ++i) {
            o << "  vertex " << p.vertices[i] << " clip (" << p.clip[i][0] << ", " << p.clip[i][1]
              << ", " << p.clip[i][2] << ", " << p.clip[i][3] << ") clip mask " << p.clipmask[i]
              << "\n";
        }
        if (p.in_draw_pipeline) o << "  its vertex segment goes through the draw pipeline\n";
        for (const auto& poly : p.clipped_polygon) {
            o << "  clipped polygon:";
            for (const auto& v : poly)
                o << " (" << v[0] << ", " << v[1] << ", " << v[2] << ", " << v[3] << ")";
            o << "\n";
        }
        if (!p.note.empty()) o << "  " << p.note << "\n";
        for (const auto& s : p.setups) {
            o << "  setup: " << s.outcome << (s.clipped ? " (clipper output)" : "") << "\n";
            for (const auto& w : s.window)
                o << "    window (" << w[0] << ", " << w[1] << ") z " << w[2] << " 1/w " << w[3]
                  << "\n";
            if (!s.x.empty()) {
                o << "    snapped (1/" << (1 << s.subpixel_bits)
                  << (p.multisample ? " px, pixel corner at 0):" : " px, pixel centre at 0):");
                for (std::size_t i = 0; i < s.x.size(); ++i)
                    o << " (" << s.x[i] << ", " << s.y[i] << ")";
                o << "\n";
                // setup_triangle swaps two corners of a triangle that is counter-clockwise in
                // GL's window space (swap_to_ccw), keeping the provoking vertex in place.
                if (s.x.size() == 3 && s.order != std::array<int, 3>{0, 1, 2}) {
                    o << "    (corners in setup's order: window vertices " << s.order[0] << ", "
                      << s.order[1] << ", " << s.order[2]
                      << "; two swapped so that the edges run one way for every triangle)\n";
                }
            }
            if (s.area != 0) {
                // llvmpipe's sign: (x0 - x1)(y2 - y0) - (x2 - x0)(y0 - y1), before the swap.
                o << "    area " << s.area << " (twice the signed area in (1/"
                  << (1 << s.subpixel_bits) << " px)^2; llvmpipe's sign: "
                  << (s.area > 0 ? "positive, clockwise" : "negative, counter-clockwise")
                  << " in GL's window space, y up): " << (s.front_facing ? "front" : "back")
                  << "-facing\n";
            }
            if (s.edges.size() == 3 && s.x.size() == 3) {
                o << "    edge k runs from corner k to the next: a = y_k - y_next, b = x_k - "
                     "x_next, "
                     "c = a x_k - b y_k, plus 1 when the edge owns ties (the tie rule); E = c - a "
                     "x "
                     "+ b y at the "
                  << (p.multisample ? "sample" : "pixel centre")
                  << " in the same units; the primitive covers it when E > 0 for every edge\n";
            }
            for (std::size_t k = 0; k < s.edges.size(); ++k) {
                const auto& ed = s.edges[k];
                o << "    edge " << k << ": a " << ed.a << " b " << ed.b << " c " << ed.c
                  << (p.multisample ? ", E at the sample " : ", E at pixel ") << ed.value
                  << (ed.tie ? (p.multisample ? "  <- sample exactly on this edge; "
                                              : "  <- centre exactly on this edge; ")
                             : "")
                  << (ed.tie ? (ed.owns_ties ? "owned" : "not owned") : "") << "\n";
            }
            if (!s.coverage_note.empty()) o << "    " << s.coverage_note << "\n";
            if (s.has_fragment) {
                const auto& f = s.fragment;
                o << "    z plane A0 " << f.z_plane[0] << " dz/dx " << f.z_plane[1] << " dz/dy "
                  << f.z_plane[2] << ", offset " << f.z_offset << "\n";
                if (f.depth_tested) {
                    o << "    depth " << f.z << " -> " << f.depth_value << " vs stored "
                      << f.depth_stored << (f.depth_pass ? ": passes" : ": fails") << "\n";
                }
                if (f.textured) write_texture_trace(o, f.texture);
                o << "    shader colour " << f.shader_color[0] << ", " << f.shader_color[1] << ", "
                  << f.shader_color[2] << ", " << f.shader_color[3] << "; destination "
                  << color_text(f.destination, is8) << "; written " << color_text(f.written, is8)
                  << "\n";
            }
        }
    }
    if (!e.reference_samples.empty()) {
        o << "\nsamples (position in the pixel; reference" << (e.backend ? " | backend" : "")
          << "):\n";
        for (std::size_t k = 0; k < e.reference_samples.size(); ++k) {
            o << "  " << k << " (" << kSampleOffsets[k][0] << ", " << kSampleOffsets[k][1]
              << "): " << color_text(e.reference_samples[k], is8);
            if (e.reference_sample_depths[k]) o << " depth " << *e.reference_sample_depths[k];
            if (k < e.backend_samples.size()) {
                o << " | " << color_text(e.backend_samples[k], is8);
                if (e.backend_sample_depths[k]) o << " depth " << *e.backend_sample_depths[k];
                if (!same_color(e.reference_samples[k], e.backend_samples[k]) ||
                    e.reference_sample_depths[k] != e.backend_sample_depths[k])
                    o << "  <- differs";
            }
            o << "\n";
        }
        o << resolve_text(e.reference_samples, is8);
    }
    o << "\nreference" << (e.sample >= 0 ? " sample " + std::to_string(e.sample) : "") << ": "
      << color_text(e.reference_color, is8);
    if (e.reference_depth) o << " depth " << *e.reference_depth;
    o << "\n";
    if (e.backend) {
        o << "backend" << (e.sample >= 0 ? " sample " + std::to_string(e.sample) : "") << ":   "
          << color_text(e.backend_color, is8);
        if (e.backend_depth) o << " depth " << *e.backend_depth;
        o << "\n";
    }
    o << "verdict: " << e.verdict << "\n";
    return o.str();
}

std::string explanation_json(const Explanation& e) {
    nlohmann::ordered_json j;
    const auto& t = e.trace;
    j["pixel"] = {t.x, t.y};
    if (!e.reference_samples.empty()) j["sample"] = e.sample;
    j["profile"] = t.profile;
    j["profile_rules"] = profile_rules(e.profile);
    j["verdict"] = e.verdict;
    j["difference"] = e.difference;
    j["rule"] = e.rule;
    if (!e.standing.empty()) j["gl_standing"] = e.standing;
    auto& cj = j["candidates"] = nlohmann::ordered_json::array();
    for (const auto& [rule, change] : e.candidates)
        cj.push_back({{"rule", rule}, {"alternative", change}});
    j["agree"] = e.agree;
    j["reference"] = {{"color", e.reference_color}};
    if (e.reference_depth) j["reference"]["depth"] = *e.reference_depth;
    if (!e.gl_verdict.empty()) j["gl_verdict"] = e.gl_verdict;
    if (e.backend) {
        // Which implementation drew it: the backend's own record of itself (renderer, driver,
        // versions, the environment that chose it).
        j["backend"] = {{"color", e.backend_color}};
        if (e.backend_depth) j["backend"]["depth"] = *e.backend_depth;
        auto& pv = j["backend"]["provenance"] = nlohmann::ordered_json::object();
        for (const auto& [k, v] : e.backend->provenance) pv[k] = v;
    }
    const auto samples_json = [](const std::vector<std::array<float, 4>>& colors,
                                 const std::vector<std::optional<std::uint32_t>>& depths) {
        auto a = nlohmann::ordered_json::array();
        for (std::size_t k = 0; k < colors.size(); ++k) {
            nlohmann::ordered_json sj{{"color", colors[k]}};
            if (depths[k]) sj["depth"] = *depths[k];
            a.push_back(sj);
        }
        return a;
    };
    if (!e.reference_samples.empty()) {
        j["reference"]["samples"] = samples_json(e.reference_samples, e.reference_sample_depths);
        if (e.backend)
            j["backend"]["samples"] = samples_json(e.backend_samples, e.backend_sample_depths);
    }
    auto& prims = j["primitives"] = nlohmann::ordered_json::array();
    for (const auto& p : t.primitives) {
        nlohmann::ordered_json pj;
        pj["draw"] = p.draw;
        pj["primitive"] = p.primitive;
        pj["kind"] = p.kind;
        pj["covered"] = p.covered;
        pj["per_sample"] = p.multisample;
        pj["vertices"] = p.vertices;
        pj["clip"] = p.clip;
        pj["clipmask"] = p.clipmask;
        pj["in_draw_pipeline"] = p.in_draw_pipeline;
        pj["clipped_polygon"] = p.clipped_polygon;
        if (!p.note.empty()) pj["note"] = p.note;
        auto& sj = pj["setups"] = nlohmann::ordered_json::array();
        for (const auto& s : p.setups) {
            nlohmann::ordered_json x;
            x["outcome"] = s.outcome;
            x["clipped"] = s.clipped;
            x["window"] = s.window;
            x["snapped_x"] = s.x;
            x["snapped_y"] = s.y;
            x["subpixel_bits"] = s.subpixel_bits;
            if (s.x.size() == 3) x["corner_order"] = s.order;
            x["area"] = s.area;
            x["front_facing"] = s.front_facing;
            auto& ej = x["edges"] = nlohmann::ordered_json::array();
            for (const auto& ed : s.edges) {
                ej.push_back({{"a", ed.a},
                              {"b", ed.b},
                              {"c", ed.c},
                              {"owns_ties", ed.owns_ties},
                              {"value", ed.value},
                              {"tie", ed.tie}});
            }
            x["covered"] = s.covered;
            if (!s.coverage_note.empty()) x["coverage_note"] = s.coverage_note;
            if (s.has_fragment) {
                const auto& f = s.fragment;
                x["fragment"] = {{"z_plane", f.z_plane},
                                 {"w_plane", f.w_plane},
                                 {"z_offset", f.z_offset},
                                 {"z", f.z},
                                 {"depth_tested", f.depth_tested},
                                 {"depth_value", f.depth_value},
                                 {"depth_stored", f.depth_stored},
                                 {"depth_pass", f.depth_pass},
                                 {"shader_color", f.shader_color},
                                 {"destination", f.destination},
                                 {"written", f.written}};
                if (f.textured) x["fragment"]["texture"] = texture_trace_json(f.texture);
            }
            sj.push_back(x);
        }
        prims.push_back(pj);
    }
    return j.dump(1);
}

}  // namespace harness
