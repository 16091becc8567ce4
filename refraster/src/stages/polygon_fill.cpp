#include "stages/polygon_fill.hpp"

#include <algorithm>
#include <bit>

#include "common/bit_count.hpp"
#include "refraster/assert.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

namespace {

// Floor and ceiling of n / d for d > 0.
std::int64_t floor_div(std::int64_t n, std::int64_t d) {
    const std::int64_t q = n / d;
    return (n % d != 0 && n < 0) ? q - 1 : q;
}
std::int64_t ceil_div(std::int64_t n, std::int64_t d) {
    const std::int64_t q = n / d;
    return (n % d != 0 && n > 0) ? q + 1 : q;
}

// One edge of a contour, oriented upwards (lo.y < hi.y), with the rows it crosses.
struct FillEdge {
    std::size_t contour = 0;
    std::size_t index = 0;
    SnappedPoint lo;
    std::int64_t dx = 0;
    std::int64_t dy = 0;  // > 0
    int direction = 0;    // +1 when the contour runs upwards along it
    std::int64_t first_row = 0;
    std::int64_t last_row = 0;
};

// The rows whose nudged centre line the edge crosses: an end lies above the line at Y + sy*e^2
// iff its y > Y (sy = +1) or y >= Y (sy = -1), and the edge crosses iff exactly one end does.
bool make_edge(std::size_t c, std::size_t k, SnappedPoint a, SnappedPoint b, int sy, int bits,
               FillEdge& e) {
    if (a.y == b.y) return false;  // horizontal: never crosses a nudged centre line
    e.contour = c;
    e.index = k;
    e.direction = b.y > a.y ? 1 : -1;
    const SnappedPoint lo = b.y > a.y ? a : b;
    const SnappedPoint hi = b.y > a.y ? b : a;
    e.lo = lo;
    e.dx = std::int64_t{hi.x} - lo.x;
    e.dy = std::int64_t{hi.y} - lo.y;
    const std::int64_t s = std::int64_t{1} << bits;
    if (sy > 0) {  // lo.y <= Y < hi.y
        e.first_row = ceil_div(lo.y, s);
        e.last_row = ceil_div(hi.y, s) - 1;
    } else {  // lo.y < Y <= hi.y
        e.first_row = floor_div(lo.y, s) + 1;
        e.last_row = floor_div(hi.y, s);
    }
    return e.first_row <= e.last_row;
}

// The crossing's numerator on row `py`: x(Y) = N / dy with N = lo.x*dy + (Y - lo.y)*dx.
std::int64_t numerator_at(const FillEdge& e, std::int64_t py, int bits) {
    return std::int64_t{e.lo.x} * e.dy + ((py << bits) - e.lo.y) * e.dx;
}

// The first pixel whose nudged centre lies right of the crossing N / dy: the centre X = px <<
// bits moved by sx*e is right of it iff X*dy >= N (sx = +1) or X*dy > N (sx = -1).
std::int64_t first_pixel_right(std::int64_t numerator, const FillEdge& e, int sx, int bits) {
    const std::int64_t d = e.dy << bits;
    return sx > 0 ? ceil_div(numerator, d) : floor_div(numerator, d) + 1;
}

bool lit(FillRule rule, std::int64_t winding) {
    if (rule == FillRule::EvenOdd) return (winding & 1) != 0;
    return (winding & 0xff) != 0;  // the stencil's 8 bits wrap
}

template <class Visit>
void for_each_edge(std::span<const Contour> contours, Visit&& visit) {
    for (std::size_t c = 0; c < contours.size(); ++c) {
        const Contour& p = contours[c];
        if (p.size() < 2) continue;
        for (std::size_t k = 0; k < p.size(); ++k) visit(c, k, p[k], p[(k + 1) % p.size()]);
    }
}

}  // namespace

bool has_nudge(TieRule rule) {
    return rule != TieRule::None && rule != TieRule::All;
}

// A centre on a left edge belongs to the polygon when the region right of it does: nudge
// right; on a bottom edge when the region above does: nudge up (rules.hpp names the sides).
std::array<int, 2> nudge_of(TieRule rule) {
    REFRASTER_ASSERT(has_nudge(rule), "a tie rule that gives each edge one side");
    return {owns_left_edges(rule) ? 1 : -1, owns_bottom_edges(rule) ? 1 : -1};
}

FillMask::FillMask(const PixelRect& rect) : rect_(rect) {
    if (rect.empty()) return;
    words_per_row_ = (static_cast<std::size_t>(rect.x1 - rect.x0) + 64) / 64;
    bits_.assign(words_per_row_ * static_cast<std::size_t>(rect.y1 - rect.y0 + 1), 0);
}

std::size_t FillMask::word(int x, int y) const {
    return static_cast<std::size_t>(y - rect_.y0) * words_per_row_ +
           static_cast<std::size_t>(x - rect_.x0) / 64;
}

bool FillMask::test(int x, int y) const {
    if (x < rect_.x0 || x > rect_.x1 || y < rect_.y0 || y > rect_.y1) return false;
    return ((bits_[word(x, y)] >> ((x - rect_.x0) & 63)) & 1u) != 0;
}

void FillMask::set(int x, int y) {
    REFRASTER_ASSERT(x >= rect_.x0 && x <= rect_.x1 && y >= rect_.y0 && y <= rect_.y1,
                     "a pixel of the mask");
    bits_[word(x, y)] |= std::uint64_t{1} << ((x - rect_.x0) & 63);
}

void FillMask::reset(int x, int y) {
    if (x < rect_.x0 || x > rect_.x1 || y < rect_.y0 || y > rect_.y1) return;
    bits_[word(x, y)] &= ~(std::uint64_t{1} << ((x - rect_.x0) & 63));
}

void FillMask::set_span(int y, int x0, int x1) {
    x0 = std::max(x0, rect_.x0);
    x1 = std::min(x1, rect_.x1);
    if (x0 > x1 || y < rect_.y0 || y > rect_.y1) return;
    for (int x = x0; x <= x1;) {
        const int bit = (x - rect_.x0) & 63;
        const int n = std::min(64 - bit, x1 - x + 1);
        const std::uint64_t m = n == 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << n) - 1) << bit;
        bits_[word(x, y)] |= m;
        x += n;
    }
}

std::uint64_t FillMask::count() const {
    std::uint64_t n = 0;
    for (auto w : bits_) n += static_cast<std::uint64_t>(bit_count(w));
    return n;
}

FillMask scanline_fill(std::span<const Contour> contours, FillRule rule, TieRule rule_of_ties,
                       int bits, const PixelRect& region, std::vector<FillScanline>* trace) {
    FillMask mask(region);
    if (region.empty()) return mask;
    const std::array<int, 2> nudge = nudge_of(rule_of_ties);
    const int sx = nudge[0];
    const int sy = nudge[1];

    // The edge table: each edge that crosses a row of the region, by the first such row.
    const auto rows = static_cast<std::size_t>(region.y1 - region.y0 + 1);
    std::vector<std::vector<FillEdge>> table(rows);
    for_each_edge(contours, [&](std::size_t c, std::size_t k, SnappedPoint a, SnappedPoint b) {
        FillEdge e;
        if (!make_edge(c, k, a, b, sy, bits, e)) return;
        if (e.last_row < region.y0 || e.first_row > region.y1) return;
        const std::int64_t start = std::max<std::int64_t>(e.first_row, region.y0);
        table[static_cast<std::size_t>(start - region.y0)].push_back(e);
    });

    // The active edge list: an edge, the crossing's numerator on the current row.
    struct Active {
        FillEdge edge;
        std::int64_t numerator = 0;
    };
    std::vector<Active> active;
    std::vector<FillCrossing> crossings;
    for (int py = region.y0; py <= region.y1; ++py) {
        FillScanline* line = nullptr;
        const auto row = static_cast<std::size_t>(py - region.y0);
        const bool changes = !table[row].empty() || !active.empty();
        if (trace != nullptr && changes) {
            line = &trace->emplace_back();
            line->y = py;
        }
        // Edges that no longer cross leave; new ones enter at their first row.
        std::erase_if(active, [&](const Active& a) {
            if (a.edge.last_row >= py) return false;
            if (line != nullptr) {
                line->edges_removed.push_back(
                    {static_cast<int>(a.edge.contour), static_cast<int>(a.edge.index)});
            }
            return true;
        });
        for (const FillEdge& e : table[row]) {
            active.push_back({e, numerator_at(e, py, bits)});
            if (line != nullptr) {
                line->edges_added.push_back(
                    {static_cast<int>(e.contour), static_cast<int>(e.index)});
            }
        }
        if (active.empty()) continue;

        crossings.clear();
        for (Active& a : active) {
            crossings.push_back({a.edge.contour, a.edge.index,
                                 first_pixel_right(a.numerator, a.edge, sx, bits),
                                 a.edge.direction});
            // The next row's crossing: Y grows by 1 << bits.
            a.numerator += a.edge.dx << bits;
        }
        std::sort(crossings.begin(), crossings.end(),
                  [](const FillCrossing& a, const FillCrossing& b) {
                      return a.first_pixel < b.first_pixel;
                  });
        // Runs between crossings: pixels at or after a crossing's first pixel have it on
        // their left.
        std::int64_t winding = 0;
        for (std::size_t k = 0; k < crossings.size(); ++k) {
            winding += crossings[k].direction;
            const std::int64_t from = crossings[k].first_pixel;
            const std::int64_t to =
                k + 1 < crossings.size() ? crossings[k + 1].first_pixel - 1 : region.x1;
            if (!lit(rule, winding) || from > to) continue;
            const std::int64_t x0 = std::max<std::int64_t>(from, region.x0);
            const std::int64_t x1 = std::min<std::int64_t>(to, region.x1);
            if (x0 > x1) continue;
            mask.set_span(py, static_cast<int>(x0), static_cast<int>(x1));
            if (line != nullptr)
                line->lit_spans.push_back({static_cast<int>(x0), static_cast<int>(x1)});
        }
        if (line != nullptr) line->crossings = crossings;
    }
    return mask;
}

std::int64_t winding_at(std::span<const Contour> contours, TieRule rule_of_ties, int bits, int px,
                        int py) {
    const std::array<int, 2> nudge = nudge_of(rule_of_ties);
    const int sx = nudge[0];
    const int sy = nudge[1];
    std::int64_t winding = 0;
    for_each_edge(contours, [&](std::size_t c, std::size_t k, SnappedPoint a, SnappedPoint b) {
        FillEdge e;
        if (!make_edge(c, k, a, b, sy, bits, e)) return;
        if (py < e.first_row || py > e.last_row) return;
        // The nudged centre (X + sx*e, Y + sy*e^2) is right of the crossing x(Y) = N / dy:
        // X*dy >= N (sx = +1) or X*dy > N (sx = -1).
        const std::int64_t lhs = (std::int64_t{px} << bits) * e.dy;
        const std::int64_t n = numerator_at(e, py, bits);
        if (sx > 0 ? lhs >= n : lhs > n) winding += e.direction;
    });
    return winding;
}

}  // namespace refraster::detail
