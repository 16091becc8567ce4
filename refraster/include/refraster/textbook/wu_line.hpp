// wu_line.hpp: Xiaolin Wu's antialiased line.
//
// Implements: Wu 1991 ("An efficient antialiasing technique", SIGGRAPH '91) in its usual
// floating-point formulation with sub-pixel endpoints. In the frame where pixel centres are
// the integers (u = x - 1/2, v = y - 1/2) and the major axis is u (the line is "steep" when
// |dv| > |du|, and the axes are swapped), running left to right with gradient g = dv/du:
// - the columns are c = round(u0) .. round(u1), round(t) = floor(t + 1/2), column c covering
//   [c - 1/2, c + 1/2);
// - column c's length L is the part of [u0, u1] inside it: 1 inside the line,
//   c + 1/2 - u0 at the first column (the usual "xgap = rfpart(x0 + 0.5)"),
//   u1 - (c - 1/2) at the last, u1 - u0 when both ends share a column;
// - the line's minor coordinate at the column centre, v_c = v0 + g (c - u0), computed as Wu
//   does by adding g once per column, splits the column between rows floor(v_c) and
//   floor(v_c) + 1 with weights (1 - frac(v_c)) L and frac(v_c) L.
// So the two weights of a column sum to L (1 inside the line), and each weight is the
// vertical overlap of a 1-pixel-thick band around the line with the pixel, sampled at the
// column centre. Against the exact area of that band inside the pixel, the error is at most
// |g| / 4 per pixel (|overlap(u) - overlap(c)| <= |g| |u - c|, integrated over a column), and
// that bound is reached when the line passes through a pixel centre.
//
// Deliberately does not: use Wu's symmetric double-step or his fixed-point intensity
// accumulator (the weights are doubles), gamma-correct the weights, or give the line any
// width but one pixel measured along the minor axis.
#pragma once

#include <vector>

#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

// One major-axis step of Wu's line: the pair of pixels it weights.
struct WuColumn {
    int x_low = 0;  // the pixel with the smaller minor coordinate
    int y_low = 0;
    int x_high = 0;  // its neighbour one step up the minor axis
    int y_high = 0;
    double weight_low = 0.0;
    double weight_high = 0.0;
    double length = 0.0;  // the column's share of the major extent, weight_low + weight_high
    double minor = 0.0;   // v_c, the line's minor coordinate at the column centre (v frame)
};

struct WuResult {
    std::vector<WuColumn> columns;  // in drawing order, none dropped
    Raster raster;                  // the weights inside the raster
};

WuResult wu_line(Point2 a, Point2 b, int width, int height, Trace* trace = nullptr);

}  // namespace refraster::textbook
