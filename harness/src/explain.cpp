#include "harness/explain.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "refraster/renderer.hpp"

namespace harness {

namespace {

std::array<float, 4> color_at(const refraster::Framebuffer& fb, int x, int y) {
    const std::size_t i = 4 * fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    std::array<float, 4> c{};
    for (std::size_t k = 0; k < 4; ++k) {
        c[k] = fb.color_format == refraster::ColorFormat::Rgba8 ? fb.color8[i + k] : fb.color32f[i + k];
    }
    return c;
}

std::optional<std::uint32_t> depth_at(const refraster::Framebuffer& fb, int x, int y) {
    if (fb.depth_format == refraster::DepthFormat::None) return std::nullopt;
    return fb.depth[fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y))];
}

bool same_color(const std::array<float, 4>& a, const std::array<float, 4>& b) {
    for (std::size_t k = 0; k < 4; ++k) {
        if (std::bit_cast<std::uint32_t>(a[k]) != std::bit_cast<std::uint32_t>(b[k])) return false;
    }
    return true;
}

std::string tie_rule_name(const refraster::Profile& p) { return refraster::to_string(p.tie_rule); }

std::string where(const refraster::PrimitiveTrace& p) {
    return "draws[" + std::to_string(p.draw) + "] " + p.kind + " " + std::to_string(p.primitive);
}

// The first rule where the reference and the backend can part at this pixel.
void judge(Explanation& e, const refraster::Profile& profile) {
    const auto& t = e.trace;
    const std::string px = "(" + std::to_string(t.x) + ", " + std::to_string(t.y) + ")";
    if (!e.backend) {
        e.rule = "none";
        e.verdict = "reference only at " + px;
        return;
    }
    if (e.agree) {
        e.rule = "none";
        e.verdict = "the reference and the backend agree at " + px;
        return;
    }
    // 1. A centre exactly on an edge whose ownership alone decides coverage.
    for (const auto& p : t.primitives) {
        for (const auto& s : p.setups) {
            for (std::size_t k = 0; k < s.edges.size(); ++k) {
                if (!s.edges[k].tie) continue;
                bool others_inside = true;
                for (std::size_t j = 0; j < s.edges.size(); ++j) {
                    if (j != k && !(s.edges[j].value > 0)) others_inside = false;
                }
                if (!others_inside) continue;
                e.rule = "tie rule";
                e.verdict = "tie rule: the centre of pixel " + px + " lies exactly on edge " + std::to_string(k) +
                            " of " + where(p) + ", and the " + tie_rule_name(profile) + " rule " +
                            (s.edges[k].owns_ties ? "gives the pixel to it" : "keeps the pixel from it") +
                            "; the backend decided the tie the other way";
                return;
            }
        }
    }
    // 2. An edge within one subpixel step of the centre: snapping decides.
    for (const auto& p : t.primitives) {
        for (const auto& s : p.setups) {
            for (std::size_t k = 0; k < s.edges.size(); ++k) {
                const auto& ed = s.edges[k];
                const std::int64_t raw = ed.value - (ed.owns_ties ? 1 : 0);
                const std::int64_t step = (std::abs(static_cast<std::int64_t>(ed.a)) + std::abs(static_cast<std::int64_t>(ed.b)));
                if (step != 0 && std::llabs(raw) <= step) {
                    e.rule = "snapping";
                    e.verdict = "snapping: edge " + std::to_string(k) + " of " + where(p) +
                                " passes within one subpixel step of the centre of pixel " + px +
                                " (edge value " + std::to_string(raw) + "), so how the vertices snap decides coverage";
                    return;
                }
            }
        }
    }
    // 3. The clipper made the geometry there.
    for (const auto& p : t.primitives) {
        for (const auto& s : p.setups) {
            if (s.clipped) {
                e.rule = "clipper";
                e.verdict = "clipper: " + where(p) + " was clipped and its new vertices set the pixel's coverage or "
                            "attributes at " + px;
                return;
            }
        }
    }
    if (same_color(e.reference_color, e.backend_color)) {
        e.rule = "depth";
        e.verdict = "depth: coverage and colour agree at " + px + " but the depth values differ (depth plane, "
                    "polygon offset or quantisation)";
        return;
    }
    e.rule = "colour";
    e.verdict = "colour: no edge is in doubt at " + px + "; the colours differ (attribute interpolation, output "
                "conversion or blending)";
}

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

}  // namespace

Explanation explain_pixel(const Scene& scene, const refraster::Profile& profile, int x, int y, Backend* backend) {
    const auto& target = scene.draw_list.target;
    if (x < 0 || y < 0 || static_cast<std::uint32_t>(x) >= target.width || static_cast<std::uint32_t>(y) >= target.height) {
        throw std::runtime_error("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                                 std::to_string(target.width) + "x" + std::to_string(target.height) + " target");
    }
    Explanation e;
    e.trace.x = x;
    e.trace.y = y;
    refraster::RenderOptions o;
    o.profile = profile;
    o.trace = &e.trace;
    const auto r = refraster::render(scene.draw_list, o, e.reference_image);
    if (r.status != refraster::RenderStatus::Ok) throw std::runtime_error("the reference cannot render it: " + r.message);
    e.reference_color = color_at(e.reference_image, x, y);
    e.reference_depth = depth_at(e.reference_image, x, y);
    if (backend != nullptr) {
        e.backend = backend->render(scene);
        if (e.backend->status != RenderStatus::Ok) {
            throw std::runtime_error(backend->name() + ": " + std::string(to_string(e.backend->status)) + ": " +
                                     e.backend->message);
        }
        e.backend_color = color_at(e.backend->image, x, y);
        e.backend_depth = depth_at(e.backend->image, x, y);
        e.agree = same_color(e.reference_color, e.backend_color) && e.reference_depth == e.backend_depth;
    }
    judge(e, profile);
    return e;
}

std::string explanation_text(const Explanation& e) {
    std::ostringstream o;
    const auto& t = e.trace;
    const bool is8 = e.reference_image.color_format == refraster::ColorFormat::Rgba8;
    o << "pixel (" << t.x << ", " << t.y << "), centre (" << t.x + 0.5 << ", " << t.y + 0.5 << "), profile " << t.profile << "\n";
    if (t.primitives.empty()) o << "  no primitive reaches this pixel\n";
    for (const auto& p : t.primitives) {
        o << "\n" << where(p) << (p.covered ? ": covers the pixel" : ": does not cover the pixel") << "\n";
        for (std::size_t i = 0; i < p.clip.size(); ++i) {
            o << "  vertex " << p.vertices[i] << " clip (" << p.clip[i][0] << ", " << p.clip[i][1] << ", " << p.clip[i][2]
              << ", " << p.clip[i][3] << ") clip mask " << p.clipmask[i] << "\n";
        }
        if (p.in_draw_pipeline) o << "  its vertex segment goes through the draw pipeline\n";
        for (const auto& poly : p.clipped_polygon) {
            o << "  clipped polygon:";
            for (const auto& v : poly) o << " (" << v[0] << ", " << v[1] << ", " << v[2] << ", " << v[3] << ")";
            o << "\n";
        }
        if (!p.note.empty()) o << "  " << p.note << "\n";
        for (const auto& s : p.setups) {
            o << "  setup: " << s.outcome << (s.clipped ? " (clipper output)" : "") << "\n";
            for (const auto& w : s.window) o << "    window (" << w[0] << ", " << w[1] << ") z " << w[2] << " 1/w " << w[3] << "\n";
            if (!s.x.empty()) {
                o << "    snapped (1/" << (1 << s.subpixel_bits) << " px, pixel centre at 0):";
                for (std::size_t i = 0; i < s.x.size(); ++i) o << " (" << s.x[i] << ", " << s.y[i] << ")";
                o << "\n";
            }
            if (s.area != 0) o << "    area " << s.area << (s.front_facing ? " front" : " back") << "-facing\n";
            for (std::size_t k = 0; k < s.edges.size(); ++k) {
                const auto& ed = s.edges[k];
                o << "    edge " << k << ": a " << ed.a << " b " << ed.b << " c " << ed.c << ", E at pixel " << ed.value
                  << (ed.tie ? "  <- centre exactly on this edge; " : "") << (ed.tie ? (ed.owns_ties ? "owned" : "not owned") : "")
                  << "\n";
            }
            if (s.has_fragment) {
                const auto& f = s.fragment;
                o << "    z plane A0 " << f.z_plane[0] << " dz/dx " << f.z_plane[1] << " dz/dy " << f.z_plane[2]
                  << ", offset " << f.z_offset << "\n";
                if (f.depth_tested) {
                    o << "    depth " << f.z << " -> " << f.depth_value << " vs stored " << f.depth_stored
                      << (f.depth_pass ? ": passes" : ": fails") << "\n";
                }
                o << "    shader colour " << f.shader_color[0] << ", " << f.shader_color[1] << ", " << f.shader_color[2]
                  << ", " << f.shader_color[3] << "; destination " << color_text(f.destination, is8) << "; written "
                  << color_text(f.written, is8) << "\n";
            }
        }
    }
    o << "\nreference: " << color_text(e.reference_color, is8);
    if (e.reference_depth) o << " depth " << *e.reference_depth;
    o << "\n";
    if (e.backend) {
        o << "backend:   " << color_text(e.backend_color, is8);
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
    j["profile"] = t.profile;
    j["verdict"] = e.verdict;
    j["rule"] = e.rule;
    j["agree"] = e.agree;
    j["reference"] = {{"color", e.reference_color}};
    if (e.reference_depth) j["reference"]["depth"] = *e.reference_depth;
    if (e.backend) {
        j["backend"] = {{"color", e.backend_color}};
        if (e.backend_depth) j["backend"]["depth"] = *e.backend_depth;
    }
    auto& prims = j["primitives"] = nlohmann::ordered_json::array();
    for (const auto& p : t.primitives) {
        nlohmann::ordered_json pj;
        pj["draw"] = p.draw;
        pj["primitive"] = p.primitive;
        pj["kind"] = p.kind;
        pj["covered"] = p.covered;
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
            x["area"] = s.area;
            x["front_facing"] = s.front_facing;
            auto& ej = x["edges"] = nlohmann::ordered_json::array();
            for (const auto& ed : s.edges) {
                ej.push_back({{"a", ed.a}, {"b", ed.b}, {"c", ed.c}, {"owns_ties", ed.owns_ties}, {"value", ed.value}, {"tie", ed.tie}});
            }
            x["covered"] = s.covered;
            if (s.has_fragment) {
                const auto& f = s.fragment;
                x["fragment"] = {{"z_plane", f.z_plane},       {"w_plane", f.w_plane},         {"z_offset", f.z_offset},
                                 {"z", f.z},                   {"depth_tested", f.depth_tested}, {"depth_value", f.depth_value},
                                 {"depth_stored", f.depth_stored}, {"depth_pass", f.depth_pass}, {"shader_color", f.shader_color},
                                 {"destination", f.destination}, {"written", f.written}};
            }
            sj.push_back(x);
        }
        prims.push_back(pj);
    }
    return j.dump(1);
}

std::string explanation_svg(const Explanation& e, int radius) {
    const auto& fb = e.reference_image;
    const int cx = e.trace.x;
    const int cy = e.trace.y;
    const int S = 48;  // screen pixels per framebuffer pixel
    const int n = 2 * radius + 1;
    const int x0 = cx - radius;
    const int y0 = cy - radius;
    const auto sx = [&](double wx) { return (wx - x0) * S; };
    const auto sy = [&](double wy) { return (y0 + n - wy) * S; };  // y up
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << n * S << "\" height=\"" << n * S + 40 << "\" viewBox=\"0 0 "
      << n * S << " " << n * S + 40 << "\">\n";
    s << "<title>pixel (" << cx << ", " << cy << "): " << e.verdict << "</title>\n";
    // Pixels in the reference's colours.
    for (int y = y0; y < y0 + n; ++y) {
        for (int x = x0; x < x0 + n; ++x) {
            std::string fill = "#ffffff";
            if (x >= 0 && y >= 0 && static_cast<std::uint32_t>(x) < fb.width && static_cast<std::uint32_t>(y) < fb.height) {
                const auto c = color_at(fb, x, y);
                int rgb[3];
                for (int k = 0; k < 3; ++k) {
                    const float v = fb.color_format == refraster::ColorFormat::Rgba8 ? c[static_cast<std::size_t>(k)]
                                                                                     : std::clamp(c[static_cast<std::size_t>(k)], 0.0f, 1.0f) * 255.0f;
                    rgb[k] = static_cast<int>(v);
                }
                char buf[8];
                std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0] & 255, rgb[1] & 255, rgb[2] & 255);
                fill = buf;
            }
            s << "<rect x=\"" << sx(x) << "\" y=\"" << sy(y + 1) << "\" width=\"" << S << "\" height=\"" << S << "\" fill=\""
              << fill << "\" stroke=\"#888\" stroke-width=\"1\"/>\n";
            s << "<circle cx=\"" << sx(x + 0.5) << "\" cy=\"" << sy(y + 0.5) << "\" r=\"2.5\" fill=\"#888\"/>\n";
        }
    }
    // The traced pixel.
    s << "<rect x=\"" << sx(cx) << "\" y=\"" << sy(cy + 1) << "\" width=\"" << S << "\" height=\"" << S
      << "\" fill=\"none\" stroke=\"#ff00ff\" stroke-width=\"3\"/>\n";
    // Snapped edges of every primitive that reaches the pixel; ties ringed.
    bool tie = false;
    for (const auto& p : e.trace.primitives) {
        for (const auto& st : p.setups) {
            if (st.x.size() < 2) continue;
            const double one = static_cast<double>(1 << st.subpixel_bits);
            s << "<polygon fill=\"none\" stroke=\"" << (p.covered ? "#00c853" : "#2962ff") << "\" stroke-width=\"2\" points=\"";
            for (std::size_t i = 0; i < st.x.size(); ++i) {
                s << sx(st.x[i] / one + 0.5) << "," << sy(st.y[i] / one + 0.5) << " ";
            }
            s << "\"><title>" << where(p) << " (" << st.outcome << ")</title></polygon>\n";
            for (const auto& ed : st.edges) tie = tie || ed.tie;
        }
    }
    if (tie) {
        s << "<circle cx=\"" << sx(cx + 0.5) << "\" cy=\"" << sy(cy + 0.5) << "\" r=\"9\" fill=\"none\" stroke=\"#ff6d00\" "
             "stroke-width=\"3\"><title>tie: the centre lies exactly on an edge</title></circle>\n";
    }
    std::string verdict = e.verdict;
    for (auto& c : verdict) {
        if (c == '<' || c == '>' || c == '&') c = ' ';
    }
    s << "<text x=\"4\" y=\"" << n * S + 16 << "\" font-family=\"sans-serif\" font-size=\"12\">" << verdict.substr(0, 140)
      << "</text>\n</svg>\n";
    return s.str();
}

}  // namespace harness
