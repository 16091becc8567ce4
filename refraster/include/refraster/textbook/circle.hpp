// circle.hpp: the midpoint circle.
//
// Implements: the midpoint circle algorithm as Foley, van Dam, Feiner and Hughes state it
// ("Computer Graphics: Principles and Practice", 2nd ed., 3.3.2, the integer version): a
// circle of integer radius R about the centre of pixel c, walked through the second octant
// (offsets 0 <= x <= y) from (0, R) with x increasing, and every pixel drawn with its eight
// mirror images (x, y) -> (+-x, +-y), (+-y, +-x) about c. At each step the candidates are E
// (x + 1, y) and SE (x + 1, y - 1); the decision is the sign of the circle's implicit function
// at their midpoint, F(M) = (x + 1)^2 + (y - 1/2)^2 - R^2: SE when F(M) > 0, E otherwise. The
// integer variable d = F(M) - 1/4 starts at 1 - R and moves by 2x + 3 (E) or 2(x - y) + 5 (SE)
// with the pre-step x and y. The walk stops after the first pixel with y <= x.
//
// Ties: none. With integer R and offsets F(M) is an integer plus 1/4, never 0, and d < 0 holds
// exactly when F(M) < 0; the dropped 1/4 costs nothing. So each pixel of the octant is the
// integer y nearest to sqrt(R^2 - x^2), the exact circle's height at x (never halfway between
// two). When the octant does not end on the diagonal, the walk's last step goes one past it,
// to (x + 1, x) after (x, x + 1): the mirror image of the pixel before, so no pixel is added.
//
// Deliberately does not: draw circles about sub-pixel centres or of non-integer radius (the
// ties then become real), ellipses, filled discs or antialiased circles.
#pragma once

#include <vector>

#include "refraster/textbook/lines.hpp"
#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

struct CircleResult {
    std::vector<PixelIndex> octant;    // the second-octant offsets (x, y) from the centre, in order
    std::vector<long long> decisions;  // d before each step (octant.size() - 1 entries)
    Raster raster;                     // all eight octants, inside the raster
};

CircleResult midpoint_circle(PixelIndex centre, int radius, int width, int height,
                             Trace* trace = nullptr);

}  // namespace refraster::textbook
