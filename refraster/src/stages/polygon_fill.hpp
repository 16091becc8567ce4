// polygon_fill.hpp: which pixels a fill rule puts inside a polygon, by a scanline filler.
//
// Implements the even-odd and non-zero rules (OpenGL has them only through the stencil
// buffer; docs/precision.md, "Polygons and fill rules") with an edge table and an active edge
// list over snapped vertices, in exact integer arithmetic:
//  - a pixel is tested at its centre moved by an infinitesimal nudge (sx * e, sy * e^2), the
//    tie rule's direction (LeftBottom: (+e, +e^2), the region just right, or for a horizontal
//    edge just above, of a centre on an edge decides it); a centre on the polygon's own edge
//    or vertex is thereby decided without any special case, and no nudged point lies on an
//    edge. That is what llvmpipe's stencil fills measure (docs/precision.md, "Polygons and fill
//    rules"): the parity, or the winding number, of the fan triangles covering a pixel under
//    llvmpipe's own tie rule equals the rule's test at the nudged centre;
//  - an edge crosses scanline py (centre Y = py << bits) when exactly one end lies above the
//    nudged centre line; where it crosses is kept as an exact rational numerator that steps by
//    dx << bits a scanline (the DDA of a textbook filler, without its rounding), and the
//    first pixel right of the crossing is a floor or ceiling division of it;
//  - along a scanline the crossings sorted by that pixel give the winding number of every run
//    between them: even-odd lights an odd count of crossings, non-zero a winding number that
//    is not zero modulo 256 (the stencil buffer's INCR_WRAP and DECR_WRAP on 8 bits).
// Any number of closed contours, in any orientation, self-intersecting or not.
//
// Deliberately does not: snap, clip or shade (the caller gives snapped contours and shades
// the mask it gets); the tie rules None and All, which are not a nudge of the centre and
// break GL's rule that a pixel has one owner.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/pixel_rect.hpp"
#include "refraster/draw.hpp"
#include "refraster/profile.hpp"

namespace refraster::detail {

// Bit budget. Snapped coordinates stay below 2^24 in magnitude (setup.hpp, kSnappedBits), so
// an edge's dx and dy are below 2^25, and the crossing numerator
//   N = x0 * dy + (Y - y0) * dx,   |N| < 2^24 * 2^25 + 2^25 * 2^25 < 2^51,
// and the divisor dy << bits < 2^33: int64 holds both with room for the per-scanline step.
inline constexpr int kFillCoordinateBits = 24;
inline constexpr int kFillNumeratorBits = kFillCoordinateBits + 25 + 2;  // 51
static_assert(kFillNumeratorBits < 63, "crossing numerators must fit int64");

struct SnappedPoint {
    std::int32_t x = 0;  // subpixels; pixel px's centre is px << bits
    std::int32_t y = 0;
    friend bool operator==(const SnappedPoint&, const SnappedPoint&) = default;
};
using Contour = std::vector<SnappedPoint>;  // closed: the last point joins the first

// The direction of the nudge for a tie rule: +1 or -1 in x and in y. Only the four rules that
// give each edge one side (LeftBottom, LeftTop, RightBottom, RightTop) have one.
bool has_nudge(TieRule rule);
std::array<int, 2> nudge_of(TieRule rule);

// One bit a pixel over `rect` (rows of 64-bit words), set for the pixels inside.
class FillMask {
  public:
    FillMask() = default;
    explicit FillMask(const PixelRect& rect);
    const PixelRect& rect() const { return rect_; }
    bool test(int x, int y) const;
    void set(int x, int y);
    void reset(int x, int y);
    // Sets pixels [x0, x1] of row y (inclusive, clipped to the rect).
    void set_span(int y, int x0, int x1);
    std::uint64_t count() const;

  private:
    std::size_t word(int x, int y) const;
    PixelRect rect_;
    std::size_t words_per_row_ = 0;
    std::vector<std::uint64_t> bits_;
};

// What the filler did on one scanline, for explain and teaching: each active edge's crossing
// (the first pixel whose nudged centre lies right of it, and +1 for an edge going up, -1 going
// down) and the runs it lit.
struct FillCrossing {
    std::size_t contour = 0;
    std::size_t edge = 0;  // from point `edge` to the next one
    std::int64_t first_pixel = 0;
    int direction = 0;
};
struct FillScanline {
    int y = 0;
    std::vector<FillCrossing> crossings;            // sorted by first_pixel
    std::vector<std::array<int, 2>> lit_spans;      // [x0, x1] inclusive, within the rect
    std::vector<std::array<int, 2>> edges_added;    // (contour, edge) entering the list here
    std::vector<std::array<int, 2>> edges_removed;  // (contour, edge) leaving it here
};

// The pixels of `region` (inclusive, non-empty or nothing is set) inside the contours by
// `rule`, tested at centres nudged by `rule_of_ties`'s direction (has_nudge must hold).
// `bits` is the subpixel precision of the coordinates. With `trace`, one FillScanline is
// appended for each row of the region that any edge crosses.
FillMask scanline_fill(std::span<const Contour> contours, FillRule rule, TieRule rule_of_ties,
                       int bits, const PixelRect& region,
                       std::vector<FillScanline>* trace = nullptr);

// The winding number at the nudged centre of pixel (px, py), by direct summation over every
// edge (no edge table): the test the filler's tests check it against.
std::int64_t winding_at(std::span<const Contour> contours, TieRule rule_of_ties, int bits, int px,
                        int py);

}  // namespace refraster::detail
