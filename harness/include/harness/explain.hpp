// explain.hpp: why one pixel looks the way it does, and where the reference and a GL
// backend part.
//
// Implements: running the reference with its trace hook on one pixel, reading the GL
// backend's bytes there, and a verdict in two steps. First what differs, from the two
// renders alone: coverage (one side leaves the pixel untouched, or another primitive owns it),
// colour (the same coverage, other colour bytes), depth (colours agree, depth values differ),
// sample (on a 4x target, the resolved pixel agrees but a sample does not). Then the rule within
// that class: every variation of rule_search.hpp (the list the GL verdict judges by: each
// parameter of the profile the scene can show, the other built-in implementations' rule sets,
// and the GL rules an implementation may break, such as ignored edge flags) is rendered on the
// whole scene, and a rule is named only when one of its alternatives reproduces the backend at
// this pixel, with GL's standing of it (a freedom or a violation, and its section); where several
// do, the one that brings most of the image into agreement is named, then the one the pixel's trace
// gives direct evidence for (a centre exactly on an edge for the tie rule, an edge within one
// subpixel step for snapping, ...), and the others are listed; two that stay equal make it
// "undecided". A coverage rule that reproduces a colour or depth difference reclasses it as
// coverage (a primitive beneath differs, seen through blending or depth). Coverage that differs
// only at lines (or points) and that no parameter reproduces is put down to the line (point) rule;
// anything else is "undecided". Three renderings of it all: text, JSON, and an SVG of the
// neighbourhood at subpixel zoom (pixel grid, centres, the snapped edges, covered pixels in their
// colours, tie-breaks ringed) for teaching.
//
// On a 4x target the explanation is about one sample when one is named (its edge values and
// tie decisions at the sample, its depth, the bytes written to it; the two sides' sample
// planes are compared), and about the resolved pixel otherwise (sample 0 is traced); either
// way it lists the pixel's four samples on both sides and the resolve's float sum.
//
// Deliberately does not: model the backend. Verdicts come from the two results, the
// reference's trace and the reference re-run under other rules.
#pragma once

#include <deque>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "harness/compare.hpp"
#include "harness/scene.hpp"
#include "refraster/trace.hpp"

namespace harness {

struct Explanation {
    refraster::PixelTrace trace;
    refraster::Profile profile;
    refraster::Framebuffer reference_image;
    std::array<float, 4> reference_color{};
    std::optional<std::uint32_t> reference_depth;
    std::optional<RenderResult> backend;  // the GL render, when one was asked for
    std::array<float, 4> backend_color{};
    std::optional<std::uint32_t> backend_depth;
    // A 4x target: the sample explained (-1: the resolved pixel), and each side's four samples
    // of the pixel (colour and depth), the reference's first.
    int sample = -1;
    std::vector<std::array<float, 4>> reference_samples;
    std::vector<std::optional<std::uint32_t>> reference_sample_depths;
    std::vector<std::array<float, 4>> backend_samples;
    std::vector<std::optional<std::uint32_t>> backend_sample_depths;
    // The texels around the last textured fragment at the pixel (the level it read first), for
    // the teaching view of `--svg`: a window of the level, its origin texel (x0, y0), rows
    // bottom to top, and which primitive sampled it.
    struct TexelWindow {
        std::size_t draw = 0;
        refraster::TextureTrace sample;
        std::uint32_t level_width = 0;
        std::uint32_t level_height = 0;
        int x0 = 0;
        int y0 = 0;
        int columns = 0;
        int rows = 0;
        std::vector<std::array<std::uint8_t, 4>> texels;
    };
    std::optional<TexelWindow> texels;
    bool agree = true;
    std::string difference = "none";  // "coverage", "colour", "depth", "sample", "none"
    std::string rule = "none";        // "tie rule", "snapping", ..., "undecided", "none"
    // Every rule one of whose alternatives reproduces the backend at the pixel, with that
    // alternative ("tie rule" -> "tie_rule=right-top").
    std::vector<std::pair<std::string, std::string>> candidates;
    // GL's word on the rule named (rule_search.hpp): "legal: <freedom (section)>" or
    // "violation: <rule broken (section)>"; empty when no variation is named.
    std::string standing;
    std::string verdict;
    // The GL verdict at the pixel (gl_verdict.hpp's at_pixel), when the caller judged it; the
    // text's "GL:" line and the JSON's "gl_verdict".
    std::string gl_verdict;
};

// A pixel outside the target (a usage error, not a rendering failure).
class PixelOutsideTarget : public std::invalid_argument {
  public:
    using std::invalid_argument::invalid_argument;
};

// One scene, its renders and its alternative renders, kept for explaining many pixels.
class Explainer {
  public:
    // Renders the reference and, when `backend` is given, the backend (each with primitive
    // owners where the backend can report them believably). Throws std::runtime_error when the
    // reference or the backend cannot render the scene. `sample` (0..3, a 4x target only)
    // compares that sample of every pixel instead of the resolved image; std::invalid_argument
    // when the target has no such sample. Every render of the reference here (the plain one,
    // its owners, each alternative rule, each pixel's trace) gets `timeout_seconds` of its own
    // (0 or less: no limit); past it, the render stops and refraster::RenderStopped is thrown
    // with the reference's Timeout message (render_reference_within, backend.hpp). A backend
    // that times out (its own BackendOptions::timeout_seconds) throws RenderStopped the same way.
    // With `rendered` (a render of this scene by `backend`, the one a case failed with), the
    // backend's side is that render and is not rendered again: a failure that depends on what
    // the worker drew before is explained from the render that failed. The backend then
    // renders only the owners, which are used only when that render's colours (and samples)
    // equal `rendered`'s.
    Explainer(const Scene& scene, const refraster::Profile& profile, Backend* backend,
              int sample = -1, double timeout_seconds = 0.0,
              const RenderResult* rendered = nullptr);
    ~Explainer();
    Explainer(const Explainer&) = delete;
    Explainer& operator=(const Explainer&) = delete;

    // Throws PixelOutsideTarget. With `full` false the verdict is the same but the pixel's
    // trace is rendered only when the decision needs it (explaining a whole image is then
    // linear in its pixels), so the trace and the evidence in the verdict's text may be missing,
    // and Explanation::backend carries the backend's outcome without its images.
    Explanation explain(int x, int y, bool full = true);

    // The images compared: the resolved ones, or the planes of the sample asked for.
    const refraster::Framebuffer& reference_image() const { return reference_; }
    // The reference's render of the target: every sample of a 4x target, else the image.
    const refraster::Framebuffer& reference_render() const {
        return reference_samples_.samples > 1 ? reference_samples_ : reference_;
    }
    const RenderResult* backend_render() const {
        return backend_result_ ? &*backend_result_ : nullptr;
    }
    const refraster::Framebuffer& backend_image() const { return backend_view_; }
    // The class of every pixel (compare.hpp), for choosing which pixels to explain.
    const PixelClassifier* classifier() const { return classifier_.get(); }

  private:
    struct Alternative;
    void render_alternatives();
    // What is compared of a render of the target: the image itself (single-sample), or of a
    // 4x render its resolve or the plane of sample_.
    refraster::Framebuffer view(const refraster::Framebuffer& fb) const;

    const Scene& scene_;
    refraster::Profile profile_;
    int sample_ = -1;
    double timeout_seconds_ = 0.0;
    refraster::Framebuffer reference_samples_;  // every sample of a 4x target
    refraster::Framebuffer reference_;
    refraster::Framebuffer backend_view_;
    std::optional<RenderResult> backend_result_;
    std::unique_ptr<PixelClassifier> classifier_;
    bool alternatives_ready_ = false;
    std::size_t mismatched_ = 0;  // pixels of the image that differ
    std::deque<Alternative> alternatives_;
};

// One pixel: an Explainer used once.
Explanation explain_pixel(const Scene& scene, const refraster::Profile& profile, int x, int y,
                          Backend* backend, int sample = -1, double timeout_seconds = 0.0,
                          const RenderResult* rendered = nullptr);

std::string explanation_text(const Explanation& e);
std::string explanation_json(const Explanation& e);
// The neighbourhood of the pixel, `radius` pixels around it, drawn from the reference.
std::string explanation_svg(const Explanation& e, int radius = 4);

}  // namespace harness
