// Ear clipping (ear_clipping.hpp) against the exact statement that its triangles tile the
// polygon, in rational arithmetic (exact_support.hpp): n - 2 triangles, each of non-zero area
// with the polygon's orientation, their areas summing exactly to the shoelace area, each inside
// the polygon (no boundary edge meets its open interior, and its centroid is inside), no two
// with overlapping interiors. For random simple polygons of 4 to 16 vertices (2-opt untangled,
// both orientations) and for hand-built ones with collinear vertices and deep concavities.
#include "refraster/textbook/ear_clipping.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "exact_support.hpp"

namespace {

using textbook_test::IPoint;
using textbook_test::Rational;
using textbook_test::RPoint;

void expect_tiling(const std::vector<IPoint>& poly) {
    std::vector<refraster::textbook::Point2> input;
    for (const IPoint& p : poly) {
        input.push_back({static_cast<double>(p.x), static_cast<double>(p.y)});
    }
    const auto result = refraster::textbook::ear_clip(input);
    ASSERT_TRUE(result.complete);
    ASSERT_EQ(result.triangles.size(), poly.size() - 2);
    const std::vector<RPoint> rpoly = textbook_test::to_rational(poly);
    const Rational area = textbook_test::twice_area(rpoly);
    Rational sum;
    std::vector<std::vector<RPoint>> pieces;
    for (const auto& t : result.triangles) {
        ASSERT_EQ(std::set<int>(t.begin(), t.end()).size(), 3u);
        std::vector<RPoint> tri;
        for (const int i : t) tri.push_back(rpoly[static_cast<std::size_t>(i)]);
        const Rational a = textbook_test::twice_area(tri);
        ASSERT_NE(a.sign(), 0);
        ASSERT_EQ(a.sign(), area.sign());  // the polygon's orientation is kept
        sum = sum + a;
        if (a.sign() < 0) std::swap(tri[1], tri[2]);
        ASSERT_TRUE(textbook_test::convex_piece_inside(tri, rpoly));
        pieces.push_back(tri);
    }
    ASSERT_EQ(sum, area);
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        for (std::size_t j = i + 1; j < pieces.size(); ++j) {
            ASSERT_TRUE(textbook_test::convex_interiors_disjoint(pieces[i], pieces[j]))
                << "triangles " << i << " and " << j;
        }
    }
}

TEST(TextbookEarClipping, RandomSimplePolygonsAreTiledExactly) {
    std::mt19937 rng(1975);
    for (int n = 0; n < 500; ++n) {
        const int vertices = 4 + n % 13;
        const auto poly = textbook_test::random_simple_polygon(rng, vertices, 12);
        SCOPED_TRACE("polygon " + std::to_string(n));
        expect_tiling(poly);
        expect_tiling(textbook_test::reversed(poly));
        if (HasFatalFailure()) return;
    }
}

TEST(TextbookEarClipping, CollinearVerticesAndCombsAreTiledExactly) {
    for (const auto& poly : textbook_test::hand_polygons()) {
        expect_tiling(poly);
        expect_tiling(textbook_test::reversed(poly));
        if (HasFatalFailure()) return;
    }
}

TEST(TextbookEarClipping, AFlatVertexIsSkippedAsAnEarTip) {
    // v0 lies on the segment v4 v1: the search starts there, rejects it and cuts v1.
    const std::vector<refraster::textbook::Point2> square = {
        {1, 0}, {2, 0}, {2, 2}, {0, 2}, {0, 0}};
    refraster::textbook::Trace trace;
    const auto result = refraster::textbook::ear_clip(square, &trace);
    ASSERT_TRUE(result.complete);
    EXPECT_EQ(result.triangles[0], (std::array<int, 3>{0, 1, 2}));
    EXPECT_EQ(trace.steps[0].state[1].second, "v0: collinear with its neighbours");
}

TEST(TextbookEarClipping, TraceHasOneStepPerEar) {
    refraster::textbook::Trace trace;
    const std::vector<refraster::textbook::Point2> poly = {{0, 0}, {4, 0}, {4, 4}, {2, 1}, {0, 4}};
    const auto result = refraster::textbook::ear_clip(poly, &trace);
    ASSERT_TRUE(result.complete);
    ASSERT_EQ(trace.steps.size(), result.triangles.size());
    EXPECT_EQ(trace.steps[0].overlay.size(), 3u);
    EXPECT_EQ(trace.steps[0].overlay[2].role, "diagonal");
}

// A comb of `teeth` teeth: the bottom edge, then the teeth from right to left (2 * teeth + 2
// vertices, counter-clockwise).
std::vector<refraster::textbook::Point2> comb(int teeth) {
    std::vector<refraster::textbook::Point2> c = {{0, 0}, {2.0 * teeth, 0}};
    for (int i = teeth; i > 0; --i) {
        c.push_back({2.0 * i, 10});
        c.push_back({2.0 * i - 1, 1});
    }
    return c;
}

TEST(TextbookEarClipping, AStepCostsTheSameOnAnyPolygon) {
    // Each step names the remaining vertices and the vertices rejected before the ear: the first
    // few of each and the count of the rest, so the trace grows linearly with the steps, not
    // with the steps times the vertices (quadratically).
    for (const int teeth : {10, 1000}) {
        refraster::textbook::Trace trace;
        const auto poly = comb(teeth);
        const auto result = refraster::textbook::ear_clip(poly, &trace);
        ASSERT_TRUE(result.complete);
        ASSERT_EQ(result.triangles.size(), poly.size() - 2);
        ASSERT_EQ(trace.steps.size(), result.triangles.size());
        std::size_t longest = 0;
        for (const auto& step : trace.steps) {
            std::size_t bytes = step.title.size();
            for (const auto& [key, value] : step.state) bytes += key.size() + value.size();
            longest = std::max(longest, bytes);
        }
        EXPECT_LE(longest, 2000u) << teeth << " teeth";
    }
    refraster::textbook::Trace trace;
    refraster::textbook::ear_clip(comb(1000), &trace);
    EXPECT_NE(trace.steps[0].state[0].second.find("... 1978 more]"), std::string::npos)
        << trace.steps[0].state[0].second;
}

TEST(TextbookEarClipping, ABoundedTraceKeepsTheFirstStepsAndCountsTheRest) {
    refraster::textbook::Trace trace;
    trace.max_steps = 10;
    const auto poly = comb(50);
    const auto result = refraster::textbook::ear_clip(poly, &trace);
    ASSERT_TRUE(result.complete);  // the bound changes the record, not the result
    EXPECT_EQ(result.triangles.size(), poly.size() - 2);
    EXPECT_EQ(trace.steps.size(), 10u);
    EXPECT_EQ(trace.omitted, poly.size() - 2 - 10);
}

}  // namespace
