#include "refraster/textbook/scanline_fill.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <numeric>
#include <string>

#include "snap.hpp"

namespace refraster::textbook {

namespace {

using detail::floor_div;
using detail::kSnapOne;

std::int64_t ceil_div(std::int64_t a, std::int64_t b) {
    return -floor_div(-a, b);
}

// A non-horizontal edge in the edge table and, once active, its crossing with the current
// scanline, x = q + r / dy in 1/256 pixel with 0 <= r < dy. Magnitudes: snapped values below
// 2^22, dy below 2^23, so q * dy and r * dy (the comparisons) stay below 2^46.
struct ActiveEdge {
    int id = 0;
    int direction = 1;  // +1 when the edge runs upward
    std::int64_t x_low = 0;
    std::int64_t y_low = 0;
    std::int64_t dx = 0;
    std::int64_t dy = 0;  // > 0
    int first_row = 0;
    int last_row = 0;
    std::int64_t q = 0;
    std::int64_t r = 0;
    std::int64_t step_q = 0;  // 256 * dx = step_q * dy + step_r, the crossing's move per row
    std::int64_t step_r = 0;
};

bool crossing_less(const ActiveEdge& a, const ActiveEdge& b) {
    if (a.q != b.q) return a.q < b.q;
    const std::int64_t lhs = a.r * b.dy;
    const std::int64_t rhs = b.r * a.dy;
    if (lhs != rhs) return lhs < rhs;
    return a.id < b.id;
}

// The centre height of row j in 1/256 pixel.
std::int64_t centre_of(std::int64_t j) {
    return j * kSnapOne + kSnapOne / 2;
}

// The first pixel whose centre is at or right of x = q + r/dy (1/256 pixel): the smallest i
// with 256 i + 128 >= q + r/dy.
std::int64_t first_pixel_at_or_right(std::int64_t q, std::int64_t r) {
    return ceil_div(q + (r > 0 ? 1 : 0) - kSnapOne / 2, kSnapOne);
}

// The crossing as the exact fraction it is, in pixels: (q dy + r) / (256 dy) in lowest terms,
// "41/4" or "10" (a double would print 10.192307692307692 for 265/26).
std::string crossing_text(const ActiveEdge& e) {
    const std::int64_t num = e.q * e.dy + e.r;
    const std::int64_t den = kSnapOne * e.dy;
    const std::int64_t g = std::gcd(num < 0 ? -num : num, den);
    const std::int64_t n = num / g, d = den / g;
    return d == 1 ? std::to_string(n) : std::to_string(n) + "/" + std::to_string(d);
}

double crossing_value(const ActiveEdge& e) {
    return (static_cast<double>(e.q) + static_cast<double>(e.r) / static_cast<double>(e.dy)) /
           static_cast<double>(kSnapOne);
}

void place_at_row(ActiveEdge& e, int row) {
    const std::int64_t num = e.x_low * e.dy + (centre_of(row) - e.y_low) * e.dx;
    e.q = floor_div(num, e.dy);
    e.r = num - e.q * e.dy;
}

}  // namespace

FillResult scanline_fill(const std::vector<Contour>& contours, FillRule rule, int width, int height,
                         Trace* trace) {
    FillResult out{{}, Raster(width, height)};
    if (trace != nullptr) {
        trace->algorithm = rule == FillRule::EvenOdd ? "scanline fill, even-odd"
                                                     : "scanline fill, non-zero winding";
        begin_part(trace, "polygon");
        set_pseudo_code(trace,
                        {("build the edge table: each non-horizontal edge in the bucket of the "
                          "first row whose centre it crosses"),
                         "for each row y from the lowest to the highest:",
                         ("    move the row's bucket into the active edge list (AEL); sort it by "
                          "crossing x"),
                         ("    walk the crossings left to right: fill the centres between one and "
                          "the next while inside (even-odd: an odd count; non-zero: a winding "
                          "sum other than 0)"),
                         "    drop the edges that end on this row; advance the rest by 1/m"});
    }
    // The edge table.
    std::vector<ActiveEdge> table;
    int id = 0;
    for (const Contour& contour : contours) {
        for (std::size_t i = 0; i < contour.size(); ++i, ++id) {
            const Point2 a = contour[i];
            const Point2 b = contour[(i + 1) % contour.size()];
            if (trace != nullptr) trace->input.push_back({a.x, a.y, b.x, b.y, "edge"});
            const std::int64_t ay = detail::snap(a.y);
            const std::int64_t by = detail::snap(b.y);
            if (ay == by) continue;
            ActiveEdge e;
            e.id = id;
            e.direction = by > ay ? 1 : -1;
            const bool a_low = ay < by;
            e.x_low = detail::snap(a_low ? a.x : b.x);
            e.y_low = a_low ? ay : by;
            const std::int64_t x_high = detail::snap(a_low ? b.x : a.x);
            const std::int64_t y_high = a_low ? by : ay;
            e.dx = x_high - e.x_low;
            e.dy = y_high - e.y_low;
            // Rows whose centre is in [y_low, y_high).
            e.first_row = static_cast<int>(ceil_div(e.y_low - kSnapOne / 2, kSnapOne));
            e.last_row = static_cast<int>(ceil_div(y_high - kSnapOne / 2, kSnapOne)) - 1;
            if (e.first_row > e.last_row) continue;
            const std::int64_t move = kSnapOne * e.dx;
            e.step_q = floor_div(move, e.dy);
            e.step_r = move - e.step_q * e.dy;
            table.push_back(e);
        }
    }
    if (table.empty() || height <= 0) return out;
    int row_begin = height;
    int row_end = -1;
    for (const ActiveEdge& e : table) {
        row_begin = std::min(row_begin, e.first_row);
        row_end = std::max(row_end, e.last_row);
    }
    row_begin = std::max(row_begin, 0);
    row_end = std::min(row_end, height - 1);
    // Buckets by the first row the scan meets each edge on.
    std::map<int, std::vector<ActiveEdge>> buckets;
    for (const ActiveEdge& e : table) {
        const int start = std::max(e.first_row, row_begin);
        if (start > e.last_row || start > row_end) continue;
        buckets[start].push_back(e);
    }
    if (trace != nullptr) {
        Step& step = add_step(
            *trace, "the edge table: " + std::to_string(table.size()) + " non-horizontal edges");
        step.line = 1;
        for (const auto& [row, edges] : buckets) {
            std::string list;
            for (const ActiveEdge& e : edges) {
                if (!list.empty()) list += ", ";
                list += "e" + std::to_string(e.id) + " rows " + std::to_string(e.first_row) + ".." +
                        std::to_string(e.last_row) + " 1/m " +
                        format_number(static_cast<double>(e.dx) / static_cast<double>(e.dy));
            }
            step.state.push_back({"ET row " + std::to_string(row), "[" + list + "]"});
        }
    }
    std::vector<ActiveEdge> active;
    for (int row = row_begin; row <= row_end; ++row) {
        // Receive this row's bucket, at this row's crossing.
        if (const auto it = buckets.find(row); it != buckets.end()) {
            for (ActiveEdge e : it->second) {
                place_at_row(e, row);
                active.push_back(e);
            }
        }
        // Insertion sort: the crossings move little from row to row.
        for (std::size_t i = 1; i < active.size(); ++i) {
            for (std::size_t k = i; k > 0 && crossing_less(active[k], active[k - 1]); --k) {
                std::swap(active[k], active[k - 1]);
            }
        }
        // Walk the crossings: the interval after crossing k is inside when the count is odd
        // (even-odd) or the winding sum is not zero.
        std::vector<Span> row_spans;
        std::vector<std::pair<double, double>> inside_intervals;  // for the trace
        int count = 0;
        int winding = 0;
        for (std::size_t k = 0; k + 1 < active.size(); ++k) {
            ++count;
            winding += active[k].direction;
            const bool inside = rule == FillRule::EvenOdd ? (count % 2) == 1 : winding != 0;
            if (!inside) continue;
            if (trace != nullptr) {
                inside_intervals.push_back(
                    {crossing_value(active[k]), crossing_value(active[k + 1])});
            }
            std::int64_t begin = first_pixel_at_or_right(active[k].q, active[k].r);
            std::int64_t end = first_pixel_at_or_right(active[k + 1].q, active[k + 1].r);
            begin = std::max<std::int64_t>(begin, 0);
            end = std::min<std::int64_t>(end, width);
            if (begin >= end) continue;
            const int b = static_cast<int>(begin);
            const int e = static_cast<int>(end);
            if (!row_spans.empty() && row_spans.back().x_end == b) {
                row_spans.back().x_end = e;
            } else {
                row_spans.push_back({row, b, e});
            }
        }
        for (const Span& s : row_spans) {
            for (int x = s.x_begin; x < s.x_end; ++x) out.raster.set(x, row, 1.0);
            out.spans.push_back(s);
        }
        if (trace != nullptr) {
            std::string ael;
            for (const ActiveEdge& e : active) {
                if (!ael.empty()) ael += ", ";
                ael += "e" + std::to_string(e.id) + " x=" + crossing_text(e) +
                       (e.direction > 0 ? " up" : " down");
            }
            std::string spans;
            for (const Span& s : row_spans) {
                if (!spans.empty()) spans += " ";
                spans += "[" + std::to_string(s.x_begin) + ", " + std::to_string(s.x_end) + ")";
            }
            const double yc = row + 0.5;
            Step& step = add_step(*trace, "y = " + std::to_string(row) + " (centre " +
                                              format_number(yc) + "): AEL [" + ael + "], spans " +
                                              (spans.empty() ? "none" : spans));
            step.line = 4;
            step.state.push_back({"AEL", "[" + ael + "]"});
            step.state.push_back({"spans", spans});
            step.overlay.push_back({0.0, yc, static_cast<double>(width), yc, "scanline"});
            for (const auto& [x0, x1] : inside_intervals) {
                step.overlay.push_back({x0, yc, x1, yc, "span"});
            }
            for (const Span& s : row_spans) {
                for (int x = s.x_begin; x < s.x_end; ++x) step.pixels.push_back({x, row, 1.0});
            }
        }
        // Drop the edges that end here; advance the rest by 1/m, exactly.
        std::erase_if(active, [row](const ActiveEdge& e) { return e.last_row <= row; });
        for (ActiveEdge& e : active) {
            e.q += e.step_q;
            e.r += e.step_r;
            if (e.r >= e.dy) {
                e.r -= e.dy;
                ++e.q;
            }
        }
    }
    return out;
}

}  // namespace refraster::textbook
