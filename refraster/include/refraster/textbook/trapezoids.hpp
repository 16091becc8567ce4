// trapezoids.hpp: the trapezoidal decomposition of a simple polygon, and its triangulation.
//
// Implements: the decomposition Seidel's algorithm builds (Seidel 1991, "A simple and fast
// incremental randomized algorithm for computing trapezoidal decompositions and for
// triangulating polygons", Computational Geometry 1(1)): through every vertex, a horizontal
// chord extends left and right inside the polygon to the nearest edge; the chords cut the
// polygon into trapezoids, each bounded by two edges on the left and right and by horizontals
// through a vertex at the bottom and at the top (either may shrink to a point).
//
// Computed not by Seidel's randomized incremental construction and its query structure, but
// by a deterministic slab sweep that yields the same trapezoids: horizontal lines through
// every vertex height cut the polygon into slabs; in each slab the edges spanning it, sorted
// by x at mid-height, pair off into interior trapezoids (the polygon is simple, so they do not
// cross inside a slab and inside is between pairs); then each slab trapezoid is merged with the
// one below it when both are bounded by the same two edges: no vertex lies on the chord between
// them, so Seidel's decomposition has no cut there. Horizontal edges bound slabs and are never
// a trapezoid's side.
//
// triangulate() splits each trapezoid along its diagonal from bottom-left to top-right, one
// triangle when a side has shrunk to a point. (Seidel's triangulation goes on to monotone
// pieces and fewer triangles; this split is the simple one that tiles exactly.)
//
// Exactness: vertices snapped to 1/256 pixel (snap.hpp); the orders at mid-slab are exact
// integer comparisons. Corner x coordinates are reported as doubles; the edge indices and the
// heights (vertex heights, exact) define them exactly.
//
// Deliberately does not: accept self-intersecting polygons or holes, handle the
// point-location queries Seidel's structure supports, or produce monotone polygons.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "refraster/textbook/trace.hpp"

namespace refraster::textbook {

// Edge i runs from vertex i to vertex i + 1 (mod n).
struct Trapezoid {
    double y_bottom = 0.0;
    double y_top = 0.0;
    double x_bottom_left = 0.0;
    double x_bottom_right = 0.0;
    double x_top_left = 0.0;
    double x_top_right = 0.0;
    int left_edge = 0;
    int right_edge = 0;
    bool bottom_is_point = false;  // the two edges meet at the bottom (exact)
    bool top_is_point = false;
};

std::vector<Trapezoid> trapezoidate(const std::vector<Point2>& polygon, Trace* trace = nullptr);

enum class TrapezoidCorner : std::uint8_t { BottomLeft, BottomRight, TopRight, TopLeft };

struct TrapezoidTriangle {
    int trapezoid = 0;
    std::array<TrapezoidCorner, 3> corners{};  // counter-clockwise
    std::array<Point2, 3> points{};
};

std::vector<TrapezoidTriangle> triangulate(const std::vector<Trapezoid>& trapezoids);

}  // namespace refraster::textbook
