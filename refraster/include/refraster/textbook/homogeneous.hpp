// homogeneous.hpp: triangle rasterization in 2D homogeneous coordinates, without clipping, and
// the clip-then-rasterize reference it is compared with.
//
// Implements:
// - homogeneous_rasterize(): Olano and Greer 1997 ("Triangle scan conversion using 2D
//   homogeneous coordinates", Graphics Hardware '97). The vertices, in clip space (x, y, w),
//   go through the viewport as homogeneous points V_i = (X_i, Y_i, w_i) with
//   X_i = (vx + (x_i / w_i + 1) width / 2) w_i, so no division happens. With M = [V_0 V_1 V_2]
//   (columns), the rows of adj(M) = det(M) M^-1 are the three edge functions, e_k(p) =
//   (V_k+1 x V_k+2) . (p_x, p_y, 1), linear in the window position p. A point of the plane is
//   the image of a point t_0 V_0 + t_1 V_1 + t_2 V_2 of the triangle with w > 0 exactly when
//   M^-1 p has three positive components, that is when every e_k has the sign of det(M); then
//   1/w = (e_0 + e_1 + e_2) / det(M) > 0, the "w > 0 test", which that sign test implies. When
//   all three have the opposite sign, the point is the image of the triangle's part behind the
//   eye (w < 0): the "external triangle". With w_positive_test false the rasterizer accepts
//   any common sign and so draws the external triangle too (the classic mistake).
// - clip_then_rasterize(): the triangle clipped against the plane w = near_w (Sutherland-
//   Hodgman, in homogeneous coordinates), its vertices projected, and the convex polygon's
//   pixel centres found by exact edge tests. Only w is clipped: the raster bounds are the
//   guard band, as for the homogeneous rasterizer.
// - explain_difference(): why a pixel differs between the two.
// Both rasterizers sample pixel centres with GL's tie rule: the exact test at the centre nudged
// to (x_c + e, y_c + e^2) (a centre exactly on an edge counts when the region just right, or
// for a horizontal edge just above, is inside). So on every edge of the original triangle
// they agree, and they differ only where 0 < w <= near_w (the clipped sliver) or, without the
// w test, in the external triangle.
//
// Exactness: clip coordinates snapped to 1/256 within |v| <= 2^12, near_w likewise (> 0), the
// viewport's integers within 2^12 (asserted). Then 512 V_i are integers below 2^35, the edge
// functions at doubled centres below 2^87 and det below 2^106 (128-bit). The clipped vertices
// are integer multiples of the exact ones, and the reference's edge tests are 3 x 3
// determinants of them in 1024-bit integers (big_int.hpp). No decision rounds.
//
// Deliberately does not: interpolate attributes (Olano and Greer's perspective-correct
// interpolation falls out of the same adjugate, but is not needed for coverage), clip against
// the side planes or scissor to the viewport, or handle z.
#pragma once

#include <array>
#include <cstdint>

#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

struct ClipVertex {
    double x = 0.0;
    double y = 0.0;
    double w = 1.0;
};

using ClipTriangle = std::array<ClipVertex, 3>;

struct Viewport {
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
};

Raster homogeneous_rasterize(const ClipTriangle& triangle, Viewport viewport, int width, int height,
                             bool w_positive_test = true, Trace* trace = nullptr);

Raster clip_then_rasterize(const ClipTriangle& triangle, Viewport viewport, double near_w,
                           int width, int height, Trace* trace = nullptr);

enum class HomogeneousDifference : std::uint8_t {
    // Categories by the nudged edge signs, the rasterizers' own decision:
    ExternalTriangle,        // every edge function has the sign opposite det: w < 0 there
    BetweenEyeAndNearPlane,  // inside the w > 0 triangle, but 0 < w <= near_w: clipped away
    OnEdge,                  // neither, and the centre is exactly on an edge line
    Unexplained,
};

HomogeneousDifference explain_difference(const ClipTriangle& triangle, Viewport viewport,
                                         double near_w, int x, int y);

const char* to_string(HomogeneousDifference d);

}  // namespace refraster::textbook
