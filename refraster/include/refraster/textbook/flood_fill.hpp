// flood_fill.hpp: boundary fill from a seed, 4- or 8-connected.
//
// Implements: the boundary fill of Foley, van Dam, Feiner and Hughes ("Computer Graphics:
// Principles and Practice", 2nd ed., 19.5.2, BoundaryFill4 and its 8-connected variant) with
// the recursion replaced by an explicit stack: push the seed; pop a pixel; if it is inside the
// raster, not a boundary pixel (weight > 0 in the boundary raster) and not filled yet, fill it
// and push its 4 (or 8) neighbours in reverse, so that the pops visit them as a recursion
// would: right, left, up, down, then the diagonals (a choice: the filled set does not depend
// on it, only the order and the stack's depth). The filled set is the seed's
// 4- (or 8-) connected component of non-boundary pixels; empty when the seed is a boundary
// pixel or outside the raster.
//
// The classic pairing: an 8-connected boundary (a Bresenham outline) holds a 4-connected fill,
// but an 8-connected fill leaks through its diagonal steps; a 4-connected boundary holds both.
//
// The seed inside an outline (seed_inside): the first pixel that is not a boundary pixel and whose
// centre the outline winds around (winding number not 0 at the centre nudged by (+e, +e^2), GL's
// tie rule), in rings of growing Chebyshev distance from the pixel holding the mean of the
// outline's vertices, each ring row by row from the bottom and left to right. Only pixels whose
// centres lie in the outline's bounding box (clipped to the raster) can be inside, so only they
// are tested, each at most once: the search examines at most the box's pixels, each at the cost
// of one pass over the outline's edges.
//
// Deliberately does not: fill by spans (the scanline seed fill), fill by colour similarity
// (flood fill proper: here the boundary alone stops the fill), or draw the boundary itself.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "refraster/textbook/lines.hpp"
#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

enum class Connectivity : std::uint8_t { Four, Eight };

struct FloodResult {
    std::vector<PixelIndex> order;  // the filled pixels, in fill order
    Raster raster;                  // weight 1 on filled pixels, the boundary's size
};

// The winding number of `outline` (closed: the last point joins the first) around the centre of
// pixel (x, y) nudged by (+e, +e^2), from the crossings of the nudged horizontal line.
int winding_at_centre(const std::vector<Point2>& outline, int x, int y);

// The seed of `outline` in `boundary` (see above), or none when no pixel qualifies. `examined`,
// when given, receives the number of pixels tested.
std::optional<PixelIndex> seed_inside(const Raster& boundary, const std::vector<Point2>& outline,
                                      std::size_t* examined = nullptr);

FloodResult flood_fill(const Raster& boundary, PixelIndex seed, Connectivity connectivity,
                       Trace* trace = nullptr);

}  // namespace refraster::textbook
