// edge_functions.hpp: GL's own edge functions, as the reference's triangle setup computes them,
// for showing the half-space rule next to the textbook algorithms.
//
// Implements: the rule a profile gives a draw (sub-pixel precision, snap rounding, pixel
// centre offset, tie rule); a window position snapped to that grid; and the edge function
// E(px, py) = c - a * (px << bits) + b * (py << bits) of a snapped edge, with the tie rule's +1
// in c on the edges that own the pixel centres lying on them. A pixel centre is covered iff
// the three edge functions of a counter-clockwise triangle are all positive there.
//
// Deliberately does not: clip, cull, orient a triangle or walk its pixels; the caller does
// what it wants to show. The values are bit for bit those of the reference's setup.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "refraster/draw.hpp"
#include "refraster/profile.hpp"

namespace refraster::textbook {

// How a draw's window positions snap and which edges own their ties.
struct GlEdgeRule {
    int subpixel_bits = 8;
    SnapRounding snap_rounding = SnapRounding::NearestEven;
    // The profile's offset, or 0 for a multisampled draw (the snap has no pixel offset then).
    float pixel_center_offset = 0.5f;
    TieRule tie_rule = TieRule::LeftBottom;
};

// The rule `profile` gives a draw with `state` on `target`.
GlEdgeRule gl_edge_rule(const Profile& profile, const DrawState& state, const Target& target);

// A window position snapped as setup snaps a vertex: the pixel centre of (px, py) becomes
// (px << bits, py << bits). nullopt for a position outside the snapped coordinates' budget.
std::optional<std::array<std::int32_t, 2>> gl_snap(const GlEdgeRule& rule, float x, float y);

// The edge function of a snapped edge.
struct GlEdgeFunction {
    std::int32_t a = 0;  // dE/dpx = -a << bits
    std::int32_t b = 0;  // dE/dpy = +b << bits
    std::int64_t c = 0;  // the tie rule's +1 included
    bool owns_ties = false;

    // E at the pixel (px, py) of a grid of `subpixel_bits`.
    std::int64_t at(int px, int py, int subpixel_bits) const;
};

// The edge from `from` to `to` (snapped positions); the interior of a counter-clockwise
// triangle is where it is positive.
GlEdgeFunction gl_edge_function(const GlEdgeRule& rule, const std::array<std::int32_t, 2>& from,
                                const std::array<std::int32_t, 2>& to);

}  // namespace refraster::textbook
