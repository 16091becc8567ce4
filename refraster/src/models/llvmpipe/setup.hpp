// setup.hpp: a window-space triangle to three integer edge functions, as llvmpipe sets it up.
//
// Implements (gallium/drivers/llvmpipe/lp_setup_tri.c):
//  - snapping: X = round((x - pixel_center_offset) * 2^bits), the subtraction and the
//    multiplication in float, then the profile's rounding (calc_fixed_position, SSE path:
//    cvtps2dq rounds to nearest even);
//  - orientation: area = (X0-X1)*(Y2-Y0) - (X2-X0)*(Y0-Y1) in int64; zero draws nothing;
//    a negative area swaps v0 and v1 (v1 and v2 with the first-vertex provoking convention)
//    and the triangle faces the other way (triangle_both / triangle_cw / triangle_ccw);
//  - culling by that fixed-point area;
//  - edge functions E(px, py) = c - a*(px << bits) + b*(py << bits), a = Y_i - Y_{i+1},
//    b = X_i - X_{i+1}, c = a*X_i - b*Y_i plus 1 when the tie rule owns the edge, so that a
//    pixel is covered iff E > 0 for all three edges (do_triangle_ccw, generic branch);
//  - the bounding box of do_triangle_ccw, intersected with the draw region.
//
// Window coordinates are those of an FBO: gallium y equals GL y (docs/precision.md,
// "Coordinate spaces"), so llvmpipe's bottom_edge_rule is 0 and the tie rule maps to GL terms
// directly.
//
// Multisampling (SetupParams::multisample) changes only the snapping, which then has no
// half-pixel offset; the edges and their tie biases are the same, tested at the samples.
//
// Deliberately does not: attribute planes.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "common/pixel_rect.hpp"
#include "models/llvmpipe/llvmpipe_walk.hpp"
#include "refraster/draw.hpp"
#include "refraster/fixed.hpp"
#include "refraster/profile.hpp"
#include "stages/edge_rules.hpp"

namespace refraster::detail {

// Everything setup decides about a triangle but llvmpipe's own walk.
struct TriangleSetupResult {
    int bits = 8;
    std::array<std::int32_t, 3> x{};  // snapped positions after the orientation swap
    std::array<std::int32_t, 3> y{};
    std::array<int, 3> order{0, 1, 2};  // input vertex at each position after the swap
    std::int64_t area = 0;              // before the swap (negative: swapped)
    bool front_facing = true;
    std::array<EdgeFunction, 3> edges;
    PixelRect bbox;  // do_triangle_ccw's box, already intersected with the draw region
    // Set when llvmpipe's integer widths decide the pixels (setup.cpp): a position outside
    // the budget above, an edge whose shifted deltas leave int32, or a one-tile walk in
    // which an edge value leaves int32. `walk` then holds llvmpipe's planes and
    // llvmpipe_walk.hpp decides coverage; `edges` stay zero.
    bool llvmpipe_walk = false;
    std::uint8_t scissor_leak = 0;  // multisample_scissor_leak
};

struct TriangleSetup : TriangleSetupResult {
    lp::Triangle walk;

    // Every field back to its initial value but `walk`, which attach_llvmpipe_walk writes whole
    // when it sets llvmpipe_walk: a TriangleSetup kept for the next triangle costs no clearing
    // of the walk's planes.
    // (Copied from a constant: a block copy, where assigning a fresh value clears the block
    // with a string instruction whose start-up cost a tiny triangle notices.)
    void clear_except_walk() { static_cast<TriangleSetupResult&>(*this) = kInitial; }

  private:
    static constexpr TriangleSetupResult kInitial{};
};

enum class SetupOutcome : std::uint8_t { Ok, ZeroArea, Culled, Outside, OutOfRange };

// Gives `t` (oriented positions set) llvmpipe's planes and walk (llvmpipe_walk.hpp), which
// setup_triangle does itself where llvmpipe's integer widths matter. In range the walk
// covers exactly the pixels the edge functions cover (a property the tests check).
void attach_llvmpipe_walk(const SetupParams& p, TriangleSetup& t);

SetupOutcome setup_triangle(const std::array<std::array<float, 2>, 3>& window, const SetupParams& p,
                            TriangleSetup& out);

// Multisampling's scissor leak. llvmpipe's scissor planes get +127 under multisampling
// (lp_setup.c, lp_setup_add_scissor_planes), which moves the left and bottom planes half a
// pixel outwards: the column left of the draw region keeps the samples whose x offset is
// above half a pixel (samples 1 and 3) and the row below it those whose y offset is (2 and 3),
// wherever the primitive covers them. A plane exists only when the primitive's binned box
// `binned` (llvmpipe's, x0 and y0 clamped to 0) crosses that side of the region, and its leak
// is drawn only in tiles the binner visits: always when the box lies in one 64x64 tile,
// otherwise only when the region's side is not on a tile boundary (lp_setup_bin_triangle).
// Widens `bbox` (already intersected with the region) over the leaked column and row, and
// returns which of them it widened (kLeakLeft, kLeakBottom); 0 without multisampling.
inline constexpr std::uint8_t kLeakLeft = 1;
inline constexpr std::uint8_t kLeakBottom = 2;
std::uint8_t multisample_scissor_leak(const PixelRect& binned, const SetupParams& p,
                                      PixelRect& bbox);

// The samples of pixel (x, y) a leak lets through (all four away from the leaked column and
// row): a mask with bit s for sample s.
inline unsigned leak_samples(std::uint8_t leak, const PixelRect& bbox, int x, int y) {
    unsigned m = 0xf;
    if ((leak & kLeakLeft) && x == bbox.x0) m &= 0xa;    // samples 1 and 3: x offset > 1/2
    if ((leak & kLeakBottom) && y == bbox.y0) m &= 0xc;  // samples 2 and 3: y offset > 1/2
    return m;
}

// The plain test: every edge value positive at the pixel.
inline bool covers_pixel(const TriangleSetup& t, int px, int py) {
    return t.edges[0].at(px, py, t.bits) > 0 && t.edges[1].at(px, py, t.bits) > 0 &&
           t.edges[2].at(px, py, t.bits) > 0;
}

}  // namespace refraster::detail
