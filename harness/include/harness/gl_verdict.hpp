// gl_verdict.hpp: whether a backend's differing pixels are freedoms GL grants or violations.
//
// Implements: the GL verdict of a comparison. Every pixel where the backend differs from the
// reference under its profile is judged against the rules the GL specification leaves to the
// implementation (OpenGL 4.6: sub-pixel precision of at least 4 bits and its rounding, 14.6.1's
// tie rule as long as a centre on a shared edge has exactly one owner, clipping against the view
// volume or a guard band, line rasterisation within the diamond-exit tolerance (14.5.1), point
// rasterisation, interpolation and conversion precision, 2.3.5, and the others rule_search.hpp
// lists). The scene is rendered through the reference under each variation of rule_search.hpp,
// the list explain searches too: every single such rule changed in the profile, the rule sets
// of the other built-in driver profiles, and GL rules an implementation may break, each with
// its section. A pixel that one of them reproduces
// (colour and depth bit for bit) is a legal variation, named by the freedom. A pixel none
// reproduces is checked against the requirements every conforming implementation keeps:
//  - a hole: the backend leaves the pixel untouched where every legal rule draws it (a
//    centre on a shared edge with no owner is named as such, reproduced by tie_rule=none);
//  - a double hit: a centre on a shared edge drawn twice (reproduced by tie_rule=all, visible
//    where blending accumulates);
//  - a pixel outside every legal coverage: drawn where no legal rule draws it;
//  - non-monotonic depth: a depth outside the range the legal rules give at the pixel;
// and otherwise reported as unexplained (neither certified legal nor proven a violation).
// Pixels reached by a draw whose attributes are beyond GL's floating-point range (NaN,
// infinity, a magnitude above 2^32: 2.3.4.1 leaves their results unspecified) are legal
// whatever colour the backend gives them, as long as the depth agrees.
//
// A multisampled target is judged sample by sample: pass the framebuffers of every sample
// (RenderResult::samples).
//
// Deliberately does not: textures' filtering and LOD freedoms beyond rho's approximation (a
// texel difference is unexplained unless a variation reproduces it, such as another
// implementation's rule set), or blending arithmetic.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/scene.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/profile.hpp"

namespace harness {

struct GlFinding {
    std::string rule;  // the freedom, or the violated requirement
    bool legal = true;
    std::uint64_t pixels = 0;
    int x = -1, y = -1;  // the first such pixel
    int sample = -1;     // its sample, on a multisampled target
    std::string detail;  // which variation reproduces it, or why it violates
};

struct GlVerdict {
    // What is counted: "pixels", or "samples" on a multisampled target (judged sample by
    // sample).
    std::string unit = "pixels";
    std::uint64_t differing = 0;
    std::uint64_t legal = 0;
    std::uint64_t violations = 0;
    std::uint64_t unexplained = 0;
    // Renders of the variations that stopped at the timeout (the cleared target counts as
    // one), out of `variations`. When any did, no pixel is called a violation: the others are
    // unexplained.
    std::uint64_t stopped = 0;
    std::uint64_t variations = 0;
    std::vector<GlFinding> findings;  // by rule, in the order first met
    // The verdict at the pixel asked for (gl_verdict's `at`): "same as the reference", or
    // "legal: <freedom> (<setting> reproduces the backend)", or "violation: <rule> (...)".
    std::string at_pixel;
    // GL-legal: every differing pixel is a legal variation.
    bool passes() const { return violations == 0 && unexplained == 0; }
    // One line: "legal: 12 px (tie rule 8, sub-pixel precision 4); ..." or the violations.
    std::string summary() const;
};

// `at_sample` picks the sample of `at` on a multisampled target. `preferred` (a setting, e.g.
// "tie_rule=right-top", the one an explanation named) is the variation named at `at` when it
// reproduces the backend there, so that the two never name different freedoms.
// Judges every pixel where `backend` differs from `reference` (the scene rendered under
// `profile`). Both images must have the scene's target size. Each variation's render gets
// `timeout_seconds` of its own (0 or less: no limit; render_reference_within, backend.hpp).
GlVerdict gl_verdict(const Scene& scene, const refraster::Profile& profile,
                     const refraster::Framebuffer& reference, const refraster::Framebuffer& backend,
                     std::optional<std::array<int, 2>> at = std::nullopt,
                     double timeout_seconds = 0.0, int at_sample = 0,
                     const std::string& preferred = "");

}  // namespace harness
