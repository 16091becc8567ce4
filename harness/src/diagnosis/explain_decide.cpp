// explain_decide.cpp: which rule explains a pixel's difference (Explainer, explain_pixel):
// the reference's trace of the pixel, the evidence gathered from it, and the alternative
// profiles that reproduce the backend's pixels.
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

#include "explain_shared.hpp"
#include "harness/explain.hpp"
#include "harness/profile_io.hpp"
#include "harness/rule_search.hpp"
#include "refraster/renderer.hpp"

namespace harness {

namespace explain_detail {

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

bool same_color(const std::array<float, 4>& a, const std::array<float, 4>& b) {
    for (std::size_t k = 0; k < 4; ++k) {
        if (std::bit_cast<std::uint32_t>(a[k]) != std::bit_cast<std::uint32_t>(b[k])) return false;
    }
    return true;
}

std::string where(const refraster::PrimitiveTrace& p) {
    return "draws[" + std::to_string(p.draw) + "] " + p.kind + " " + std::to_string(p.primitive);
}

}  // namespace explain_detail

using explain_detail::color_at;
using explain_detail::same_color;
using explain_detail::where;

namespace {

std::optional<std::uint32_t> depth_at(const refraster::Framebuffer& fb, int x, int y) {
    if (fb.depth_format == refraster::DepthFormat::None) return std::nullopt;
    return fb.depth[fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y))];
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
    std::string nan_offset;   // the draw module's polygon offset made a vertex depth NaN
    bool lines_only = true;   // every primitive reaching the pixel is a line
    bool points_only = true;  // ... a point
    bool any = false;
};

// `backend_owner`: the primitive that draws the pixel in the backend (owner_text's encoding; 0
// when unknown).
Evidence gather(const refraster::PixelTrace& t, const refraster::Profile& profile,
                std::uint32_t backend_owner) {
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
        if (ev.nan_offset.empty() &&
            p.note.find("NaN depth from polygon offset") != std::string::npos) {
            ev.nan_offset = where(p) + ": " + p.note.substr(p.note.find("the draw module"));
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
    // The tie: a centre exactly on one or more edges of a primitive whose other edges hold it
    // inside, so that ownership alone decides. The primitive that draws the pixel comes first,
    // in the reference (the last such, the owner), else in the backend: at a corner the centre
    // lies on edges of both triangles, and the one that draws the pixel on neither side is
    // not the one to name.
    const auto backend_draws = [&](const refraster::PrimitiveTrace& p) {
        return backend_owner != 0 && p.draw == (backend_owner >> 24) &&
               p.primitive + 1 == (backend_owner & 0xffffffu);
    };
    for (int pass = 0; pass < 3; ++pass) {
        const bool drawing = pass == 0;
        for (auto p = t.primitives.rbegin(); p != t.primitives.rend() && ev.tie.empty(); ++p) {
            if (pass == 1 && !backend_draws(*p)) continue;
            for (const auto& s : p->setups) {
                if (s.covered != drawing || !ev.tie.empty()) continue;
                std::vector<std::size_t> on;
                bool others_inside = true;
                bool owned = true;
                for (std::size_t k = 0; k < s.edges.size(); ++k) {
                    if (s.edges[k].tie) {
                        on.push_back(k);
                        owned = owned && s.edges[k].owns_ties;
                    } else if (!(s.edges[k].value > 0)) {
                        others_inside = false;
                    }
                }
                if (on.empty() || !others_inside) continue;
                std::string edges = on.size() == 1 ? "edge " : "edges ";
                for (std::size_t i = 0; i < on.size(); ++i)
                    edges += (i == 0               ? ""
                              : i + 1 == on.size() ? " and "
                                                   : ", ") +
                             std::to_string(on[i]);
                ev.tie = "the centre lies exactly on " + edges + " of " + where(*p) + ", and the " +
                         refraster::to_string(profile.gl.tie_rule) + " rule " +
                         (drawing && owned ? "gives the pixel to it" : "keeps the pixel from it");
            }
        }
    }
    if (!ev.any) ev.lines_only = ev.points_only = false;
    return ev;
}

// The draw module's SATURATE of a NaN polygon offset (draw_offset_nan_to_zero).
constexpr const char* kNanOffsetRule = "NaN depth from polygon offset";

// Polygon offset's minimum resolvable difference r (offset_units_scale, OpenGL 4.6 14.6.5).
constexpr const char* kOffsetScaleRule = "polygon offset r";

// softpipe's colour tiles written back by a fill rule's stencil clear (fill_clear_writes_tiles).
constexpr const char* kTileWriteBackRule = "tile write-back";

// The rules explain can try, in the order a tie between candidates is broken when the trace
// gives no evidence for any of them: the draw module's decisions first, then coverage, then
// arithmetic.
const std::vector<std::string>& rule_order() {
    static const std::vector<std::string> order{"nine-vertex analysis",
                                                "cull",
                                                kNanOffsetRule,
                                                kOffsetScaleRule,
                                                "tie rule",
                                                "snapping",
                                                "clipper",
                                                kTileWriteBackRule,
                                                "line rule",
                                                "point rule",
                                                "depth clear",
                                                "depth rounding",
                                                "colour rounding",
                                                "texture LOD",
                                                "mip blend",
                                                "fused arithmetic",
                                                "denormals",
                                                "integer widths",
                                                "another implementation",
                                                "multisample enable",
                                                "edge flags"};
    return order;
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
    std::string change;          // the variation's setting (rule_search.hpp)
    std::size_t reproduced = 0;  // mismatching pixels of the whole image it reproduces
    std::size_t broken = 0;      // agreeing pixels it makes differ
    bool legal = true;           // a freedom GL grants, or a GL rule broken
    std::string gl;              // which, with its section
    long net() const { return static_cast<long>(reproduced) - static_cast<long>(broken); }
    // Each pixel's class against the backend: a byte a pixel, where the render itself would
    // hold tens (a scene at the target limit has a dozen alternatives).
    std::vector<PixelClass> classes;
};

namespace {

// The plain render, and with `owners` the primitive owners from a second pass: recording
// owners changes what llvmpipe's nine-vertex analysis does (an owner pass is never analysed),
// so the pixels always come from the plain render, as for the GL backends. Each pass gets the
// timeout on its own.
refraster::RenderOutcome render_reference(const Scene& scene, const refraster::Profile& profile,
                                          bool owners, double timeout_seconds,
                                          refraster::Framebuffer& out) {
    refraster::RenderOptions o;
    o.profile = profile;
    const auto r = render_reference_within(scene, o, timeout_seconds, out);
    if (r.status != refraster::RenderStatus::Ok || !owners) return r;
    refraster::Framebuffer with_owners;
    o.record_owners = true;
    const auto w = render_reference_within(scene, o, timeout_seconds, with_owners);
    if (w.status == refraster::RenderStatus::Ok) out.owner = std::move(with_owners.owner);
    return w;
}

}  // namespace

Explainer::Explainer(const Scene& scene, const refraster::Profile& profile, Backend* backend,
                     int sample, double timeout_seconds, const RenderResult* rendered)
    : scene_(scene), profile_(profile), sample_(sample), timeout_seconds_(timeout_seconds) {
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
        backend_result_ = rendered != nullptr ? *rendered : backend->render(scene_);
        // Out of time on the GL side is what it is on the reference's: the run was cut short.
        if (backend_result_->status == RenderStatus::Timeout)
            throw refraster::RenderStopped(backend->name() + ": " + backend_result_->message);
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
        // Owners of another render than the one explained would not be its owners.
        const auto same_colours = [](const refraster::Framebuffer& a,
                                     const refraster::Framebuffer& b) {
            return a.color8 == b.color8 && a.color32f == b.color32f;
        };
        const bool owners_of_this_render =
            rendered == nullptr || (same_colours(owners.image, rendered->image) &&
                                    same_colours(owners.samples, rendered->samples));
        if (owners.status == RenderStatus::Ok && owners_of_this_render) {
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
    const auto r =
        render_reference(scene_, profile_, with_owners, timeout_seconds_, reference_samples_);
    if (r.status != refraster::RenderStatus::Ok)
        throw std::runtime_error("the reference cannot render it: " + r.message);
    // A single-sample render is its own view: moved, not copied (reference_samples_ holds
    // only a 4x target's samples).
    if (reference_samples_.samples == 1) {
        reference_ = std::move(reference_samples_);
        reference_samples_ = refraster::Framebuffer();
    } else {
        reference_ = view(reference_samples_);
    }
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
    // The same variations the GL verdict judges by (rule_search.hpp), violations included, so
    // that a backend that breaks a GL rule is named by the rule it breaks.
    for (auto& var : rule_variations(profile_, scene_)) {
        auto& a = alternatives_.emplace_back();
        a.rule = var.rule;
        a.change = var.setting;
        a.legal = var.legal;
        a.gl = var.gl;
        refraster::Framebuffer rendered;
        if (render_reference(var.scene ? *var.scene : scene_, var.profile, owners, timeout_seconds_,
                             rendered)
                .status != refraster::RenderStatus::Ok) {
            alternatives_.pop_back();
            continue;
        }
        if (rendered.samples != 1) rendered = view(rendered);
        const PixelClassifier classify(rendered, backend_view_, scene_.draw_list.clear,
                                       scene_.file.expect);
        a.classes.resize(reference_.pixel_count());
        for (std::size_t i = 0; i < reference_.pixel_count(); ++i) {
            const auto before = classifier_->at(i).cls;
            const auto after = classify.at(i).cls;
            a.classes[i] = after;
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
                                                     const refraster::PixelTrace& trace,
                                                     const refraster::Profile& profile) {
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
    const auto levels = refraster::texture_levels(tex, profile);
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
        (void)render_reference_within(scene_, o, timeout_seconds_, rendered);
        e.reference_image = view(rendered);
    };
    if (full) {
        trace();
        e.texels = texel_window(scene_.draw_list, e.trace, profile_);
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
    if (full) {
        e.backend = *backend_result_;
    } else {
        // Its outcome without its images: a copy of a whole image a pixel would make
        // explaining every pixel quadratic (and hold the image twice).
        RenderResult outcome;
        outcome.status = backend_result_->status;
        outcome.message = backend_result_->message;
        outcome.provenance = backend_result_->provenance;
        outcome.seconds = backend_result_->seconds;
        outcome.round_trip_seconds = backend_result_->round_trip_seconds;
        e.backend = std::move(outcome);
    }
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
                   std::to_string(cls.depth_difference) + " (reference " +
                   std::to_string(e.reference_depth.value_or(0)) + ", backend " +
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
        if (chosen.count(a.rule) == 0 && resolves(cls.cls, a.classes[i])) {
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
            ev = gather(e.trace, profile_,
                        backend_view_.owner.empty() ? 0u : backend_view_.owner[i]);
            gathered = true;
        }
        return ev;
    };
    if (full) (void)evidence();
    const auto evidence_for = [&](const std::string& rule) -> std::string {
        if (!gathered) {
            // Needed only to break a tie in the image brought into agreement.
            // (Among the single rules, when one reproduces the pixel: they are named first.)
            const bool singles =
                std::any_of(e.candidates.begin(), e.candidates.end(),
                            [](const auto& c) { return c.first != "another implementation"; });
            const auto counted = [&](const auto& c) {
                return !singles || c.first != "another implementation";
            };
            long best = std::numeric_limits<long>::min();
            std::size_t ties = 0;
            for (const auto& c : e.candidates)
                if (counted(c)) best = std::max(best, chosen[c.first]->net());
            for (const auto& c : e.candidates) ties += counted(c) && chosen[c.first]->net() == best;
            if (ties < 2) return "";
        }
        const Evidence& ev_ = evidence();
        if (rule == "tie rule") return ev_.tie;
        if (rule == "snapping") return ev_.snapping;
        if (rule == "nine-vertex analysis") return ev_.nine_vertex;
        if (rule == "cull") return ev_.cull;
        if (rule == "clipper") return ev_.clipper;
        if (rule == kNanOffsetRule) return ev_.nan_offset;
        return "";
    };
    std::string why;
    if (!e.candidates.empty()) {
        // The best-reproducing candidate; among equals, the one the trace shows at work, then
        // the draw module before coverage before arithmetic.
        // Another implementation's whole rule set is named only where no single rule
        // reproduces the pixel: it says less about why.
        const auto rank = [&](const std::pair<std::string, std::string>& c) {
            const auto pos =
                std::find(rule_order().begin(), rule_order().end(), c.first) - rule_order().begin();
            return std::make_tuple(c.first == "another implementation" ? 1 : 0,
                                   -chosen[c.first]->net(), evidence_for(c.first).empty() ? 1 : 0,
                                   pos);
        };
        auto sorted = e.candidates;
        std::stable_sort(sorted.begin(), sorted.end(),
                         [&](const auto& a, const auto& b) { return rank(a) < rank(b); });
        const auto& best = sorted.front();
        const auto tied = [&](const auto& c) {
            const auto rc = rank(c);
            const auto rb = rank(best);
            return std::get<0>(rc) == std::get<0>(rb) && std::get<1>(rc) == std::get<1>(rb) &&
                   std::get<2>(rc) == std::get<2>(rb);
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
            const Alternative& named = *chosen[best.first];
            e.standing = (named.legal ? "legal: " : "violation: ") + named.gl;
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
    if (e.difference != "coverage" &&
        (e.rule == "tie rule" || e.rule == "snapping" || e.rule == "cull" ||
         e.rule == "nine-vertex analysis" || e.rule == "line rule" || e.rule == "point rule" ||
         e.rule == "edge flags" || e.rule == "multisample enable")) {
        e.difference = "coverage";
        what +=
            ", because the coverage of a primitive drawn earlier differs (blending or the depth "
            "test shows it)";
    }
    // A NaN or offset depth that changes coverage does so through the depth test.
    if (e.difference == "coverage" && (e.rule == kNanOffsetRule || e.rule == kOffsetScaleRule)) {
        what += ", because the depth test sees another depth";
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
                          Backend* backend, int sample, double timeout_seconds,
                          const RenderResult* rendered) {
    require_inside(scene.draw_list.target, x, y);  // before the backend renders anything
    Explainer ex(scene, profile, backend, sample, timeout_seconds, rendered);
    return ex.explain(x, y);
}

}  // namespace harness
