#include "refraster/textbook/trapezoids.hpp"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

#include "snap.hpp"

namespace refraster::textbook {

namespace {

using detail::Int128;
using detail::SnappedPoint;

struct SweepEdge {
    int index = 0;
    SnappedPoint low;
    SnappedPoint high;
};

// x of the edge at height twice_y / 2, as num / den with den > 0. Below 2^47 and 2^24.
std::pair<std::int64_t, std::int64_t> x_at_twice(const SweepEdge& e, std::int64_t twice_y) {
    const std::int64_t dx = e.high.x - e.low.x;
    const std::int64_t dy = e.high.y - e.low.y;
    return {2 * e.low.x * dy + (twice_y - 2 * e.low.y) * dx, 2 * dy};
}

// Compares two edges' x at the same height: -1, 0 or 1. The cross products stay below 2^72.
int compare_x(const SweepEdge& a, const SweepEdge& b, std::int64_t twice_y) {
    const auto [na, da] = x_at_twice(a, twice_y);
    const auto [nb, db] = x_at_twice(b, twice_y);
    const Int128 lhs = static_cast<Int128>(na) * db;
    const Int128 rhs = static_cast<Int128>(nb) * da;
    return lhs < rhs ? -1 : (lhs > rhs ? 1 : 0);
}

double x_value(const SweepEdge& e, std::int64_t y) {
    const auto [num, den] = x_at_twice(e, 2 * y);
    return static_cast<double>(num) / static_cast<double>(den) /
           static_cast<double>(detail::kSnapOne);
}

}  // namespace

std::vector<Trapezoid> trapezoidate(const std::vector<Point2>& polygon, Trace* trace) {
    std::vector<Trapezoid> out;
    const std::size_t n = polygon.size();
    if (trace != nullptr) {
        trace->algorithm = "trapezoidal decomposition";
        set_pseudo_code(trace, {("sort the vertices' heights: each two neighbouring heights bound "
                                 "a slab"),
                                "for each slab from the bottom:",
                                "    list the edges that span it, sorted by x at its middle",
                                ("    pair them left to right: each pair bounds a trapezoid "
                                 "(continued from the slab below when the same pair did)"),
                                "split each trapezoid into triangles"});
        add_outline(trace->input, polygon);
        begin_part(trace, "polygon");
    }
    if (n < 3) return out;
    std::vector<SnappedPoint> p(n);
    std::vector<std::int64_t> heights;
    for (std::size_t i = 0; i < n; ++i) {
        p[i] = {detail::snap(polygon[i].x), detail::snap(polygon[i].y)};
        heights.push_back(p[i].y);
    }
    std::sort(heights.begin(), heights.end());
    heights.erase(std::unique(heights.begin(), heights.end()), heights.end());
    std::vector<SweepEdge> edges;
    for (std::size_t i = 0; i < n; ++i) {
        const SnappedPoint a = p[i];
        const SnappedPoint b = p[(i + 1) % n];
        if (a.y == b.y) continue;
        edges.push_back({static_cast<int>(i), a.y < b.y ? a : b, a.y < b.y ? b : a});
    }
    std::vector<SweepEdge> edge_of(n);
    for (const SweepEdge& e : edges) edge_of[static_cast<std::size_t>(e.index)] = e;
    // The trapezoids open at the top of the previous slab, by (left edge, right edge).
    std::map<std::pair<int, int>, std::size_t> open;
    std::vector<std::int64_t> top_of;  // exact top height of each output trapezoid
    std::vector<std::int64_t> bottom_of;
    for (std::size_t k = 0; k + 1 < heights.size(); ++k) {
        const std::int64_t y0 = heights[k];
        const std::int64_t y1 = heights[k + 1];
        std::vector<SweepEdge> spanning;
        for (const SweepEdge& e : edges) {
            if (e.low.y <= y0 && e.high.y >= y1) spanning.push_back(e);
        }
        const std::int64_t twice_mid = y0 + y1;
        std::sort(spanning.begin(), spanning.end(), [&](const SweepEdge& a, const SweepEdge& b) {
            const int c = compare_x(a, b, twice_mid);
            return c != 0 ? c < 0 : a.index < b.index;
        });
        std::map<std::pair<int, int>, std::size_t> next_open;
        std::string pairs;
        for (std::size_t j = 0; j + 1 < spanning.size(); j += 2) {
            const std::pair<int, int> key{spanning[j].index, spanning[j + 1].index};
            const auto it = open.find(key);
            bool merged = false;
            if (it != open.end()) {
                top_of[it->second] = y1;
                next_open[key] = it->second;
                merged = true;
            } else {
                Trapezoid t;
                t.left_edge = key.first;
                t.right_edge = key.second;
                out.push_back(t);
                bottom_of.push_back(y0);
                top_of.push_back(y1);
                next_open[key] = out.size() - 1;
            }
            if (trace != nullptr) {
                if (!pairs.empty()) pairs += ", ";
                pairs += "(e" + std::to_string(key.first) + ", e" + std::to_string(key.second) +
                         (merged ? ") continues" : ") opens");
            }
        }
        if (trace != nullptr) {
            std::string crossing;
            for (const SweepEdge& e : spanning) {
                if (!crossing.empty()) crossing += ", ";
                crossing += "e" + std::to_string(e.index);
            }
            const double yb = detail::unsnap(y0);
            const double yt = detail::unsnap(y1);
            Step& s =
                add_step(*trace, "slab y in [" + format_number(yb) + ", " + format_number(yt) +
                                     "]: " + (pairs.empty() ? "outside" : pairs));
            s.line = 4;
            s.state.push_back({"edges by x", "[" + crossing + "]"});
            for (std::size_t j = 0; j + 1 < spanning.size(); j += 2) {
                const SweepEdge& l = spanning[j];
                const SweepEdge& r = spanning[j + 1];
                s.overlay.push_back({x_value(l, y0), yb, x_value(r, y0), yb, "trapezoid"});
                s.overlay.push_back({x_value(r, y0), yb, x_value(r, y1), yt, "trapezoid"});
                s.overlay.push_back({x_value(r, y1), yt, x_value(l, y1), yt, "trapezoid"});
                s.overlay.push_back({x_value(l, y1), yt, x_value(l, y0), yb, "trapezoid"});
            }
        }
        open = std::move(next_open);
    }
    for (std::size_t i = 0; i < out.size(); ++i) {
        Trapezoid& t = out[i];
        const SweepEdge& l = edge_of[static_cast<std::size_t>(t.left_edge)];
        const SweepEdge& r = edge_of[static_cast<std::size_t>(t.right_edge)];
        t.y_bottom = detail::unsnap(bottom_of[i]);
        t.y_top = detail::unsnap(top_of[i]);
        t.x_bottom_left = x_value(l, bottom_of[i]);
        t.x_bottom_right = x_value(r, bottom_of[i]);
        t.x_top_left = x_value(l, top_of[i]);
        t.x_top_right = x_value(r, top_of[i]);
        t.bottom_is_point = compare_x(l, r, 2 * bottom_of[i]) == 0;
        t.top_is_point = compare_x(l, r, 2 * top_of[i]) == 0;
    }
    if (trace != nullptr) {
        Step& s = add_step(*trace, std::to_string(out.size()) + " trapezoids");
        s.line = 5;
        for (std::size_t i = 0; i < out.size(); ++i) {
            const Trapezoid& t = out[i];
            s.state.push_back({"T" + std::to_string(i), "e" + std::to_string(t.left_edge) + " | e" +
                                                            std::to_string(t.right_edge) +
                                                            ", y in [" + format_number(t.y_bottom) +
                                                            ", " + format_number(t.y_top) + "]"});
            s.overlay.push_back(
                {t.x_bottom_left, t.y_bottom, t.x_bottom_right, t.y_bottom, "trapezoid"});
            s.overlay.push_back(
                {t.x_bottom_right, t.y_bottom, t.x_top_right, t.y_top, "trapezoid"});
            s.overlay.push_back({t.x_top_right, t.y_top, t.x_top_left, t.y_top, "trapezoid"});
            s.overlay.push_back({t.x_top_left, t.y_top, t.x_bottom_left, t.y_bottom, "trapezoid"});
        }
    }
    return out;
}

std::vector<TrapezoidTriangle> triangulate(const std::vector<Trapezoid>& trapezoids) {
    std::vector<TrapezoidTriangle> out;
    for (std::size_t i = 0; i < trapezoids.size(); ++i) {
        const Trapezoid& t = trapezoids[i];
        const Point2 bl{t.x_bottom_left, t.y_bottom};
        const Point2 br{t.x_bottom_right, t.y_bottom};
        const Point2 tr{t.x_top_right, t.y_top};
        const Point2 tl{t.x_top_left, t.y_top};
        const int index = static_cast<int>(i);
        using C = TrapezoidCorner;
        if (!t.bottom_is_point) {
            out.push_back({index, {C::BottomLeft, C::BottomRight, C::TopRight}, {bl, br, tr}});
        }
        if (!t.top_is_point) {
            out.push_back({index, {C::BottomLeft, C::TopRight, C::TopLeft}, {bl, tr, tl}});
        }
    }
    return out;
}

}  // namespace refraster::textbook
