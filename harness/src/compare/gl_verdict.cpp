// gl_verdict.cpp: legal variations and violations of GL's rasterisation rules (gl_verdict.hpp).
#include "harness/gl_verdict.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include "harness/backend.hpp"
#include "harness/profile_io.hpp"
#include "harness/rule_search.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

using refraster::Framebuffer;
using refraster::Profile;

bool same_pixel(const Framebuffer& a, const Framebuffer& b, std::size_t i) {
    for (std::size_t k = 0; k < 4; ++k) {
        if (a.color_format == refraster::ColorFormat::Rgba8) {
            if (a.color8[4 * i + k] != b.color8[4 * i + k]) return false;
        } else if (std::bit_cast<std::uint32_t>(a.color32f[4 * i + k]) !=
                   std::bit_cast<std::uint32_t>(b.color32f[4 * i + k])) {
            return false;
        }
    }
    return a.depth.empty() || a.depth[i] == b.depth[i];
}

// The depth value as a number to order (z32f by its float value).
double depth_number(const Framebuffer& fb, std::size_t i) {
    if (fb.depth_format == refraster::DepthFormat::Z32f)
        return static_cast<double>(std::bit_cast<float>(fb.depth[i]));
    return static_cast<double>(fb.depth[i]);
}

// The scene under one variation, within the timeout (each render on its own); nothing when it
// cannot be rendered or stopped at the timeout (counted in `stopped`).
std::optional<Framebuffer> render(const Scene& scene, const Profile& p, double timeout_seconds,
                                  std::uint64_t& stopped) {
    refraster::RenderOptions o;
    o.profile = p;
    Framebuffer fb;
    try {
        if (render_reference_within(scene, o, timeout_seconds, fb).status !=
            refraster::RenderStatus::Ok)
            return std::nullopt;
    } catch (const refraster::RenderStopped&) {
        ++stopped;
        return std::nullopt;
    }
    return fb;
}

// OpenGL 4.6, 2.3.4.1: a value that is not a floating-point number (infinity, NaN) gives
// unspecified results, and the GL need represent magnitudes up to 2^32 only. An attribute
// beyond that makes the colours of the pixels its draw reaches unspecified.
constexpr float kGlMinimumMagnitude = 4294967296.0f;  // 2^32
static_assert(kGlMinimumMagnitude == 0x1p32f);

bool beyond_gl_range(const refraster::Draw& d) {
    const std::size_t stride = d.vertices.stride();
    for (std::size_t i = 0; i < d.vertices.data.size(); ++i) {
        if (i % stride < refraster::VertexArray::kPositionComponents) continue;
        const float v = d.vertices.data[i];
        if (!std::isfinite(v) || std::fabs(v) > kGlMinimumMagnitude) return true;
    }
    return false;
}

// The pixels reached by a draw with attributes beyond GL's range: those draws alone, their
// attributes made 1 and their state made to write (no depth test, stencil-free, no blending)
// over a target cleared to 0, so that every pixel they cover differs from the clear. Empty
// when no draw has such attributes (or the render failed: then nothing is excused).
std::vector<char> unspecified_pixels(const Scene& scene, const Profile& profile,
                                     double timeout_seconds, std::uint64_t& stopped) {
    Scene only = scene;
    only.draw_list.draws.clear();
    for (const auto& d : scene.draw_list.draws) {
        if (!beyond_gl_range(d)) continue;
        refraster::Draw w = d;
        const std::size_t stride = w.vertices.stride();
        for (std::size_t i = 0; i < w.vertices.data.size(); ++i)
            if (i % stride >= refraster::VertexArray::kPositionComponents)
                w.vertices.data[i] = 1.0f;
        w.state.depth_test.reset();
        w.state.blend = refraster::BlendPreset::None;
        w.state.texture.reset();
        w.state.polygon_offset.reset();
        only.draw_list.draws.push_back(std::move(w));
    }
    if (only.draw_list.draws.empty()) return {};
    only.draw_list.clear.color = {0.0f, 0.0f, 0.0f, 0.0f};
    Scene cleared = only;
    cleared.draw_list.draws.clear();
    const auto fb = render(only, profile, timeout_seconds, stopped);
    const auto empty = render(cleared, profile, timeout_seconds, stopped);
    if (!fb || !empty) return {};
    std::vector<char> mask(fb->pixel_count() * fb->samples, 0);
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = !same_pixel(*fb, *empty, i);
    return mask;
}

}  // namespace

std::string GlVerdict::summary() const {
    std::string legal_text, bad_text;
    for (const auto& f : findings) {
        std::string& t = f.legal ? legal_text : bad_text;
        const bool samples = unit == "samples";
        t += (t.empty() ? "" : ", ") + f.rule + " " + std::to_string(f.pixels) +
             (samples ? " samples" : " px");
        if (!f.legal && f.x >= 0) {
            t += " first at (" + std::to_string(f.x) + ", " + std::to_string(f.y) +
                 (samples ? ", sample " + std::to_string(f.sample) : "") + ")";
        }
    }
    std::string s = "GL verdict: " + std::to_string(legal) + " of " + std::to_string(differing) +
                    " differing " + unit + " legal";
    if (!legal_text.empty()) s += " (" + legal_text + ")";
    if (violations + unexplained > 0) {
        s += "; " + std::to_string(violations) + " violate GL, " + std::to_string(unexplained) +
             " unexplained";
        if (!bad_text.empty()) s += " (" + bad_text + ")";
    }
    if (stopped > 0)
        s += "; " + std::to_string(stopped) + " of " + std::to_string(variations) +
             " variations stopped at the timeout, so no violation is claimed";
    return s;
}

GlVerdict gl_verdict(const Scene& scene, const Profile& profile, const Framebuffer& reference,
                     const Framebuffer& backend, std::optional<std::array<int, 2>> at,
                     double timeout_seconds, int at_sample, const std::string& preferred) {
    GlVerdict v;
    v.at_pixel = "same as the reference";
    const auto at_index = [&]() -> std::optional<std::size_t> {
        if (!at || (*at)[0] < 0 || (*at)[1] < 0 ||
            static_cast<std::uint32_t>((*at)[0]) >= reference.width ||
            static_cast<std::uint32_t>((*at)[1]) >= reference.height)
            return std::nullopt;
        // The sample asked for on a multisampled target (sample 0 when out of range).
        const std::size_t s =
            at_sample > 0 && static_cast<std::uint32_t>(at_sample) < reference.samples
                ? static_cast<std::size_t>(at_sample)
                : 0;
        return (static_cast<std::size_t>((*at)[1]) * reference.width +
                static_cast<std::size_t>((*at)[0])) *
                   reference.samples +
               s;
    }();
    if (reference.width != backend.width || reference.height != backend.height ||
        reference.samples != backend.samples || reference.color_format != backend.color_format)
        return v;
    std::vector<std::size_t> pixels;
    // A multisampled target is judged sample by sample (same_pixel's index is then a sample's:
    // the layout is pixel-major, each pixel's samples together).
    v.unit = reference.samples > 1 ? "samples" : "pixels";
    for (std::size_t i = 0; i < reference.pixel_count() * reference.samples; ++i)
        if (!same_pixel(reference, backend, i)) pixels.push_back(i);
    v.differing = pixels.size();
    if (pixels.empty()) return v;

    // The cleared target: what "untouched" looks like.
    Scene cleared = scene;
    cleared.draw_list.draws.clear();
    const auto clear = render(cleared, profile, timeout_seconds, v.stopped);

    const auto unspecified = unspecified_pixels(scene, profile, timeout_seconds, v.stopped);
    const auto vars = rule_variations(profile, scene);
    v.variations = vars.size();
    const std::size_t n = pixels.size();
    std::vector<int> legal_match(n, -1), illegal_match(n, -1);
    std::vector<char> all_legal_draw(n, 1), any_legal_draw(n, 0);
    std::vector<double> zmin(n, std::numeric_limits<double>::infinity());
    std::vector<double> zmax(n, -std::numeric_limits<double>::infinity());
    const auto drawn = [&](const Framebuffer& fb, std::size_t i) {
        return !clear || !same_pixel(fb, *clear, i);
    };
    for (std::size_t k = 0; k < n; ++k) {
        // The reference itself is a legal rendering.
        const std::size_t i = pixels[k];
        const bool d = drawn(reference, i);
        all_legal_draw[k] = d;
        any_legal_draw[k] = d;
        if (!reference.depth.empty() && d) zmin[k] = zmax[k] = depth_number(reference, i);
    }
    for (std::size_t vi = 0; vi < vars.size(); ++vi) {
        const auto fb = render(vars[vi].scene ? *vars[vi].scene : scene, vars[vi].profile,
                               timeout_seconds, v.stopped);
        if (!fb) continue;
        for (std::size_t k = 0; k < n; ++k) {
            const std::size_t i = pixels[k];
            const bool same = same_pixel(*fb, backend, i);
            if (vars[vi].legal) {
                // The preferred variation wins at the pixel asked about.
                const bool take = legal_match[k] < 0 || (at_index == i && !preferred.empty() &&
                                                         vars[vi].setting == preferred);
                if (same && take) legal_match[k] = static_cast<int>(vi);
                const bool d = drawn(*fb, i);
                all_legal_draw[k] = static_cast<char>(all_legal_draw[k] && d);
                any_legal_draw[k] = static_cast<char>(any_legal_draw[k] || d);
                if (!fb->depth.empty() && d) {
                    zmin[k] = std::min(zmin[k], depth_number(*fb, i));
                    zmax[k] = std::max(zmax[k], depth_number(*fb, i));
                }
            } else if (same && illegal_match[k] < 0) {
                illegal_match[k] = static_cast<int>(vi);
            }
        }
    }
    std::map<std::string, std::size_t> index;
    const auto count = [&](const std::string& rule, bool legal, std::size_t i,
                           const std::string& detail) {
        auto it = index.find(rule);
        if (it == index.end()) {
            it = index.emplace(rule, v.findings.size()).first;
            GlFinding f;
            f.rule = rule;
            f.legal = legal;
            f.x = static_cast<int>(i / reference.samples % reference.width);
            f.y = static_cast<int>(i / reference.samples / reference.width);
            if (reference.samples > 1) f.sample = static_cast<int>(i % reference.samples);
            f.detail = detail;
            v.findings.push_back(f);
        }
        ++v.findings[it->second].pixels;
    };
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = pixels[k];
        if (legal_match[k] >= 0) {
            const auto& var = vars[static_cast<std::size_t>(legal_match[k])];
            ++v.legal;
            count(var.gl, true, i, var.setting + " reproduces the backend");
            if (at_index == i)
                v.at_pixel = "legal: " + var.gl + " (" + var.setting + " reproduces the backend)";
            continue;
        }
        if (!unspecified.empty() && unspecified[i] &&
            (reference.depth.empty() || reference.depth[i] == backend.depth[i])) {
            // Undefined, not wrong: whatever colour the backend wrote there, including none.
            const std::string freedom =
                "unspecified result of an attribute beyond GL's floating-point range (NaN, "
                "infinity or a magnitude above 2^32; 2.3.4.1)";
            ++v.legal;
            count(freedom, true, i, "a draw with such attributes reaches the pixel");
            if (at_index == i) v.at_pixel = "legal: " + freedom;
            continue;
        }
        const bool backend_drawn = drawn(backend, i);
        std::string rule;
        std::string detail;
        if (illegal_match[k] >= 0) {
            const auto& var = vars[static_cast<std::size_t>(illegal_match[k])];
            rule = var.gl;
            detail = var.setting + " reproduces the backend, no legal rule does";
        } else if (!backend_drawn && all_legal_draw[k]) {
            rule = "hole (every legal coverage draws the pixel)";
            detail = "the backend leaves it untouched";
        } else if (backend_drawn && !any_legal_draw[k]) {
            rule = "a pixel outside every legal coverage";
            detail = "no legal rule draws it";
        } else if (backend_drawn && !backend.depth.empty() && zmin[k] <= zmax[k] &&
                   (depth_number(backend, i) < zmin[k] - 2.0 ||
                    depth_number(backend, i) > zmax[k] + 2.0)) {
            rule = "non-monotonic depth (outside every legal depth at the pixel)";
            detail = "depth " + std::to_string(depth_number(backend, i)) + " outside [" +
                     std::to_string(zmin[k]) + ", " + std::to_string(zmax[k]) + "]";
        }
        // A variation that stopped might have reproduced the pixel (or widened the legal
        // coverage and depth range): without every one, nothing is proven.
        if (!rule.empty() && v.stopped == 0) {
            ++v.violations;
            count(rule, false, i, detail);
            if (at_index == i) v.at_pixel = "violation: " + rule + " (" + detail + ")";
        } else {
            ++v.unexplained;
            const std::string why = v.stopped > 0 ? "a variation stopped at the timeout"
                                                  : "no legal rule reproduces it";
            count("unexplained (" + why + ")", false, i,
                  v.stopped > 0 ? "not every legal variation could be rendered in time"
                                : "neither a legal variation nor a proven violation");
            if (at_index == i) v.at_pixel = "unexplained: " + why;
        }
    }
    return v;
}

}  // namespace harness
