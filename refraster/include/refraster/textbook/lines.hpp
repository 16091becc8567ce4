// lines.hpp: the three textbook line algorithms, DDA, Bresenham and midpoint.
//
// Implements, for a segment from a to b in window coordinates, one pixel per step along the
// major axis (x when |dx| >= |dy|, else y), from a's pixel to b's pixel inclusive:
// - dda_line: the digital differential analyzer as Foley, van Dam, Feiner and Hughes state it
//   ("Computer Graphics: Principles and Practice", 2nd ed., 3.2.1): the minor coordinate is a
//   double advanced by the slope each step and rounded per step with floor(v + 0.5), so a tie
//   goes to the larger minor coordinate (MinorTie::TowardPositive) up to float error.
// - bresenham_line: Bresenham 1965 ("Algorithm for computer control of a digital plotter",
//   IBM Systems Journal 4(1)): the integer decision variable nabla = 2*b*i - 2*a*k - a for the
//   major length a, minor length b, step i and minor offset k, started at 2b - a and advanced
//   by 2b or 2b - 2a. The paper moves diagonally when nabla >= 0, so its default tie is
//   MinorTie::Step.
// - midpoint_line: Pitteway 1967 / van Aken 1984 as Foley 3.2.2 states it: the line reflected
//   into the first octant, the implicit function F(x, y) = dy*x - dx*y + c evaluated (doubled)
//   at the midpoint (x + 1, y + 1/2) between the two candidates; d <= 0 chooses E, so its
//   default tie is MinorTie::Keep. For lines the two integer algorithms compute the same
//   decision numbers by different derivations; they differ in their default tie.
// A tie is a major-axis step where the exact line passes exactly halfway between the two
// candidate pixel centres.
//
// Endpoints: the textbook has no sub-pixel precision. Each endpoint becomes the pixel whose
// square contains it, (floor(x), floor(y)) (a point on a pixel boundary goes to the pixel
// above or to the right), and the algorithms draw the line between those pixels' centres.
//
// Deliberately does not: follow GL's diamond-exit rule (docs/teaching.md compares them), use the
// sub-pixel position of the endpoints, omit the last pixel, or antialias (wu_line.hpp).
#pragma once

#include <cstdint>
#include <vector>

#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

// Which of the two candidate pixels a line algorithm takes on a tie.
enum class MinorTie : std::uint8_t {
    Keep,            // stay on the current minor coordinate (the candidate nearer the start)
    Step,            // take the step (the candidate nearer the end)
    TowardNegative,  // the smaller minor coordinate, whichever way the line runs
    TowardPositive,  // the larger minor coordinate, whichever way the line runs
};

struct PixelIndex {
    int x = 0;
    int y = 0;
    friend bool operator==(const PixelIndex&, const PixelIndex&) = default;
};

// The pixel whose square contains p: (floor(x), floor(y)).
PixelIndex pixel_containing(Point2 p);

struct LineResult {
    std::vector<PixelIndex> path;  // one pixel per major step, in drawing order, none dropped
    Raster raster;                 // the path's pixels inside the raster, weight 1
};

LineResult dda_line(Point2 a, Point2 b, int width, int height, Trace* trace = nullptr);
LineResult bresenham_line(Point2 a, Point2 b, int width, int height, MinorTie tie = MinorTie::Step,
                          Trace* trace = nullptr);
LineResult midpoint_line(Point2 a, Point2 b, int width, int height, MinorTie tie = MinorTie::Keep,
                         Trace* trace = nullptr);

// Whether a tie, on a line whose minor coordinate moves in the direction minor_sign (+1 or
// -1), takes the step.
bool tie_takes_step(MinorTie tie, int minor_sign);

}  // namespace refraster::textbook
