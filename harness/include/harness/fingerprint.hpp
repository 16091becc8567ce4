// fingerprint.hpp: infer the rules of a GL implementation from what it draws.
//
// Implements: a fixed set of probe scenes (triangles on fine subpixel grids and through pixel
// centres; width-1 lines; points of fractional sizes; primitives bleeding past a viewport;
// perspective-correct colours into rgba32f; depth values and clears; colours between two
// bytes), rendered once through the backend under study and, for every candidate value of the
// rules each probe is sensitive to, through the reference. A rule is decided when exactly one
// value reproduces every probe pixel given the rules decided before it; the finding carries
// the evidence (the probe and a pixel where a rival value gives another result than the
// backend's). A rule no candidate reproduces, or that several reproduce, is undecided: it is
// reported so, and the profile keeps its family's default for it, never a guess.
//
// Rules, in the order they are decided (profile keys, docs/precision.md):
//   coverage, subpixel_bits, snap_rounding, pixel_center_offset, tie_rule  (jointly)
//   line_rule; line width rounding (a finding from the same probe, implied by the line rule)
//   point_rule; point_line_clipping (points and wide lines); viewport_fma, and the attribute
//   setup order (a finding: the coverage family's, which the fusion probe confirms); clipping
//   (triangles, from their float colours); depth_rounding; offset_units_scale; depth_clear;
//   color_rounding. Then, per primitive class, findings on the rules one profile holds for every
//   class but decided from one or from all together (OpenGL 4.6 lets each class differ):
//   line_snapping and point_snapping (the triangles' snapping, every snapping tried with the
//   class's own rule), point_clipping and line_clipping (point_line_clipping on each alone),
//   line_precision and point_precision (the triangles' depth and colour conversions): "as ..."
//   when the profile's values reproduce the class, "differs" (undecided, with a pixel and the
//   values that do) otherwise; a differing class keeps the profile's values. Then two findings on
//   draw state GL requires honoured, never written into the profile: multisample_enable
//   (GL_MULTISAMPLE disabled on a 4x target, 14.3.1) and edge_flags (a GL_POLYGON's internal edges
//   in polygon mode line, 14.6.4): "honoured", "ignored" or "n/a"; and point_sprite_origin
//   (GL_POINT_SPRITE_COORD_ORIGIN, 14.4, drawn upper-left and lower-left in turn, and swapped in a
//   fresh worker): "honoured", "ignored" or "order-dependent". Then texture_rho (8.14.1's rho),
//   texture_mip_blend and texture_filtering, jointly from a trilinear perspective probe, and
//   texture_sampling, a finding: the same probe against the profile decided, undecided where the
//   backend's LOD or filtering arithmetic is none the profile has. A rule the family's model does
//   not read (refraster::unread_parameter) is not probed. Each rule's values are those of
//   rule_search.hpp, and the JSON gives each decided value's GL standing.
//
// Deliberately does not: infer the driver quirks (flush_denormals, draw_pipeline_cull,
// draw_segment_vertices, nine_vertex_quirk, wrapping_arithmetic, draw_offset_nan_to_zero,
// fill_clear_writes_tiles: the family's defaults are kept and listed as not probed), blending,
// textures or multisampling, or rules the reference cannot draw (a diamond-exit line rule other
// than llvmpipe's is reported undecided).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "harness/backend.hpp"
#include "refraster/profile.hpp"

namespace harness {

struct RuleFinding {
    // A profile parameter, or a finding only: "line_width_rounding", "attribute_setup_order".
    std::string key;
    std::string value;
    bool decided = false;
    bool probed = true;                   // false: not probed, the family's default kept
    std::vector<std::string> candidates;  // the values tried
    std::vector<std::string> matching;    // the values that reproduce every probe pixel
    std::string evidence;                 // one line: probe, pixel, values
};

struct FingerprintResult {
    std::string backend;
    std::vector<RuleFinding> rules;
    refraster::Profile profile;  // loadable; undecided rules keep the family's defaults
    bool complete() const;       // every probed rule decided
};

using FingerprintProgress = std::function<void(const std::string&)>;
// Another backend of the same implementation in a fresh worker (null when none can be made),
// for the probes whose answer may depend on what the worker drew before.
using FreshBackend = std::function<std::unique_ptr<Backend>()>;

// Runs every probe through `target` and the reference. Throws std::runtime_error when the
// backend cannot render a probe at all (a crash or an internal error); a probe the backend
// does not support leaves its rules undecided.
// With `fresh`, the sprite-origin probes run again in a fresh worker, so that an origin that
// depends on the worker's history is told from one that is ignored.
FingerprintResult fingerprint(Backend& target, const FingerprintProgress& progress = {},
                              const FreshBackend& fresh = {});

// One line per rule: key, value (or "undecided"), evidence.
std::string fingerprint_text(const FingerprintResult& r);
// The findings as JSON: {"backend", "complete", "profile": {...}, "rules": [...]}.
std::string fingerprint_json(const FingerprintResult& r);

}  // namespace harness
