// scanline_fill.hpp: polygon fill by scanlines, with an edge table and an active edge list.
//
// Implements: the scan-conversion of Foley, van Dam, Feiner and Hughes ("Computer Graphics:
// Principles and Practice", 2nd ed., 3.6), sampling at pixel centres, for any set of closed
// contours (self-intersecting, nested, overlapping), under the even-odd or the non-zero
// winding rule:
// - the edge table (ET) holds every non-horizontal edge, bucketed by the first scanline whose
//   centre height y_c = j + 1/2 it reaches; an edge is active on scanline j when
//   ymin <= y_c < ymax (half-open in y: its bottom vertex counts, its top does not; horizontal
//   edges are never active);
// - the active edge list (AEL), sorted by crossing x, receives the ET bucket of each scanline,
//   drops the edges whose ymax it has passed, and advances each crossing by 1/m per scanline;
// - along the scanline the crossings are walked left to right, counting crossings (even-odd)
//   or summing their directions (+1 upward, -1 downward; non-zero), and the pixels whose
//   centres x_c = i + 1/2 fall in an inside interval are filled: intervals are half-open,
//   x_left <= x_c < x_right.
// This convention is the exact point-in-polygon test at the centre nudged to (x_c + e,
// y_c + e^2) for an infinitesimal e, the same point GL's stencil-based fills test.
//
// Exactness: vertices are snapped to 1/256 pixel (snap.hpp, as GL's 8 sub-pixel bits) and
// every crossing is kept exactly as an integer plus a fraction with the edge's dy as
// denominator, advanced by integer addition (Foley's integer edge tracking, in 1/256 units);
// no decision rounds.
//
// Deliberately does not: antialias, treat horizontal edges as spans of their own, or fill
// edge pixels whose centres are outside (the textbook's "shared edge" pixels belong to
// exactly one of two adjacent polygons by the half-open rules).
#pragma once

#include <cstdint>
#include <vector>

#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

enum class FillRule : std::uint8_t { EvenOdd, NonZero };

// Pixels [x_begin, x_end) of row y.
struct Span {
    int y = 0;
    int x_begin = 0;
    int x_end = 0;
    friend bool operator==(const Span&, const Span&) = default;
};

struct FillResult {
    std::vector<Span> spans;  // inside the raster, bottom row first, left to right
    Raster raster;
};

using Contour = std::vector<Point2>;

FillResult scanline_fill(const std::vector<Contour>& contours, FillRule rule, int width, int height,
                         Trace* trace = nullptr);

}  // namespace refraster::textbook
