// rule_search.hpp: the rules under which the reference might draw what a backend drew: one
// list that `explain`, the GL verdict (gl_verdict.hpp), `reduce`'s signature (through explain)
// and `fingerprint` all search, so that no two of them answer from different rule sets.
//
// Implements: rule_variations(profile, scene), every variation of the profile and of how the
// scene is drawn that the scene can show, each with its GL standing:
//  - a freedom GL leaves to the implementation (OpenGL 4.6; the section is cited in `gl`):
//    sub-pixel precision and its rounding, any tie rule that gives a centre on a shared edge one
//    owner (14.6.1), clipping with or without a guard band (13.7), point and line clipping by
//    vertices or by pixels, line and point rasterisation within their tolerances (14.5.1, 14.4),
//    interpolation, conversion and clear precision (2.3.4.1, 2.3.5), polygon offset's r
//    (14.6.5), the texture LOD's rho (8.14.1), the mip blend (8.14.3), denormals flushed to
//    zero and facing computed
//    at the implementation's precision (2.3.4.1), results of values beyond the
//    implementation's range (2.3.4.1), and the whole rule set of another modelled conforming
//    implementation;
//  - a violation, a rule every conforming implementation keeps broken on purpose, so that a
//    backend that breaks it is reproduced and named: a centre on a shared edge with no owner or
//    two (14.6.1), a triangle of a draw dropped (llvmpipe's nine-vertex analysis), brilinear
//    filtering (a LOD outside 8.14.1's bounds), GL_MULTISAMPLE disabled ignored (14.3.1), edge
//    flags ignored (14.6.4);
// and search_values(key), the values each profile parameter is searched over, which the
// fingerprint's probes search as well.
//
// Only a parameter the profile's model reads (refraster::unread_parameter) is varied, and a rule
// that needs some draw (polygon offset, lines, points, textures, fill rules with blending,
// GL_POLYGON outlines, GL_MULTISAMPLE off on a 4x target) only when the scene has one.
//
// Deliberately does not: vary textures' filtering precision (llvmpipe's float path for what it
// samples in 8 bits is a rule the profile does not have: such a texel difference is unexplained
// unless another implementation's rule set reproduces it), or render anything: each caller
// renders the variations it needs.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "harness/scene.hpp"
#include "refraster/profile.hpp"

namespace harness {

struct RuleVariation {
    // The rule as explain names it: "tie rule", "snapping", "polygon offset r", "edge flags",
    // "another implementation", ...
    std::string rule;
    // What changes: "key=value", a built-in profile's name, or "edge flags ignored".
    std::string setting;
    // True: a freedom GL grants. False: a GL rule broken.
    bool legal = true;
    // The freedom, or the rule broken, with its section of OpenGL 4.6.
    std::string gl;
    refraster::Profile profile;
    // The scene as an implementation that ignores some of its state draws it (null: the scene
    // itself).
    std::shared_ptr<const Scene> scene;
};

// Every variation the scene can show under `profile`, freedoms first (in the order a tie
// between equally good explanations is broken: the draw module's decisions, coverage, then
// arithmetic), then violations. No variation equals `profile`.
std::vector<RuleVariation> rule_variations(const refraster::Profile& profile, const Scene& scene);

// The scene as an implementation that ignores GL_MULTISAMPLE disabled draws it (every draw of a
// 4x target multisampled), or null when no draw of a 4x target disables it.
std::shared_ptr<const Scene> multisample_enable_ignored(const Scene& scene);
// The scene as an implementation that ignores edge flags draws it: each GL_POLYGON in polygon
// mode line or point (no fill rule) as the triangles it is split into, in the polygon's own
// split and vertex order; null when no draw is such a polygon.
std::shared_ptr<const Scene> edge_flags_ignored(const Scene& scene);

// The values a parameter is searched over (empty for a parameter never searched): the
// variations above and the fingerprint's probes use the same lists.
std::vector<std::string> search_values(const std::string& key);

// The GL standing of a parameter at a value, as rule_variations states it: "legal: <freedom>"
// or "violation: <rule>"; empty for a parameter rule_variations never varies.
std::string gl_standing(const std::string& key, const std::string& value);

}  // namespace harness
