// pixel_rect.hpp: an inclusive rectangle of pixels, the unit of boxes and draw regions.
//
// Deliberately does not: know about subpixels or tiles.
#pragma once

#include <algorithm>

namespace refraster::detail {

// An inclusive rectangle of pixels; empty when x0 > x1 or y0 > y1.
struct PixelRect {
    int x0 = 0;
    int y0 = 0;
    int x1 = -1;
    int y1 = -1;
    bool empty() const { return x0 > x1 || y0 > y1; }
    friend bool operator==(const PixelRect&, const PixelRect&) = default;
};
inline PixelRect intersect(const PixelRect& a, const PixelRect& b) {
    return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

}  // namespace refraster::detail
