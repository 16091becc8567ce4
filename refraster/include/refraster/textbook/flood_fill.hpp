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
// Deliberately does not: fill by spans (the scanline seed fill), fill by colour similarity
// (flood fill proper: here the boundary alone stops the fill), or draw the boundary itself.
#pragma once

#include <cstdint>
#include <vector>

#include "refraster/textbook/lines.hpp"
#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

enum class Connectivity : std::uint8_t { Four, Eight };

struct FloodResult {
    std::vector<PixelIndex> order;  // the filled pixels, in fill order
    Raster raster;                  // weight 1 on filled pixels, the boundary's size
};

FloodResult flood_fill(const Raster& boundary, PixelIndex seed, Connectivity connectivity,
                       Trace* trace = nullptr);

}  // namespace refraster::textbook
