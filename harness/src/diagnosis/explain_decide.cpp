#include "harness/explain.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "harness/profile_io.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace {

std::array<float, 4> color_at(const refraster::Framebuffer& fb, int x, int y) {
    const std::size_t i =
        4 * fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    std::array<float, 4> c{};
    for (std::size_t k = 0; k < 4; ++k) {
        c[k] = fb.color_format == refraster::ColorFormat::Rgba8 ? fb.color8[i + k]
                                                                : fb.color32f[i + k];
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

std::string where(const refraster::PrimitiveTrace& p) {
    return "draws[" + std::to_string(p.draw) + "] " + p.kind + " " + std::to_string(p.primitive);
}

std::string owner_text(std::uint32_t owner) {
    if (owner == 0) return "nothing";
    return "draws[" + std::to_string(owner >> 24) + "] primitive " +
           std::to_string((owner & 0xffffffu) - 1);
}

std::string px_text(int x, int y) {
    return "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

void require_inside(const refraster::Target& target, int x, int y) {
    if (x < 0 || y < 0 || static_cast<std::uint32_t>(x) >= target.width ||
        static_cast<std::uint32_t>(y) >= target.height) {
        throw PixelOutsideTarget("pixel " + px_text(x, y) + " is outside the " +
                                 std::to_string(target.width) + "x" +
                                 std::to_string(target.height) + " target");
    }
}

// What the trace shows at the pixel, as evidence for a rule.
struct Evidence {
    std::string tie;       // a centre exactly on an edge whose ownership alone decides coverage
    std::string snapping;  // an edge within one subpixel step of the centre
    std::string nine_vertex;
    std::string cull;
    std::string clipper;
    bool lines_only = true;   // every primitive reaching the pixel is a line
    bool points_only = true;  // ... a point
    bool any = false;
};

Evidence gather(const refraster::PixelTrace& t, const refraster::Profile& profile) {
    Evidence ev;
    for (const auto& p : t.primitives) {
        ev.any = true;
        ev.lines_only = ev.lines_only && p.kind == "line";
        ev.points_only = ev.points_only && p.kind == "point";
        if (ev.nine_vertex.empty() && p.note.find("nine-vertex") != std::string::npos) {
            ev.nine_vertex = where(p) + " is in a draw that " +
                             p.note.substr(0, p.note.find(" by ")) +
                             " by llvmpipe's nine-vertex rectangle analysis";
        }
        if (ev.cull.empty() && p.in_draw_pipeline && p.kind == "triangle") {
            ev.cull =
                where(p) +
                " is in a vertex segment that goes through the draw pipeline, whose float cull "
                "decides before setup's fixed-point one";
        }
        for (const auto& s : p.setups) {
            if (s.outcome.find("cull") != std::string::npos)
                ev.cull = where(p) + " was " + s.outcome;
            if (ev.clipper.empty() && s.clipped)
                ev.clipper = where(p) + " was clipped, and its new vertices reach the pixel";
            for (std::size_t k = 0; k < s.edges.size(); ++k) {
                const auto& ed = s.edges[k];
                if (ev.tie.empty() && ed.tie) {
                    bool others_inside = true;
                    for (std::size_t j = 0; j < s.edges.size(); ++j) {
                        if (j != k && !(s.edges[j].value > 0)) others_inside = false;
                    }
                    if (others_inside) {
                        ev.tie =
                            "the centre lies exactly on edge " + std::to_string(k) + " of " +
                            where(p) + ", and the " + refraster::to_string(profile.gl.tie_rule) +
                            " rule " +
                            (ed.owns_ties ? "gives the pixel to it" : "keeps the pixel from it");
                    }
                }
                const std::int64_t raw = ed.value - (ed.owns_ties ? 1 : 0);
                const std::int64_t step = std::abs(static_cast<std::int64_t>(ed.a)) +
                                          std::abs(static_cast<std::int64_t>(ed.b));
                if (ev.snapping.empty() && step != 0 && std::llabs(raw) <= step) {
                    ev.snapping = "edge " + std::to_string(k) + " of " + where(p) +
                                  " passes within one subpixel step of the centre (edge value " +
                                  std::to_string(raw) + ")";
                }
            }
        }
    }
    if (!ev.any) ev.lines_only = ev.points_only = false;
    return ev;
}

// The rules explain can try, in the order a tie between candidates is broken when the trace
// gives no evidence for any of them: the draw module's decisions first, then coverage, then
// arithmetic.
const std::vector<std::string>& rule_order() {
    static const std::vector<std::string> order{
        "nine-vertex analysis", "cull",     "tie rule", "snapping", "clipper",
        "fused arithmetic",     "denormals"};
    return order;
}

// Every alternative of the profile's parameters, as (rule, key=value).
std::vector<std::pair<std::string, std::string>> alternatives_of(const refraster::Profile& p) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const char* r : {"left-bottom", "left-top", "right-bottom", "right-top"}) {
        if (refraster::to_string(p.gl.tie_rule) != r)
            out.emplace_back("tie rule", std::string("tie_rule=") + r);
    }
    if (p.model != refraster::CoverageModel::Snapped)
        return out;  // the exact oracle has no other parameter
    for (const char* r : {"nearest-even", "half-away", "truncate"}) {
        if (refraster::to_string(p.gl.snap_rounding) != r)
            out.emplace_back("snapping", std::string("snap_rounding=") + r);
    }
    for (int bits : {4, 8}) {
        if (p.gl.subpixel_bits != bits)
            out.emplace_back("snapping", "subpixel_bits=" + std::to_string(bits));
    }
    const bool fused = p.gl.viewport_fma == refraster::FmaMode::On ||
                       (p.gl.viewport_fma == refraster::FmaMode::Auto && refraster::host_has_fma());
    out.emplace_back("fused arithmetic", fused ? "viewport_fma=off" : "viewport_fma=on");
    out.emplace_back("denormals",
                     p.gl.flush_denormals ? "flush_denormals=false" : "flush_denormals=true");
    out.emplace_back("cull", p.quirks.draw_pipeline_cull ? "draw_pipeline_cull=false"
                                                         : "draw_pipeline_cull=true");
    out.emplace_back("nine-vertex analysis", p.quirks.nine_vertex_quirk ? "nine_vertex_quirk=false"
                                                                        : "nine_vertex_quirk=true");
    out.emplace_back("integer widths", p.quirks.wrapping_arithmetic ? "wrapping_arithmetic=false"
                                                                    : "wrapping_arithmetic=true");
    out.emplace_back("clipper", p.gl.clipping == refraster::Clipping::ViewVolume
                                    ? "clipping=guard-band"
                                    : "clipping=view-volume");
    return out;
}

bool is_coverage(PixelClass c) {
    return c == PixelClass::Missing || c == PixelClass::Extra || c == PixelClass::Coverage;
}

std::string difference_of(PixelClass c) {
    switch (c) {
        case PixelClass::Equal:
            return "none";
        case PixelClass::Missing:
        case PixelClass::Extra:
        case PixelClass::Coverage:
            return "coverage";
        case PixelClass::ColorOnly:
            return "colour";
        case PixelClass::DepthOnly:
            return "depth";
    }
    return "none";
}

// Whether an alternative render agrees with the backend on what differed: the same coverage
// for a coverage difference, the same bytes for colour and depth.
bool resolves(PixelClass before, PixelClass after) {
    return is_coverage(before) ? !is_coverage(after) : after == PixelClass::Equal;
}

}  // namespace

struct Explainer::Alternative {
    std::string rule;
    std::string change;          // key=value
    std::size_t reproduced = 0;  // mismatching pixels of the whole image it reproduces
    std::size_t broken = 0;      // agreeing pixels it makes differ
    long net() const { return static_cast<long>(reproduced) - static_cast<long>(broken); }
    std::unique_ptr<refraster::Framebuffer> image;  // held apart: the classifier refers to it
    std::unique_ptr<PixelClassifier> classifier;
};

namespace {

// The plain render, and with `owners` the primitive owners from a second pass: recording
// owners changes what llvmpipe's nine-vertex analysis does (an owner pass is never analysed),
// so the pixels always come from the plain render, as for the GL backends.
refraster::RenderOutcome render_reference(const refraster::DrawList& dl,
                                          const refraster::Profile& profile, bool owners,
                                          refraster::Framebuffer& out) {
    refraster::RenderOptions o;
    o.profile = profile;
    const auto r = refraster::render(dl, o, out);
    if (r.status != refraster::RenderStatus::Ok || !owners) return r;
    refraster::Framebuffer with_owners;
    o.record_owners = true;
    const auto w = refraster::render(dl, o, with_owners);
    if (w.status == refraster::RenderStatus::Ok) out.owner = std::move(with_owners.owner);
    return w;
}

}  // namespace

Explainer::Explainer(const Scene& scene, const refraster::Profile& profile, Backend* backend,
                     int sample)
    : scene_(scene), profile_(profile), sample_(sample) {
    const auto& target = scene_.draw_list.target;
    if (sample_ >= 0 && (target.samples != 4 || sample_ > 3)) {
        throw std::invalid_argument("sample " + std::to_string(sample_) + " of a target of " +
                                    std::to_string(target.samples) + " sample" +
                                    (target.samples == 1 ? "" : "s") +
                                    " (a 4x target has samples 0 to 3)");
    }
    const bool multisampled = target.samples > 1;
    // Owners are wanted only when the backend can report them believably; otherwise coverage
    // is judged by the clear values on both sides.
    if (backend != nullptr) {
        backend_result_ = backend->render(scene_);
        if (backend_result_->status != RenderStatus::Ok) {
            throw std::runtime_error(backend->name() + ": " +
                                     std::string(to_string(backend_result_->status)) + ": " +
                                     backend_result_->message);
        }
        if (multisampled && backend_result_->samples.samples != target.samples) {
            throw std::runtime_error(backend->name() + " did not return the samples of the " +
                                     std::to_string(target.samples) + "x target");
        }
        auto owners = backend->render_owners(scene_);
        auto& into = multisampled ? backend_result_->samples : backend_result_->image;
        if (owners.status == RenderStatus::Ok) {
            into.owner = std::move(multisampled ? owners.samples.owner : owners.image.owner);
        }
        // The resolved image is the backend's own resolve; its owners are sample 0's.
        if (multisampled && sample_ < 0) {
            backend_view_ = backend_result_->image;
            if (!into.owner.empty()) backend_view_.owner = refraster::sample_plane(into, 0).owner;
        } else {
            backend_view_ = view(into);
        }
        if (!owners_plausible(backend_view_.owner, backend_view_, scene_.draw_list.clear)) {
            backend_view_.owner.clear();
            into.owner.clear();
        }
    }
    const bool with_owners = backend_result_ && !backend_view_.owner.empty();
    const auto r = render_reference(scene_.draw_list, profile_, with_owners, reference_samples_);
    if (r.status != refraster::RenderStatus::Ok)
        throw std::runtime_error("the reference cannot render it: " + r.message);
    reference_ = view(reference_samples_);
    if (backend_result_) {
        classifier_ = std::make_unique<PixelClassifier>(reference_, backend_view_,
                                                        scene_.draw_list.clear, scene_.file.expect);
    }
}

refraster::Framebuffer Explainer::view(const refraster::Framebuffer& fb) const {
    if (fb.samples == 1) return fb;
    if (sample_ >= 0) return refraster::sample_plane(fb, static_cast<std::uint32_t>(sample_));
    return refraster::resolve_samples(fb);
}

Explainer::~Explainer() = default;

void Explainer::render_alternatives() {
    if (alternatives_ready_) return;
    alternatives_ready_ = true;
    const bool owners = !backend_view_.owner.empty();
    for (const auto& [rule, change] : alternatives_of(profile_)) {
        auto& a = alternatives_.emplace_back();
        a.rule = rule;
        a.change = change;
        refraster::Profile p = profile_;
        refraster::set_profile_parameter(p, change.substr(0, change.find('=')),
                                         change.substr(change.find('=') + 1));
        refraster::Framebuffer rendered;
        if (render_reference(scene_.draw_list, p, owners, rendered).status !=
            refraster::RenderStatus::Ok) {
            alternatives_.pop_back();
            continue;
        }
        a.image = std::make_unique<refraster::Framebuffer>(view(rendered));
        a.classifier = std::make_unique<PixelClassifier>(
            *a.image, backend_view_, scene_.draw_list.clear, scene_.file.expect);
        for (std::size_t i = 0; i < reference_.pixel_count(); ++i) {
            const auto before = classifier_->at(i).cls;
            const auto after = a.classifier->at(i).cls;
            if (before != PixelClass::Equal && resolves(before, after)) ++a.reproduced;
            if (before == PixelClass::Equal && after != PixelClass::Equal) ++a.broken;
        }
    }
    for (std::size_t i = 0; i < reference_.pixel_count(); ++i) {
        mismatched_ += classifier_->at(i).cls != PixelClass::Equal;
    }
    // Where several alternatives reproduce a pixel, the one that brings most of the image into
    // agreement (pixels reproduced less pixels it breaks) is the better explanation: try them in
    // that order.
    std::stable_sort(alternatives_.begin(), alternatives_.end(),
                     [](const Alternative& a, const Alternative& b) { return a.net() > b.net(); });
}

namespace {

// The texels around the last textured fragment of the trace: a window of up to 8x8 texels of
// the level it read first, centred on the sampled coordinate.
std::optional<Explanation::TexelWindow> texel_window(const refraster::DrawList& list,
                                                     const refraster::PixelTrace& trace) {
    std::optional<Explanation::TexelWindow> out;
    for (const auto& p : trace.primitives) {
        for (const auto& st : p.setups) {
            if (!st.has_fragment || !st.fragment.textured) continue;
            const auto& state = list.draws[p.draw].state.texture;
            if (!state || state->texture >= list.textures.size()) continue;
            Explanation::TexelWindow w;
            w.draw = p.draw;
            w.sample = st.fragment.texture;
            out = std::move(w);
        }
    }
    if (!out) return out;
    const auto& tex = list.textures[list.draws[out->draw].state.texture->texture];
    const auto levels = refraster::texture_levels(tex);
    const auto level = std::min<std::size_t>(out->sample.level0, levels.size() - 1);
    const auto& img = levels[level];
    out->level_width = img.width;
    out->level_height = img.height;
    const auto centre = [](float u, std::uint32_t n) {
        const double c = std::floor(static_cast<double>(u) * n);
        return std::isfinite(c) ? static_cast<int>(std::clamp(c, -1e6, 1e6)) : 0;
    };
    out->columns = static_cast<int>(std::min<std::uint32_t>(img.width, 8));
    out->rows = static_cast<int>(std::min<std::uint32_t>(img.height, 8));
    const int cx = centre(out->sample.coord[0], img.width);
    const int cy = centre(out->sample.coord[1], img.height);
    out->x0 = std::clamp(cx - out->columns / 2, 0, static_cast<int>(img.width) - out->columns);
    out->y0 = std::clamp(cy - out->rows / 2, 0, static_cast<int>(img.height) - out->rows);
    for (int y = out->y0; y < out->y0 + out->rows; ++y) {
        for (int x = out->x0; x < out->x0 + out->columns; ++x) {
            const std::size_t i =
                4 * (static_cast<std::size_t>(y) * img.width + static_cast<std::size_t>(x));
            out->texels.push_back({img.rgba[i], img.rgba[i + 1], img.rgba[i + 2], img.rgba[i + 3]});
        }
    }
    return out;
}

}  // namespace

Explanation Explainer::explain(int x, int y, bool full) {
    require_inside(scene_.draw_list.target, x, y);
    Explanation e;
    e.profile = profile_;
    e.trace.x = x;
    e.trace.y = y;
    e.trace.sample = std::max(sample_, 0);
    e.sample = sample_;
    bool traced = false;
    const auto trace = [&] {
        if (traced) return;
        traced = true;
        refraster::RenderOptions o;
        o.profile = profile_;
        o.trace = &e.trace;
        refraster::Framebuffer rendered;
        (void)refraster::render(scene_.draw_list, o, rendered);
        e.reference_image = view(rendered);
    };
    if (full) {
        trace();
        e.texels = texel_window(scene_.draw_list, e.trace);
    }
    e.reference_color = color_at(reference_, x, y);
    e.reference_depth = depth_at(reference_, x, y);
    const auto samples_of = [&](const refraster::Framebuffer& ms,
                                std::vector<std::array<float, 4>>& colors,
                                std::vector<std::optional<std::uint32_t>>& depths) {
        for (std::uint32_t s = 0; s < ms.samples && ms.samples > 1; ++s) {
            const auto plane = refraster::sample_plane(ms, s);
            colors.push_back(color_at(plane, x, y));
            depths.push_back(depth_at(plane, x, y));
        }
    };
    samples_of(reference_samples_, e.reference_samples, e.reference_sample_depths);
    const std::string px =
        px_text(x, y) + (sample_ >= 0 ? " sample " + std::to_string(sample_) : "");
    if (!backend_result_) {
        e.verdict = "reference only at " + px;
        return e;
    }
    e.backend = *backend_result_;
    e.backend_color = color_at(backend_view_, x, y);
    e.backend_depth = depth_at(backend_view_, x, y);
    samples_of(backend_result_->samples, e.backend_samples, e.backend_sample_depths);
    const std::size_t i =
        reference_.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    const auto cls = classifier_->at(i);
    e.agree =
        same_color(e.reference_color, e.backend_color) && e.reference_depth == e.backend_depth;
    if (cls.cls == PixelClass::Equal && sample_ < 0 && !e.reference_samples.empty()) {
        // The resolve can hide a sample that differs.
        std::string differing;
        for (std::size_t k = 0; k < e.reference_samples.size() && k < e.backend_samples.size();
             ++k) {
            if (!same_color(e.reference_samples[k], e.backend_samples[k]) ||
                e.reference_sample_depths[k] != e.backend_sample_depths[k]) {
                differing += (differing.empty() ? "" : ", ") + std::to_string(k);
            }
        }
        if (!differing.empty()) {
            e.agree = false;
            e.difference = "sample";
            e.verdict = "the resolved pixel " + px + " agrees, but sample" +
                        (differing.size() > 1 ? "s " : " ") + differing +
                        " differ; explain one with --sample";
            return e;
        }
    }
    if (cls.cls == PixelClass::Equal) {
        e.verdict = e.agree ? "the reference and the backend agree at " + px
                            : "the reference and the backend agree at " + px +
                                  " within the scene's colour tolerance";
        return e;
    }

    // 1. What differs.
    e.difference = difference_of(cls.cls);
    const bool owners = classifier_->by_owners();
    std::string what;
    switch (cls.cls) {
        case PixelClass::Missing:
            what = "the reference draws pixel " + px +
                   (owners ? " (" + owner_text(reference_.owner[i]) + ")" : "") +
                   " and the backend leaves it untouched";
            break;
        case PixelClass::Extra:
            what = "the backend draws pixel " + px +
                   (owners ? " (" + owner_text(backend_view_.owner[i]) + ")" : "") +
                   " and the reference leaves it untouched";
            break;
        case PixelClass::Coverage:
            what = "pixel " + px + " comes from " + owner_text(reference_.owner[i]) +
                   " in the reference and from " + owner_text(backend_view_.owner[i]) +
                   " in the backend";
            break;
        case PixelClass::ColorOnly:
            what =
                "both draw pixel " + px +
                (owners ? " from " + owner_text(reference_.owner[i]) : "") +
                ", and the colours differ by " + std::to_string(cls.color_difference) +
                (reference_.color_format == refraster::ColorFormat::Rgba8 ? " unorm8 steps"
                                                                          : " ULPs") +
                " in channel " + "RGBA"[cls.channel & 3] +
                (cls.depth_difference ? " (depth by " + std::to_string(cls.depth_difference) + ")"
                                      : "");
            break;
        case PixelClass::DepthOnly:
            what = "the colours agree at " + px + " and the depth values differ by " +
                   std::to_string(cls.depth_difference) + " (" +
                   std::to_string(e.reference_depth.value_or(0)) + " vs " +
                   std::to_string(e.backend_depth.value_or(0)) + ")";
            break;
        case PixelClass::Equal:
            break;
    }

    // 2. The rule within that class: alternatives that reproduce the backend here, the one that
    // reproduces most of the image first (one per rule).
    render_alternatives();
    const auto extent = [&](const Alternative& a) {
        return " and at " + std::to_string(a.reproduced) + " of the " +
               std::to_string(mismatched_) + " mismatching pixels" +
               (a.broken ? ", changing " + std::to_string(a.broken) + " that agree" : "");
    };
    std::map<std::string, const Alternative*> chosen;  // the best alternative of each rule
    for (const auto& a : alternatives_) {
        if (chosen.count(a.rule) == 0 && resolves(cls.cls, a.classifier->at(i).cls)) {
            e.candidates.emplace_back(a.rule, a.change);
            chosen[a.rule] = &a;
        }
    }
    // The trace is evidence only where the alternatives leave a choice (two candidates that
    // reproduce equally much) or none (which primitives reach the pixel); a verdict-only
    // explanation renders it just then.
    Evidence ev;
    bool gathered = false;
    const auto evidence = [&]() -> const Evidence& {
        if (!gathered) {
            trace();
            ev = gather(e.trace, profile_);
            gathered = true;
        }
        return ev;
    };
    if (full) (void)evidence();
    const auto evidence_for = [&](const std::string& rule) -> std::string {
        if (!gathered) {
            // Needed only to break a tie in the image brought into agreement.
            long best = std::numeric_limits<long>::min();
            std::size_t ties = 0;
            for (const auto& c : e.candidates) best = std::max(best, chosen[c.first]->net());
            for (const auto& c : e.candidates) ties += chosen[c.first]->net() == best;
            if (ties < 2) return "";
        }
        const Evidence& ev_ = evidence();
        if (rule == "tie rule") return ev_.tie;
        if (rule == "snapping") return ev_.snapping;
        if (rule == "nine-vertex analysis") return ev_.nine_vertex;
        if (rule == "cull") return ev_.cull;
        if (rule == "clipper") return ev_.clipper;
        return "";
    };
    std::string why;
    if (!e.candidates.empty()) {
        // The best-reproducing candidate; among equals, the one the trace shows at work, then
        // the draw module before coverage before arithmetic.
        const auto rank = [&](const std::pair<std::string, std::string>& c) {
            const auto pos =
                std::find(rule_order().begin(), rule_order().end(), c.first) - rule_order().begin();
            return std::make_tuple(-chosen[c.first]->net(), evidence_for(c.first).empty() ? 1 : 0,
                                   pos);
        };
        auto sorted = e.candidates;
        std::stable_sort(sorted.begin(), sorted.end(),
                         [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
        const auto& best = sorted.front();
        const auto tied = [&](const auto& c) {
            return std::get<0>(rank(c)) == std::get<0>(rank(best)) &&
                   std::get<1>(rank(c)) == std::get<1>(rank(best));
        };
        if (sorted.size() > 1 && tied(sorted[1])) {
            // Two rules explain the pixel, and the image, equally well, and the trace favours
            // neither: no rule can be named.
            e.rule = "undecided";
            why = "each of";
            for (const auto& c : sorted) {
                if (tied(c)) why += " " + c.first + " (" + c.second + "),";
            }
            why.back() = ' ';
            why += "reproduces the backend here" + extent(*chosen[best.first]);
        } else {
            e.rule = best.first;
            const std::string shown = evidence_for(best.first);
            why = (shown.empty() ? "" : shown + "; ") + best.second +
                  " reproduces the backend here" + extent(*chosen[best.first]);
        }
    }
    if (e.rule == "none") {
        if (e.difference == "coverage") (void)evidence();  // which primitives reach the pixel
        if (e.difference == "coverage" && ev.lines_only) {
            e.rule = "line rule";
            why =
                "only lines reach the pixel, and no parameter of the profile reproduces the "
                "backend's line coverage";
        } else if (e.difference == "coverage" && ev.points_only) {
            e.rule = "point rule";
            why =
                "only points reach the pixel, and no parameter of the profile reproduces the "
                "backend's point coverage";
        } else {
            e.rule = "undecided";
            why = "no parameter of the profile reproduces the backend here";
            if (e.difference == "coverage" && !ev.tie.empty()) why += "; " + ev.tie;
            if (e.difference == "coverage" && ev.tie.empty() && !ev.snapping.empty())
                why += "; " + ev.snapping;
        }
    }
    // A coverage rule that reproduces a colour or depth difference exactly: the coverage of a
    // primitive beneath the last one differs, seen through blending or the depth test.
    if (e.difference != "coverage" && (e.rule == "tie rule" || e.rule == "snapping" ||
                                       e.rule == "cull" || e.rule == "nine-vertex analysis")) {
        e.difference = "coverage";
        what +=
            ", because the coverage of a primitive drawn earlier differs (blending or the depth "
            "test shows it)";
    }
    std::string also;
    for (const auto& [rule, change] : e.candidates) {
        if (rule != e.rule) also += (also.empty() ? "" : ", ") + rule + " (" + change + ")";
    }
    e.verdict = e.difference + ": " + what + "; " + e.rule + ": " + why +
                (also.empty() ? "" : "; also reproduced by " + also);
    return e;
}

Explanation explain_pixel(const Scene& scene, const refraster::Profile& profile, int x, int y,
                          Backend* backend, int sample) {
    require_inside(scene.draw_list.target, x, y);  // before the backend renders anything
    Explainer ex(scene, profile, backend, sample);
    return ex.explain(x, y);
}

namespace {

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

namespace {

// The 4x sample positions (lp_rast.c, lp_sample_pos_4x), for the text.
constexpr std::array<std::array<double, 2>, 4> kSampleOffsets{
    {{0.375, 0.125}, {0.875, 0.375}, {0.125, 0.625}, {0.625, 0.875}}};

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
            }
            if (s.area != 0)
                o << "    area " << s.area << (s.front_facing ? " front" : " back") << "-facing\n";
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
    auto& cj = j["candidates"] = nlohmann::ordered_json::array();
    for (const auto& [rule, change] : e.candidates)
        cj.push_back({{"rule", rule}, {"alternative", change}});
    j["agree"] = e.agree;
    j["reference"] = {{"color", e.reference_color}};
    if (e.reference_depth) j["reference"]["depth"] = *e.reference_depth;
    if (e.backend) {
        j["backend"] = {{"color", e.backend_color}};
        if (e.backend_depth) j["backend"]["depth"] = *e.backend_depth;
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

namespace {

constexpr int kTexelCell = 40;  // screen pixels per texel
constexpr int kTexelPanelWidth = 8 * kTexelCell + 320;
constexpr int kTexelPanelHeight = 8 * kTexelCell + 60;

// The teaching view of a textured fragment: the level's texels (rows bottom to top, as the
// texture is addressed), the sampled point, the texels the filter read with their weights,
// and the pixel's footprint (the quad's derivatives as a parallelogram in texels).
std::string texel_panel_svg(const Explanation::TexelWindow& w, int top) {
    std::ostringstream s;
    const auto& t = w.sample;
    const int C = kTexelCell;
    const int rows = w.rows;
    const auto tx = [&](double u) { return 10 + (u - w.x0) * C; };  // texel units to screen
    const auto ty = [&](double v) { return top + 30 + (w.y0 + rows - v) * C; };
    s << "<text x=\"4\" y=\"" << top + 16
      << "\" font-family=\"sans-serif\" font-size=\"12\">texels of level " << t.level0 << " ("
      << w.level_width << "x" << w.level_height << "), " << (t.linear ? "bilinear" : "nearest")
      << ", " << (t.aos ? "8-bit path" : "float path") << "</text>\n";
    for (int y = 0; y < rows; ++y) {
        for (int x = 0; x < w.columns; ++x) {
            const auto& c = w.texels[static_cast<std::size_t>(y * w.columns + x)];
            char fill[8];
            std::snprintf(fill, sizeof fill, "#%02x%02x%02x", c[0], c[1], c[2]);
            s << "<rect x=\"" << tx(w.x0 + x) << "\" y=\"" << ty(w.y0 + y + 1) << "\" width=\"" << C
              << "\" height=\"" << C << "\" fill=\"" << fill
              << "\" stroke=\"#888\" stroke-width=\"1\"><title>texel (" << w.x0 + x << ", "
              << w.y0 + y << "): " << int{c[0]} << "," << int{c[1]} << "," << int{c[2]} << ","
              << int{c[3]} << "</title></rect>\n";
        }
    }
    // The texels read (level 0 of the sample), outlined.
    const auto& r = t.texels[0];
    const auto outline = [&](int x, int y, const char* colour) {
        if (x < w.x0 || y < w.y0 || x >= w.x0 + w.columns || y >= w.y0 + rows) return;
        s << "<rect x=\"" << tx(x) + 2 << "\" y=\"" << ty(y + 1) + 2 << "\" width=\"" << C - 4
          << "\" height=\"" << C - 4 << "\" fill=\"none\" stroke=\"" << colour
          << "\" stroke-width=\"3\"/>\n";
    };
    outline(r[0], r[2], "#ff00ff");
    if (t.linear) {
        outline(r[1], r[2], "#ff00ff");
        outline(r[0], r[3], "#ff00ff");
        outline(r[1], r[3], "#ff00ff");
    }
    // The sampled point and the footprint: the quad's steps along x and y, in texels of this
    // level (the derivatives are in base-level texels).
    const double scale = std::ldexp(1.0, -static_cast<int>(t.level0));
    const double u = static_cast<double>(t.coord[0]) * w.level_width;
    const double v = static_cast<double>(t.coord[1]) * w.level_height;
    const double ax = double{t.rho_terms[0]} * scale, ay = double{t.rho_terms[1]} * scale;
    const double bx = double{t.rho_terms[2]} * scale, by = double{t.rho_terms[3]} * scale;
    s << "<polygon fill=\"#00c85333\" stroke=\"#00c853\" stroke-width=\"2\" points=\"" << tx(u)
      << "," << ty(v) << " " << tx(u + ax) << "," << ty(v + ay) << " " << tx(u + ax + bx) << ","
      << ty(v + ay + by) << " " << tx(u + bx) << "," << ty(v + by)
      << "\"><title>the pixel's footprint: one pixel step along x and along y</title></polygon>\n";
    s << "<circle cx=\"" << tx(u) << "\" cy=\"" << ty(v)
      << "\" r=\"4\" fill=\"#ff00ff\"><title>sampled at (" << u << ", " << v
      << ") texels</title></circle>\n";
    // The numbers beside the grid.
    std::ostringstream lines;
    lines.precision(6);
    lines << "s, t = " << t.coord[0] << ", " << t.coord[1] << "|rho^2 = " << t.rho2
          << (t.minified ? " (minified)" : " (magnified)") << "|levels " << t.level0;
    if (t.level1 != t.level0) lines << " and " << t.level1 << ", weight " << t.level_weight;
    lines << "|texels x " << r[0] << (t.linear ? ", " + std::to_string(r[1]) : "") << " y " << r[2]
          << (t.linear ? ", " + std::to_string(r[3]) : "");
    if (t.linear) {
        lines << "|weights " << t.weights[0][0] << (t.aos ? "/256" : "") << ", " << t.weights[0][1]
              << (t.aos ? "/256" : "");
    }
    lines << "|colour " << t.color[0] << ", " << t.color[1] << ", " << t.color[2] << ", "
          << t.color[3];
    std::string text = lines.str();
    int line = 0;
    std::size_t start = 0;
    while (start <= text.size()) {
        const auto bar = text.find('|', start);
        const std::string part =
            text.substr(start, bar == std::string::npos ? std::string::npos : bar - start);
        s << "<text x=\"" << 20 + 8 * C << "\" y=\"" << top + 50 + 18 * line
          << "\" font-family=\"sans-serif\" font-size=\"12\">" << part << "</text>\n";
        ++line;
        if (bar == std::string::npos) break;
        start = bar + 1;
    }
    return s.str();
}

}  // namespace

// The explain view (explanation_svg): the pixel's neighbourhood twice, side by side, on the
// same pixel grid: left the primitives as setup receives them (unsnapped window coordinates),
// right as the edge functions see them (snapped to the 1/2^bits grid), each edge with its
// direction and the side its inside lies on. Cells outside the target are hatched; geometry
// is clipped to each panel. A legend says what every mark means.
namespace svg_view {
constexpr int kCell = 40;     // screen pixels per framebuffer pixel
constexpr int kAxis = 34;     // room for the y labels left of a panel
constexpr int kTitle = 30;    // a panel's title above it
constexpr int kTicks = 22;    // the x labels below a panel
constexpr int kGap = 28;      // between the panels
constexpr int kLegend = 132;  // the legend's height
constexpr int kSubpixel = 8;  // grid lines a pixel: 1/8 pixel (32 of llvmpipe's 1/256)
}  // namespace svg_view

std::string explanation_svg(const Explanation& e, int radius) {
    using namespace svg_view;
    const auto& fb = e.reference_image;
    const int cx = e.trace.x;
    const int cy = e.trace.y;
    const int S = kCell;
    const int n = 2 * radius + 1;
    const int x0 = cx - radius;
    const int y0 = cy - radius;
    const int PW = n * S;
    const int panel_w = kAxis + PW;
    const int W0 = 2 * panel_w + kGap + 8;
    const int pictures_h = kTitle + PW + kTicks;
    const int verdict_y = pictures_h + 18;
    const int legend_top = verdict_y + 12;
    const int H0 = legend_top + kLegend;
    const bool multisampled = !e.reference_samples.empty();
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W0 << "\" height=\"" << H0
      << "\" viewBox=\"0 0 " << W0 << " " << H0
      << "\" font-family=\"system-ui,sans-serif\" font-size=\"12\">\n";
    s << "<title>pixel (" << cx << ", " << cy << "): " << e.verdict << "</title>\n";
    s << "<defs><pattern id=\"outside\" width=\"8\" height=\"8\" patternUnits=\"userSpaceOnUse\" "
         "patternTransform=\"rotate(45)\"><rect width=\"8\" height=\"8\" fill=\"#d7d7d7\"/>"
         "<line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"8\" stroke=\"#9e9e9e\" stroke-width=\"3\"/>"
         "</pattern><marker id=\"arrow\" viewBox=\"0 0 10 10\" refX=\"5\" refY=\"5\" "
         "markerWidth=\"7\" markerHeight=\"7\" orient=\"auto-start-reverse\"><path d=\"M0,0 "
         "L10,5 L0,10 z\" fill=\"context-stroke\"/></marker></defs>\n";
    bool tie = false;
    for (const auto& p : e.trace.primitives)
        for (const auto& st : p.setups)
            for (const auto& ed : st.edges) tie = tie || ed.tie;
    // The traced point: the pixel centre, or the traced sample of a 4x target.
    double tx = cx + 0.5;
    double ty = cy + 0.5;
    if (multisampled) {
        const auto& o = kSampleOffsets[static_cast<std::size_t>(e.trace.sample)];
        tx = cx + o[0];
        ty = cy + o[1];
    }

    const auto panel = [&](int left, bool snapped) {
        const int top = kTitle;
        const auto sx = [&](double wx) { return left + kAxis + (wx - x0) * S; };
        const auto sy = [&](double wy) { return top + (y0 + n - wy) * S; };  // y up
        const std::string clip = snapped ? "clip-snapped" : "clip-unsnapped";
        s << "<g class=\"panel\" id=\"" << (snapped ? "snapped" : "unsnapped") << "\">\n";
        s << "<text x=\"" << left + kAxis << "\" y=\"18\" font-weight=\"600\">"
          << (snapped ? "snapped: corners as the edge functions see them"
                      : "unsnapped: window coordinates into setup")
          << "</text>\n";
        s << "<clipPath id=\"" << clip << "\"><rect x=\"" << sx(x0) << "\" y=\"" << sy(y0 + n)
          << "\" width=\"" << PW << "\" height=\"" << PW << "\"/></clipPath>\n";
        // Pixels in the reference's colours; outside the target hatched.
        for (int y = y0; y < y0 + n; ++y) {
            for (int x = x0; x < x0 + n; ++x) {
                const bool inside = x >= 0 && y >= 0 && static_cast<std::uint32_t>(x) < fb.width &&
                                    static_cast<std::uint32_t>(y) < fb.height;
                std::string fill = "url(#outside)";
                if (inside) {
                    const auto c = color_at(fb, x, y);
                    int rgb[3];
                    for (int k = 0; k < 3; ++k) {
                        const float v =
                            fb.color_format == refraster::ColorFormat::Rgba8
                                ? c[static_cast<std::size_t>(k)]
                                : std::clamp(c[static_cast<std::size_t>(k)], 0.0f, 1.0f) * 255.0f;
                        rgb[k] = static_cast<int>(v);
                    }
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0] & 255, rgb[1] & 255,
                                  rgb[2] & 255);
                    fill = buf;
                }
                s << "<rect class=\"" << (inside ? "cell" : "cell outside") << "\" x=\"" << sx(x)
                  << "\" y=\"" << sy(y + 1) << "\" width=\"" << S << "\" height=\"" << S
                  << "\" fill=\"" << fill << "\" stroke=\"#888\" stroke-width=\"1\">"
                  << "<title>pixel (" << x << ", " << y << ")"
                  << (inside ? "" : ": outside the target") << "</title></rect>\n";
            }
        }
        // The sub-pixel grid, faint, over the cells.
        s << "<g class=\"subpixel-grid\" stroke=\"#7f7f7f\" stroke-opacity=\"0.25\" "
             "stroke-width=\"0.5\">";
        for (int k = 1; k < n * kSubpixel; ++k) {
            if (k % kSubpixel == 0) continue;
            const double f = static_cast<double>(k) / kSubpixel;
            s << "<line x1=\"" << sx(x0 + f) << "\" y1=\"" << sy(y0) << "\" x2=\"" << sx(x0 + f)
              << "\" y2=\"" << sy(y0 + n) << "\"/><line x1=\"" << sx(x0) << "\" y1=\"" << sy(y0 + f)
              << "\" x2=\"" << sx(x0 + n) << "\" y2=\"" << sy(y0 + f) << "\"/>";
        }
        s << "</g>\n";
        // Sample points: pixel centres, or a 4x target's four positions.
        for (int y = y0; y < y0 + n; ++y) {
            for (int x = x0; x < x0 + n; ++x) {
                if (!multisampled) {
                    s << "<circle cx=\"" << sx(x + 0.5) << "\" cy=\"" << sy(y + 0.5)
                      << "\" r=\"2.5\" fill=\"#666\"/>\n";
                } else {
                    for (const auto& o : kSampleOffsets) {
                        s << "<circle cx=\"" << sx(x + o[0]) << "\" cy=\"" << sy(y + o[1])
                          << "\" r=\"2\" fill=\"#666\"/>\n";
                    }
                }
            }
        }
        // The traced pixel.
        s << "<rect x=\"" << sx(cx) << "\" y=\"" << sy(cy + 1) << "\" width=\"" << S
          << "\" height=\"" << S << "\" fill=\"none\" stroke=\"#ff00ff\" stroke-width=\"3\"/>\n";
        // The primitives that reach the pixel, clipped to the panel.
        s << "<g clip-path=\"url(#" << clip << ")\">\n";
        for (const auto& p : e.trace.primitives) {
            for (const auto& st : p.setups) {
                const char* colour = p.covered ? "#00a844" : "#2962ff";
                std::vector<std::array<double, 2>> pts;
                if (snapped) {
                    if (st.x.size() < 2) continue;
                    const double one = static_cast<double>(1 << st.subpixel_bits);
                    // The snapped grid's origin: the pixel centre, or its corner when
                    // multisampling.
                    const double origin = p.multisample ? 0.0 : 0.5;
                    for (std::size_t i = 0; i < st.x.size(); ++i)
                        pts.push_back({st.x[i] / one + origin, st.y[i] / one + origin});
                } else {
                    for (const auto& w : st.window) pts.push_back({w[0], w[1]});
                }
                if (pts.empty()) continue;
                if (pts.size() == 1) {
                    // A point: its centre.
                    s << "<circle cx=\"" << sx(pts[0][0]) << "\" cy=\"" << sy(pts[0][1])
                      << "\" r=\"4\" fill=\"" << colour << "\"><title>" << where(p) << ": centre ("
                      << pts[0][0] << ", " << pts[0][1] << ")</title></circle>\n";
                    continue;
                }
                s << "<polygon class=\"" << (snapped ? "snapped" : "unsnapped")
                  << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\""
                  << (snapped ? "" : " stroke-dasharray=\"6 4\"") << " points=\"";
                for (const auto& q : pts) s << sx(q[0]) << "," << sy(q[1]) << " ";
                s << "\"><title>" << where(p) << " (" << st.outcome << ")</title></polygon>\n";
                if (!snapped || pts.size() < 3) continue;
                // Each edge's direction (an arrow at its middle) and its inside side (a tick
                // towards the polygon's centre, which is inside: the set-up polygons are convex).
                double mx = 0, my = 0;
                for (const auto& q : pts) {
                    mx += q[0];
                    my += q[1];
                }
                mx /= static_cast<double>(pts.size());
                my /= static_cast<double>(pts.size());
                for (std::size_t i = 0; i < pts.size(); ++i) {
                    const auto& a = pts[i];
                    const auto& b = pts[(i + 1) % pts.size()];
                    const double ex = b[0] - a[0], ey = b[1] - a[1];
                    const double len = std::hypot(ex, ey);
                    if (len == 0) continue;
                    const double hx = (a[0] + b[0]) / 2, hy = (a[1] + b[1]) / 2;
                    const double step = 0.18;  // pixels
                    s << "<line class=\"edge-direction\" x1=\"" << sx(hx - ex / len * step)
                      << "\" y1=\"" << sy(hy - ey / len * step) << "\" x2=\""
                      << sx(hx + ex / len * step) << "\" y2=\"" << sy(hy + ey / len * step)
                      << "\" stroke=\"" << colour
                      << "\" stroke-width=\"2\" marker-end=\"url(#arrow)\"><title>edge " << i
                      << ": from corner " << i << " to corner " << (i + 1) % pts.size()
                      << "</title></line>\n";
                    // The normal towards the centre.
                    double nx = -ey / len, ny = ex / len;
                    if ((mx - hx) * nx + (my - hy) * ny < 0) {
                        nx = -nx;
                        ny = -ny;
                    }
                    s << "<line class=\"inside-side\" x1=\"" << sx(hx) << "\" y1=\"" << sy(hy)
                      << "\" x2=\"" << sx(hx + nx * 0.3) << "\" y2=\"" << sy(hy + ny * 0.3)
                      << "\" stroke=\"" << colour
                      << "\" stroke-width=\"3\" stroke-linecap=\"round\"><title>edge " << i
                      << ": its inside is this side</title></line>\n";
                }
            }
        }
        s << "</g>\n";
        if (multisampled) {
            s << "<circle cx=\"" << sx(tx) << "\" cy=\"" << sy(ty)
              << "\" r=\"4\" fill=\"#ff00ff\"><title>sample " << e.trace.sample
              << "</title></circle>\n";
        }
        if (tie) {
            s << "<circle cx=\"" << sx(tx) << "\" cy=\"" << sy(ty)
              << "\" r=\"9\" fill=\"none\" stroke=\"#ff6d00\" stroke-width=\"3\"><title>tie: the "
                 "point lies exactly on an edge</title></circle>\n";
        }
        // Pixel-coordinate axes: each column's x below, each row's y to the left.
        for (int x = x0; x < x0 + n; ++x) {
            s << "<text class=\"axis-x\" x=\"" << sx(x + 0.5) << "\" y=\"" << sy(y0) + 15
              << "\" text-anchor=\"middle\" fill=\"#444\">" << x << "</text>";
        }
        for (int y = y0; y < y0 + n; ++y) {
            s << "<text class=\"axis-y\" x=\"" << sx(x0) - 5 << "\" y=\"" << sy(y + 0.5) + 4
              << "\" text-anchor=\"end\" fill=\"#444\">" << y << "</text>";
        }
        s << "\n</g>\n";
    };
    panel(0, false);
    panel(panel_w + kGap, true);

    std::string verdict = e.verdict;
    for (auto& c : verdict) {
        if (c == '<' || c == '>' || c == '&') c = ' ';
    }
    s << "<text x=\"4\" y=\"" << verdict_y << "\">" << verdict.substr(0, 160) << "</text>\n";
    // The legend: every mark of the two panels.
    s << "<g id=\"legend\" transform=\"translate(8 " << legend_top << ")\">\n";
    struct Entry {
        std::string mark;
        const char* text;
    };
    const Entry entries[] = {
        {"<rect x=\"0\" y=\"-10\" width=\"14\" height=\"14\" fill=\"none\" stroke=\"#ff00ff\" "
         "stroke-width=\"3\"/>",
         "the explained pixel (x right, y up, GL's window coordinates)"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"22\" y2=\"-3\" stroke=\"#00a844\" stroke-width=\"2\"/>",
         "a primitive that covers the point"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"22\" y2=\"-3\" stroke=\"#2962ff\" stroke-width=\"2\"/>",
         "a primitive that reaches the pixel but does not cover the point"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"22\" y2=\"-3\" stroke=\"#555\" stroke-width=\"2\" "
         "stroke-dasharray=\"6 4\"/>",
         "unsnapped outline (left); solid: snapped corners (right)"},
        {"<line x1=\"0\" y1=\"-3\" x2=\"16\" y2=\"-3\" stroke=\"#555\" stroke-width=\"2\" "
         "marker-end=\"url(#arrow)\"/><line x1=\"8\" y1=\"-3\" x2=\"8\" y2=\"4\" stroke=\"#555\" "
         "stroke-width=\"3\"/>",
         "an edge's direction, and a tick on its inside side"},
        {"<circle cx=\"7\" cy=\"-3\" r=\"2.5\" fill=\"#666\"/>",
         multisampled ? "sample positions (4x: four a pixel)"
                      : "pixel centres (where coverage is tested)"},
        {"<circle cx=\"7\" cy=\"-3\" r=\"6\" fill=\"none\" stroke=\"#ff6d00\" stroke-width=\"3\"/>",
         "a tie: the point lies exactly on an edge, and the tie rule decides"},
        {"<rect x=\"0\" y=\"-10\" width=\"14\" height=\"14\" fill=\"url(#outside)\"/>",
         "outside the target"},
        {"<rect x=\"0\" y=\"-10\" width=\"14\" height=\"14\" fill=\"none\" stroke=\"#7f7f7f\" "
         "stroke-opacity=\"0.5\"/><line x1=\"7\" y1=\"-10\" x2=\"7\" y2=\"4\" stroke=\"#7f7f7f\" "
         "stroke-opacity=\"0.5\"/>",
         "faint lines: the sub-pixel grid, every 1/8 pixel"},
    };
    int row = 0;
    for (const auto& en : entries) {
        const int col = row % 2;
        const int line = row / 2;
        s << "<g transform=\"translate(" << col * (W0 / 2) << " " << 14 + line * 24 << ")\">"
          << en.mark << "<text x=\"30\" y=\"0\">" << en.text << "</text></g>\n";
        ++row;
    }
    s << "</g>\n";
    if (e.texels) s << texel_panel_svg(*e.texels, H0);
    s << "</svg>\n";
    std::string out = s.str();
    if (e.texels) {
        // The texel panel sits below: widen and heighten the picture to hold it.
        const int width = std::max(W0, kTexelPanelWidth);
        const int height = H0 + kTexelPanelHeight;
        const std::string old_head = "width=\"" + std::to_string(W0) + "\" height=\"" +
                                     std::to_string(H0) + "\" viewBox=\"0 0 " + std::to_string(W0) +
                                     " " + std::to_string(H0) + "\"";
        const std::string new_head = "width=\"" + std::to_string(width) + "\" height=\"" +
                                     std::to_string(height) + "\" viewBox=\"0 0 " +
                                     std::to_string(width) + " " + std::to_string(height) + "\"";
        if (const auto at = out.find(old_head); at != std::string::npos)
            out.replace(at, old_head.size(), new_head);
    }
    return out;
}

}  // namespace harness
