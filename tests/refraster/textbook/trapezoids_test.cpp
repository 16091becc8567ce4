// The trapezoidal decomposition (trapezoids.hpp) against exact statements, in rational
// arithmetic (exact_support.hpp), with every corner recomputed here from the edge indices and
// heights the decomposition reports:
// - the trapezoids tile the polygon: positive height, left side at or left of the right side,
//   areas summing exactly to the shoelace area, each inside the polygon, interiors pairwise
//   disjoint;
// - they are Seidel's trapezoids: a polygon vertex lies on the closed bottom side and on the
//   closed top side of each (every cut is a chord through a vertex), and no trapezoid sits on
//   another bounded by the same two edges (no cut without a vertex);
// - triangulate() tiles the polygon the same way with triangles.
// For random simple polygons (2-opt untangled, both orientations) and hand-built ones.
#include "refraster/textbook/trapezoids.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "exact_support.hpp"

namespace {

using refraster::textbook::TrapezoidCorner;
using textbook_test::IPoint;
using textbook_test::Rational;
using textbook_test::RPoint;

Rational exact_height(double y) {
    const auto v = static_cast<long long>(std::llround(y));
    EXPECT_EQ(static_cast<double>(v), y);  // heights are vertex heights: integers here
    return Rational(v);
}

// x of edge i at height y.
Rational x_on_edge(const std::vector<RPoint>& poly, int edge, const Rational& y) {
    const RPoint& a = poly[static_cast<std::size_t>(edge)];
    const RPoint& b = poly[(static_cast<std::size_t>(edge) + 1) % poly.size()];
    EXPECT_FALSE(a.y == b.y);
    EXPECT_TRUE(min(a.y, b.y) <= y && y <= max(a.y, b.y));
    return a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y);
}

// The distinct corners, counter-clockwise.
std::vector<RPoint> dedupe(const std::vector<RPoint>& pts) {
    std::vector<RPoint> out;
    for (const RPoint& p : pts) {
        if (!out.empty() && out.back().x == p.x && out.back().y == p.y) continue;
        out.push_back(p);
    }
    while (out.size() > 1 && out.front().x == out.back().x && out.front().y == out.back().y) {
        out.pop_back();
    }
    return out;
}

void expect_pieces_tile(const std::vector<std::vector<RPoint>>& pieces,
                        const std::vector<RPoint>& rpoly) {
    Rational sum;
    for (const auto& piece : pieces) {
        ASSERT_GE(piece.size(), 3u);
        const Rational a = textbook_test::twice_area(piece);
        ASSERT_GT(a.sign(), 0);
        sum = sum + a;
        ASSERT_TRUE(textbook_test::convex_piece_inside(piece, rpoly));
    }
    ASSERT_EQ(sum, abs(textbook_test::twice_area(rpoly)));
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        for (std::size_t j = i + 1; j < pieces.size(); ++j) {
            ASSERT_TRUE(textbook_test::convex_interiors_disjoint(pieces[i], pieces[j]))
                << "pieces " << i << " and " << j;
        }
    }
}

bool vertex_on_chord(const std::vector<RPoint>& poly, const Rational& y, const Rational& x0,
                     const Rational& x1) {
    for (const RPoint& v : poly) {
        if (v.y == y && x0 <= v.x && v.x <= x1) return true;
    }
    return false;
}

void expect_decomposition(const std::vector<IPoint>& poly) {
    std::vector<refraster::textbook::Point2> input;
    for (const IPoint& p : poly) {
        input.push_back({static_cast<double>(p.x), static_cast<double>(p.y)});
    }
    const auto traps = refraster::textbook::trapezoidate(input);
    const std::vector<RPoint> rpoly = textbook_test::to_rational(poly);
    std::vector<std::vector<RPoint>> pieces;
    // The exact corners of each trapezoid, for the triangles below.
    std::vector<std::array<RPoint, 4>> corners;
    for (const auto& t : traps) {
        const Rational yb = exact_height(t.y_bottom);
        const Rational yt = exact_height(t.y_top);
        ASSERT_LT(yb, yt);
        const RPoint bl{x_on_edge(rpoly, t.left_edge, yb), yb};
        const RPoint br{x_on_edge(rpoly, t.right_edge, yb), yb};
        const RPoint tr{x_on_edge(rpoly, t.right_edge, yt), yt};
        const RPoint tl{x_on_edge(rpoly, t.left_edge, yt), yt};
        ASSERT_LE(bl.x, br.x);
        ASSERT_LE(tl.x, tr.x);
        EXPECT_EQ(t.bottom_is_point, bl.x == br.x);
        EXPECT_EQ(t.top_is_point, tl.x == tr.x);
        EXPECT_EQ(t.x_bottom_left, bl.x.to_double());
        EXPECT_EQ(t.x_top_right, tr.x.to_double());
        // Seidel's property: every cut goes through a vertex.
        EXPECT_TRUE(vertex_on_chord(rpoly, yb, bl.x, br.x));
        EXPECT_TRUE(vertex_on_chord(rpoly, yt, tl.x, tr.x));
        pieces.push_back(dedupe({bl, br, tr, tl}));
        corners.push_back({bl, br, tr, tl});
    }
    expect_pieces_tile(pieces, rpoly);
    for (std::size_t i = 0; i < traps.size(); ++i) {
        for (std::size_t j = 0; j < traps.size(); ++j) {
            const bool stacked = traps[i].left_edge == traps[j].left_edge &&
                                 traps[i].right_edge == traps[j].right_edge &&
                                 traps[i].y_top == traps[j].y_bottom;
            EXPECT_FALSE(stacked) << "trapezoids " << i << " and " << j << " share a needless cut";
        }
    }
    // The triangulation.
    const auto triangles = refraster::textbook::triangulate(traps);
    std::vector<std::vector<RPoint>> tri_pieces;
    for (const auto& tri : triangles) {
        std::vector<RPoint> piece;
        for (const TrapezoidCorner c : tri.corners) {
            piece.push_back(
                corners[static_cast<std::size_t>(tri.trapezoid)][static_cast<std::size_t>(c)]);
        }
        tri_pieces.push_back(piece);
    }
    expect_pieces_tile(tri_pieces, rpoly);
}

TEST(TextbookTrapezoids, RandomSimplePolygonsDecomposeIntoSeidelsTrapezoidsExactly) {
    std::mt19937 rng(1991);
    for (int n = 0; n < 400; ++n) {
        const int vertices = 4 + n % 13;
        const auto poly = textbook_test::random_simple_polygon(rng, vertices, 12);
        SCOPED_TRACE("polygon " + std::to_string(n));
        expect_decomposition(poly);
        expect_decomposition(textbook_test::reversed(poly));
        if (HasFatalFailure()) return;
    }
}

TEST(TextbookTrapezoids, CollinearVerticesHorizontalEdgesAndCombsDecomposeExactly) {
    for (const auto& poly : textbook_test::hand_polygons()) {
        expect_decomposition(poly);
        expect_decomposition(textbook_test::reversed(poly));
        if (HasFatalFailure()) return;
    }
}

TEST(TextbookTrapezoids, AConvexPolygonNeedsOneTrapezoidPerVertexHeightBand) {
    // A hexagon with vertices at four heights: three trapezoids, none merged (each band's
    // left or right edge changes at every height).
    const std::vector<refraster::textbook::Point2> hexagon = {{2, 0}, {4, 0}, {6, 2},
                                                              {5, 5}, {1, 5}, {0, 3}};
    refraster::textbook::Trace trace;
    const auto traps = refraster::textbook::trapezoidate(hexagon, &trace);
    ASSERT_EQ(traps.size(), 3u);
    EXPECT_EQ(traps[0].y_bottom, 0.0);
    EXPECT_EQ(traps[0].y_top, 2.0);
    EXPECT_EQ(trace.steps.size(), 3u + 1u);  // one per slab, and the result
}

}  // namespace
