// painter.hpp: hidden surfaces by the painter's algorithm and by a z-buffer, and where the two
// disagree.
//
// Implements:
// - painter(): the depth sort of Newell, Newell and Sancha's algorithm without its overlap
//   tests and splits, as Foley, van Dam, Feiner and Hughes present the simple painter's
//   algorithm (15.5): triangles sorted back to front by a key (PainterKey: the farthest
//   vertex's depth, or the mean depth), ties in input order, then drawn in that order, each
//   pixel showing the last triangle drawn over it;
// - z_buffer(): Catmull's z-buffer (Foley 15.4): triangles drawn in input order, a pixel taking
//   a triangle when its depth at the pixel centre is strictly less than the stored one (GL's
//   LESS; equal depths keep the earlier triangle);
// - first_difference(): the first pixel, in row-major order from the bottom row, where the two
//   show different triangles, and the two triangles.
// Depth follows GL's convention: smaller is nearer. A triangle's depth at a point is the
// affine (screen-space linear) interpolation of its vertex depths, as window-space z is in GL.
//
// Coverage, shared by both: pixel (i, j) is covered when its centre is inside the triangle
// under GL's tie rule, i.e. the exact test at the centre nudged to (x_c + e, y_c + e^2): a
// centre exactly on an edge counts when the region just right of it (or, for a horizontal
// edge, just above) is inside. Triangles of either orientation; zero-area ones cover nothing.
//
// Exactness: positions snapped to 1/256 pixel (snap.hpp), depths to 2^-16 within |z| <= 2^8.
// The depth at a centre is the rational N / D, N = sum of edge functions times snapped depths
// (below 3 * 2^47 * 2^24 < 2^73), D = twice the area (below 2^48); two depths compare by
// N1 D2 against N2 D1 in 128 bits (below 2^121). No depth decision rounds.
//
// Deliberately does not: resolve cyclic overlaps or interpenetration by splitting (that is the
// point the comparison makes), clip, or cull back faces.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

struct DepthTriangle {
    std::array<Point2, 3> position{};
    std::array<double, 3> depth{};
};

enum class PainterKey : std::uint8_t {
    FarthestVertex,  // the largest vertex depth
    MeanDepth,       // the mean of the three vertex depths
};

struct VisibilityResult {
    int width = 0;
    int height = 0;
    std::vector<int> visible;  // per pixel, row-major from the bottom: triangle index or -1
    std::vector<int> order;    // the drawing order
    Raster raster;             // weight 1 where some triangle is visible
    int at(int x, int y) const;
};

// Whether the triangle covers the centre of pixel (x, y) under the rule above.
bool covers_centre(const DepthTriangle& triangle, int x, int y);

VisibilityResult painter(const std::vector<DepthTriangle>& triangles, PainterKey key, int width,
                         int height, Trace* trace = nullptr);
VisibilityResult z_buffer(const std::vector<DepthTriangle>& triangles, int width, int height,
                          Trace* trace = nullptr);

struct VisibilityDifference {
    int x = 0;
    int y = 0;
    int painter_triangle = -1;
    int z_buffer_triangle = -1;
    friend bool operator==(const VisibilityDifference&, const VisibilityDifference&) = default;
};

std::optional<VisibilityDifference> first_difference(const VisibilityResult& painted,
                                                     const VisibilityResult& z_buffered);

}  // namespace refraster::textbook
