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

#include "models/llvmpipe/llvmpipe_walk.hpp"
#include "common/pixel_rect.hpp"
#include "refraster/draw.hpp"
#include "refraster/fixed.hpp"
#include "refraster/profile.hpp"

namespace refraster::detail {

// Bit budget of the snapped path. Window coordinates stay below 2^16 in magnitude (viewport
// origin in [-32768, 32767] plus a width of at most 16384, and the clipper keeps vertices
// inside the viewport up to float rounding), so with at most 8 subpixel bits:
//   snapped coordinates      |X|      < 2^24
//   edge deltas a, b         |a|,|b|  < 2^25
//   edge constants c         |c|      < 2^25 * 2^24 * 2 = 2^50
//   edge value at a pixel    |E|      < 2^50 + 2 * 2^25 * 2^(14+8) = 2^51 (framebuffer < 2^14)
inline constexpr int kMaxSubpixelBits = 8;
inline constexpr int kWindowCoordinateBits = 16;
inline constexpr int kSnappedBits = kWindowCoordinateBits + kMaxSubpixelBits;  // 24
inline constexpr int kEdgeDeltaBits = kSnappedBits + 1;                        // 25
inline constexpr int kEdgeConstantBits = kEdgeDeltaBits + kSnappedBits + 1;    // 50
inline constexpr int kFramebufferBits = 14;                                    // 16384
inline constexpr int kEdgeValueBits = kEdgeConstantBits + 1;                   // 51
static_assert(kSnappedBits < 31, "snapped coordinates must fit int32 (llvmpipe's 24.8)");
static_assert(kEdgeDeltaBits < 31, "edge deltas must fit int32");
static_assert(kEdgeDeltaBits + kFramebufferBits + kMaxSubpixelBits + 1 <= kEdgeConstantBits,
              "stepping across the framebuffer must stay within the constant's budget");
static_assert(kEdgeValueBits < 63, "edge values must fit int64");

using Subpixel = Fixed<kMaxSubpixelBits, std::int32_t>;

struct EdgeFunction {
    std::int32_t a = 0;  // dE/dpx = -a << bits
    std::int32_t b = 0;  // dE/dpy = +b << bits
    std::int64_t c = 0;  // includes the tie bias
    bool owns_ties = false;

    // E at the pixel (px, py); the pixel centre is the origin of the snapped grid (its
    // bottom-left corner when multisampling).
    std::int64_t at(int px, int py, int bits) const {
        const std::int64_t one = std::int64_t{1} << bits;
        return checked_add(checked_sub(c, checked_mul(wide_mul(a, px), one)),
                           checked_mul(wide_mul(b, py), one));
    }
    // What a sample at (sx, sy) subpixels from the pixel's origin adds to at(px, py): the
    // multisample rasterizer's (sy * dcdy - sx * dcdx) >> FIXED_ORDER, exact because dcdx and
    // dcdy are pre-shifted (lp_rast_tri_tmp.h, MULTISAMPLE).
    std::int64_t sample_offset(std::int32_t sx, std::int32_t sy) const {
        return checked_sub(wide_mul(b, sy), wide_mul(a, sx));
    }
};

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

struct SetupParams {
    int bits = 8;
    SnapRounding rounding = SnapRounding::NearestEven;
    float pixel_center_offset = 0.5f;
    // The profile's pixel centre offset even when multisampling zeroes the one above
    // (llvmpipe's setup->pixel_offset, from half_pixel_center alone).
    float half_pixel_center = 0.5f;
    TieRule tie_rule = TieRule::LeftBottom;
    CullMode cull = CullMode::None;
    bool front_ccw = false;  // gallium's rasterizer front_ccw (FBO: flipped from GL)
    bool provoking_first = false;
    PixelRect draw_region;  // framebuffer, intersected with the scissor
    PixelRect framebuffer;
    // Profile.wrapping_arithmetic: reproduce llvmpipe's conversion of out-of-range
    // positions and its 32-bit wrapping (llvmpipe_walk.hpp) instead of refusing them.
    bool wrapping = true;
    // A 4x target drawn with GL_MULTISAMPLE on: positions snap without the half-pixel offset
    // (pixel_center_offset is 0) and coverage is tested at each sample (samples.hpp).
    bool multisample = false;
};

// The profile's subpixel bits must be at most kMaxSubpixelBits and the target at most
// 2^kFramebufferBits pixels a side: the bit budget above rests on both.
SetupParams setup_params(const Profile& profile, const DrawState& state, const Target& target);

// Whether the tie rule gives an edge the pixel centres lying exactly on it (see setup.cpp).
bool owns_ties(std::int32_t a, std::int32_t b, TieRule rule);

// The edge function of the snapped edge (xi, yi) -> (xj, yj), tie bias included; the
// interior of a polygon oriented as set-up triangles are is where it is positive.
EdgeFunction make_edge(std::int32_t xi, std::int32_t yi, std::int32_t xj, std::int32_t yj,
                       TieRule rule);

// Gives `t` (oriented positions set) llvmpipe's planes and walk (llvmpipe_walk.hpp), which
// setup_triangle does itself where llvmpipe's integer widths matter. In range the walk
// covers exactly the pixels the edge functions cover (a property the tests check).
void attach_llvmpipe_walk(const SetupParams& p, TriangleSetup& t);

SetupOutcome setup_triangle(const std::array<std::array<float, 2>, 3>& window, const SetupParams& p,
                            TriangleSetup& out);

// One window position snapped as setup_triangle snaps a vertex (calc_fixed_position): the
// pixel centre of (px, py) is (px << bits, py << bits). nullopt for a position outside the
// budget above (setup then takes llvmpipe's own walk).
std::optional<std::array<std::int32_t, 2>> snap_position(float x, float y, const SetupParams& p);

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
