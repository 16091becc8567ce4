// llvmpipe_walk.hpp: llvmpipe's own planes, binning and tile walk, with llvmpipe's integer
// widths, for the triangles where those widths decide the pixels.
//
// Implements (gallium/drivers/llvmpipe, rewritten):
//  - the planes of do_triangle_ccw's SSE branch (lp_setup_tri.c) from snapped positions:
//    dcdx = Y_i - Y_{i+1} and dcdy = X_i - X_{i+1} as wrapping int32 differences,
//    c = dcdx * X_i - dcdy * Y_i in wrapping int64 plus the tie bias, then dcdx and dcdy
//    shifted left by FIXED_ORDER (8) in int32, and the trivial-reject offset eo built from
//    the shifted values under the signs of the unshifted ones, stored as uint32;
//  - the draw-region planes of lp_setup_add_scissor_planes (lp_setup.c) for each side of the
//    draw region (framebuffer and scissor) the box reaches past (scissor_planes_needed);
//  - the tile classification of lp_setup_bin_triangle: one tile with every plane when the
//    box crosses no 64-pixel boundary, otherwise 64-bit tests per tile that skip the tile,
//    shade it whole, or walk it with the planes it does not trivially accept, a row ending
//    at the first rejected tile after one that was not;
//  - the tile walk of lp_rast_tri_tmp.h with RASTER_64 (TAG(lp_rast_triangle), do_block_16,
//    do_block_4) and build_mask_linear of lp_rast_tri.c: c >> FIXED_ORDER narrowed to int32
//    per block, and every sum after it wrapping in int32.
//
// Where the positions stay within the 24.8 budget of setup.hpp and no edge value leaves int32
// inside a one-tile walk, these tests decide exactly what the edge functions decide, and the
// traversal of traverse.hpp is used instead (setup.cpp chooses). This walk is for the rest:
// a window coordinate that is not finite or too large converts to 0x80000000 (cvtps2dq's
// integer indefinite) and the differences wrap (docs/precision.md, "Huge coordinates and far
// beyond the guard band"), and one-tile triangles with far edges ("One-tile triangles with
// far edges").
//
// Multisampling (Triangle::samples 4): the same tile and block tests on the pixels, then
// do_block_4's MULTISAMPLE branch: for each sample, c plus (sy * dcdy - sx * dcdx) >> 8 in 64
// bits, then the same int32 mask; the draw-region planes get +127 (lp_setup_add_scissor_planes).
//
// Deliberately does not: the 32-bit rasterizer (boxes of at most MAX_FIXED_LENGTH32 = 128
// pixels, where nothing wraps; setup.cpp refuses such a triangle here), or any subpixel
// precision but llvmpipe's 8 bits.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

#include "common/pixel_rect.hpp"

namespace refraster::detail::lp {

inline constexpr int kFixedOrder = 8;          // FIXED_ORDER: subpixel bits of llvmpipe's positions
inline constexpr int kTileOrder = 6;           // TILE_ORDER: 64x64 tiles
inline constexpr int kMaxFixedLength32 = 128;  // MAX_FIXED_LENGTH32 = 1 << (15 - FIXED_ORDER)
static_assert(kMaxFixedLength32 == 1 << (32 / 2 - 1 - kFixedOrder),
              "lp_rast.h, MAX_FIXED_LENGTH32");
static_assert(1 << kTileOrder == 64, "llvmpipe's tiles are 64 pixels wide");

// Two's-complement arithmetic as the machine does it: C++20 defines the narrowing
// conversions modulo 2^N, and unsigned arithmetic wraps.
inline std::int32_t wrap32(std::uint32_t v) {
    return static_cast<std::int32_t>(v);
}
inline std::int32_t add32(std::int32_t a, std::int32_t b) {
    return wrap32(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
}
inline std::int32_t sub32(std::int32_t a, std::int32_t b) {
    return wrap32(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
}
inline std::int32_t shl32(std::int32_t a, int n) {
    return wrap32(static_cast<std::uint32_t>(a) << n);
}
inline std::int32_t neg32(std::int32_t a) {
    return wrap32(0u - static_cast<std::uint32_t>(a));
}
inline std::int64_t add64(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) + static_cast<std::uint64_t>(b));
}
inline std::int64_t sub64(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) - static_cast<std::uint64_t>(b));
}
inline std::int64_t shl64(std::int64_t a, int n) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) << n);
}
// IMUL64 of two int32 values never overflows; a further factor (TILE_SIZE) may wrap.
inline std::int64_t mul64(std::int64_t a, std::int64_t b) {
    return static_cast<std::int64_t>(static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b));
}

// struct lp_rast_plane (lp_rast.h): c in 1/256 pixel units at the framebuffer origin,
// dcdx and dcdy already shifted by FIXED_ORDER, eo unsigned.
struct Plane {
    std::int64_t c = 0;
    std::int32_t dcdx = 0;
    std::int32_t dcdy = 0;
    std::uint32_t eo = 0;
};

inline constexpr int kMaxPlanes = 7;  // three edges and four draw-region sides

struct Triangle {
    std::array<Plane, kMaxPlanes> planes{};
    int count = 0;
    PixelRect box;          // do_triangle_ccw's box, x0 and y0 clamped to 0, x1 and y1 not
    PixelRect draw_region;  // lp_setup.c draw_regions: framebuffer and scissor
    PixelRect framebuffer;  // pixels outside it are never stored
    int samples = 1;        // 4: the multisample rasterizer
};

// lp_rast.c, lp_sample_pos_4x in FIXED_ORDER units: x, y of each sample (samples.hpp).
inline constexpr std::array<std::array<std::int32_t, 2>, 4> kFixedSamplePos4x{
    {{96, 32}, {224, 96}, {32, 160}, {160, 224}}};

// do_triangle_ccw, SSE branch: the plane of the edge from vertex i to vertex i+1.
inline Plane edge_plane(std::int32_t xi, std::int32_t yi, std::int32_t xj, std::int32_t yj,
                        bool owns_ties) {
    const std::int32_t dcdx = sub32(yi, yj);
    const std::int32_t dcdy = sub32(xi, xj);
    Plane p;
    p.c = sub64(std::int64_t{dcdx} * xi, std::int64_t{dcdy} * yi);
    if (owns_ties) p.c = add64(p.c, 1);
    p.dcdx = shl32(dcdx, kFixedOrder);
    p.dcdy = shl32(dcdy, kFixedOrder);
    // eo = (dcdy unshifted >= 0 ? dcdy : 0) - (dcdx unshifted < 0 ? dcdx : 0), the masks
    // taken before the shift, the values after it, in int32.
    const std::int32_t pos = dcdy >= 0 ? p.dcdy : 0;
    const std::int32_t neg = dcdx < 0 ? p.dcdx : 0;
    p.eo = static_cast<std::uint32_t>(sub32(pos, neg));
    return p;
}

// lp_setup_add_scissor_planes, for the sides scissor_planes_needed picks; multisampling adds
// 127 to every constant (the left and bottom planes then sit half a pixel outside).
inline void add_region_planes(Triangle& t) {
    const PixelRect& b = t.box;
    const PixelRect& s = t.draw_region;
    const std::int64_t adj = t.samples > 1 ? 127 : 0;
    const auto push = [&](std::int32_t dcdx, std::int32_t dcdy, std::int64_t c, std::uint32_t eo) {
        t.planes[static_cast<std::size_t>(t.count++)] = {c, dcdx, dcdy, eo};
    };
    if (b.x0 < s.x0)
        push(shl32(-1, kFixedOrder), 0, -(std::int64_t{shl32(s.x0 - 1, kFixedOrder)} + adj),
             1u << kFixedOrder);
    if (b.x1 > s.x1)
        push(1 << kFixedOrder, 0, std::int64_t{shl32(s.x1, kFixedOrder)} + 127 + adj, 0);
    if (b.y0 < s.y0)
        push(0, 1 << kFixedOrder, -(std::int64_t{shl32(s.y0 - 1, kFixedOrder)} + adj),
             1u << kFixedOrder);
    if (b.y1 > s.y1)
        push(0, shl32(-1, kFixedOrder), std::int64_t{shl32(s.y1, kFixedOrder)} + 127 + adj, 0);
}

// build_mask_linear: bit j * 4 + i is the sign of c + i * dcdx + j * dcdy in int32.
inline unsigned mask_linear(std::int32_t c, std::int32_t dcdx, std::int32_t dcdy) {
    unsigned mask = 0;
    for (int j = 0; j < 4; ++j) {
        const std::int32_t row =
            add32(c, wrap32(static_cast<std::uint32_t>(dcdy) * static_cast<std::uint32_t>(j)));
        for (int i = 0; i < 4; ++i) {
            const std::int32_t v = add32(
                row, wrap32(static_cast<std::uint32_t>(dcdx) * static_cast<std::uint32_t>(i)));
            if (v < 0) mask |= 1u << (j * 4 + i);
        }
    }
    return mask;
}

// The planes a walk tests, and the covered pixels (of each sample) as 64-bit rows of one tile.
struct Walk {
    std::array<Plane, kMaxPlanes> planes{};
    int count = 0;
    int tile_x = 0;
    int tile_y = 0;
    int samples = 1;
    std::uint64_t rows[4][64] = {};

    void fill(int x, int y, int n) {
        for (int s = 0; s < samples; ++s) {
            for (int yy = y; yy < y + n; ++yy) {
                for (int xx = x; xx < x + n; ++xx)
                    rows[s][yy - tile_y] |= std::uint64_t{1} << (xx - tile_x);
            }
        }
    }

    // do_block_4, RASTER_64; with samples, its MULTISAMPLE branch.
    void block_4(int x, int y, const std::int64_t* c) {
        for (int s = 0; s < samples; ++s) {
            unsigned mask = 0xffff;
            for (int k = 0; k < count; ++k) {
                const Plane& p = planes[static_cast<std::size_t>(k)];
                std::int64_t cs = c[k];
                if (samples > 1) {
                    const auto& pos = kFixedSamplePos4x[static_cast<std::size_t>(s)];
                    cs = add64(cs, add64(mul64(pos[1], p.dcdy), mul64(pos[0], neg32(p.dcdx))) >>
                                       kFixedOrder);
                }
                const auto q = static_cast<std::int32_t>(sub64(cs, 1) >> kFixedOrder);
                mask &= ~mask_linear(q, neg32(p.dcdx) >> kFixedOrder, p.dcdy >> kFixedOrder);
            }
            for (int j = 0; j < 4; ++j) {
                for (int i = 0; i < 4; ++i) {
                    if (mask & (1u << (j * 4 + i)))
                        rows[s][y + j - tile_y] |= std::uint64_t{1} << (x + i - tile_x);
                }
            }
        }
    }

    // The block tests of TAG(lp_rast_triangle) (shift 4, blocks of 16) and do_block_16
    // (shift 2, blocks of 4), RASTER_64.
    void masks(const std::int64_t* c, int shift, unsigned& outmask, unsigned& partmask) const {
        outmask = 0;
        partmask = 0;
        for (int k = 0; k < count; ++k) {
            const Plane& p = planes[static_cast<std::size_t>(k)];
            std::int32_t dcdx = neg32(p.dcdx) >> kFixedOrder;
            std::int32_t dcdy = p.dcdy >> kFixedOrder;
            const auto cox = static_cast<std::int32_t>(p.eo >> kFixedOrder);
            const std::int32_t ei = shl32(sub32(add32(dcdy, dcdx), cox), shift);
            const std::int32_t cox_s = shl32(cox, shift);
            const auto c_hi = static_cast<std::int32_t>(c[k] >> kFixedOrder);
            const auto c1_hi = static_cast<std::int32_t>(sub64(c[k], 1) >> kFixedOrder);
            const std::int32_t co = add32(c_hi, cox_s);
            const std::int32_t cdiff = add32(sub32(ei, cox_s), sub32(c1_hi, c_hi));
            dcdx = shl32(dcdx, shift);
            dcdy = shl32(dcdy, shift);
            outmask |= mask_linear(co, dcdx, dcdy);
            partmask |= mask_linear(add32(co, cdiff), dcdx, dcdy);
        }
    }

    void offset(const std::int64_t* c, int ix, int iy, std::int64_t* out) const {
        for (int k = 0; k < count; ++k) {
            const Plane& p = planes[static_cast<std::size_t>(k)];
            out[k] = add64(sub64(c[k], std::int64_t{p.dcdx} * ix), std::int64_t{p.dcdy} * iy);
        }
    }

    void block_16(int x, int y, const std::int64_t* c) {
        unsigned outmask = 0;
        unsigned partmask = 0;
        masks(c, 2, outmask, partmask);
        if (outmask == 0xffff) return;
        const unsigned inmask = ~partmask & 0xffff;
        const unsigned partial = partmask & ~outmask;
        for (int s = 0; s < 16; ++s) {
            const int ix = (s & 3) * 4;
            const int iy = (s >> 2) * 4;
            if (partial & (1u << s)) {
                std::int64_t cx[kMaxPlanes];
                offset(c, ix, iy, cx);
                block_4(x + ix, y + iy, cx);
            } else if (inmask & (1u << s)) {
                fill(x + ix, y + iy, 4);
            }
        }
    }

    // TAG(lp_rast_triangle) over the tile at (tile_x, tile_y).
    void tile() {
        std::int64_t c[kMaxPlanes];
        for (int k = 0; k < count; ++k) {
            const Plane& p = planes[static_cast<std::size_t>(k)];
            c[k] = sub64(add64(p.c, std::int64_t{p.dcdy} * tile_y), std::int64_t{p.dcdx} * tile_x);
        }
        unsigned outmask = 0;
        unsigned partmask = 0;
        masks(c, 4, outmask, partmask);
        if (outmask == 0xffff) return;
        const unsigned inmask = ~partmask & 0xffff;
        const unsigned partial = partmask & ~outmask;
        for (int s = 0; s < 16; ++s) {
            const int ix = (s & 3) * 16;
            const int iy = (s >> 2) * 16;
            if (partial & (1u << s)) {
                std::int64_t cx[kMaxPlanes];
                offset(c, ix, iy, cx);
                block_16(tile_x + ix, tile_y + iy, cx);
            } else if (inmask & (1u << s)) {
                fill(tile_x + ix, tile_y + iy, 16);
            }
        }
    }
};

// Keeps the pixels of a tile's rows that lie inside the framebuffer: llvmpipe shades whole
// blocks, but only the framebuffer's pixels are stored.
inline bool clip_to_framebuffer(std::uint64_t* rows, int tile_x, int tile_y, const PixelRect& fb) {
    const int lo = std::max(fb.x0 - tile_x, 0);
    const int hi = std::min(fb.x1 - tile_x, 63);
    if (lo > hi) return false;
    const std::uint64_t keep =
        (hi - lo == 63 ? ~std::uint64_t{0} : ((std::uint64_t{1} << (hi - lo + 1)) - 1)) << lo;
    bool any = false;
    for (int r = 0; r < 64; ++r) {
        const int y = tile_y + r;
        rows[r] = (y < fb.y0 || y > fb.y1) ? 0 : rows[r] & keep;
        any = any || rows[r] != 0;
    }
    return any;
}

inline std::uint32_t floor_pot(std::uint32_t n) {
    return n == 0 ? 0 : std::bit_floor(n);
}

// Keeps every sample's rows inside the framebuffer; whether any is left.
inline bool clip_walk(Walk& w, const PixelRect& fb) {
    bool any = false;
    for (int s = 0; s < w.samples; ++s) {
        any =
            clip_to_framebuffer(w.rows[static_cast<std::size_t>(s)], w.tile_x, w.tile_y, fb) || any;
    }
    return any;
}

// lp_setup_bin_triangle with the tile walks it bins; calls on_walk(walk) with each tile's
// covered pixels inside the framebuffer (bit x - tile_x of rows[s][y - tile_y] for sample s),
// tile by tile in llvmpipe's binning order.
template <class OnWalk>
void walk_binned(const Triangle& t, OnWalk&& on_walk) {
    const PixelRect& b = t.box;
    const auto walk_tile = [&](int tx, int ty, unsigned plane_mask) {
        if (tx > t.framebuffer.x1 || ty > t.framebuffer.y1) return;
        Walk w;
        w.samples = t.samples;
        for (int k = 0; k < t.count; ++k) {
            if (plane_mask & (1u << k))
                w.planes[static_cast<std::size_t>(w.count++)] =
                    t.planes[static_cast<std::size_t>(k)];
        }
        w.tile_x = tx;
        w.tile_y = ty;
        w.tile();
        if (clip_walk(w, t.framebuffer)) on_walk(static_cast<const Walk&>(w));
    };
    const unsigned all = (1u << t.count) - 1;
    const std::uint32_t dx = floor_pot(static_cast<std::uint32_t>((b.x0 ^ b.x1) | (b.y0 ^ b.y1)));
    if (dx < 64) {
        // One tile, every plane: the 4x4 and 16x16 commands of the 64-bit rasterizer
        // (lp_rast_triangle_3_4, _3_16, _4_16) walk the whole tile with all planes too.
        walk_tile(b.x0 / 64 * 64, b.y0 / 64 * 64, all);
        return;
    }
    const PixelRect trimmed = intersect(b, t.draw_region);
    if (trimmed.empty()) return;
    const int ix0 = trimmed.x0 / 64;
    const int iy0 = trimmed.y0 / 64;
    const int ix1 = trimmed.x1 / 64;
    const int iy1 = trimmed.y1 / 64;
    std::int64_t c[kMaxPlanes];
    std::int64_t ei[kMaxPlanes];
    std::int64_t eo[kMaxPlanes];
    std::int64_t xstep[kMaxPlanes];
    std::int64_t ystep[kMaxPlanes];
    for (int i = 0; i < t.count; ++i) {
        const Plane& p = t.planes[static_cast<std::size_t>(i)];
        c[i] = sub64(add64(p.c, mul64(std::int64_t{p.dcdy} * iy0, 64)),
                     mul64(std::int64_t{p.dcdx} * ix0, 64));
        // (dcdy - dcdx) is an int subtraction in C, then widened for the eo term.
        ei[i] = shl64(std::int64_t{sub32(p.dcdy, p.dcdx)} - std::int64_t{p.eo}, kTileOrder);
        eo[i] = shl64(std::int64_t{p.eo}, kTileOrder);
        xstep[i] = -shl64(std::int64_t{p.dcdx}, kTileOrder);
        ystep[i] = shl64(std::int64_t{p.dcdy}, kTileOrder);
    }
    for (int y = iy0; y <= iy1; ++y) {
        bool in = false;
        std::int64_t cx[kMaxPlanes];
        std::copy(c, c + t.count, cx);
        for (int x = ix0; x <= ix1; ++x) {
            bool out = false;
            unsigned partial = 0;
            for (int i = 0; i < t.count; ++i) {
                if (add64(cx[i], eo[i]) < 0) out = true;
                if (sub64(add64(cx[i], ei[i]), 1) < 0) partial |= 1u << i;
            }
            if (out) {
                if (in) break;  // exiting the triangle: the rest of the row is not binned
            } else if (partial != 0) {
                in = true;
                walk_tile(x * 64, y * 64, partial);
            } else {
                in = true;
                Walk w;
                w.samples = t.samples;
                w.tile_x = x * 64;
                w.tile_y = y * 64;
                w.fill(w.tile_x, w.tile_y, 64);
                if (clip_walk(w, t.framebuffer)) on_walk(static_cast<const Walk&>(w));
            }
            for (int i = 0; i < t.count; ++i) cx[i] = add64(cx[i], xstep[i]);
        }
        for (int i = 0; i < t.count; ++i) c[i] = add64(c[i], ystep[i]);
    }
}

// The single-sample walk: on_tile(rows, tile_x, tile_y).
template <class OnTile>
void walk_tiles(const Triangle& t, OnTile&& on_tile) {
    walk_binned(t, [&](const Walk& w) {
        on_tile(static_cast<const std::uint64_t*>(w.rows[0]), w.tile_x, w.tile_y);
    });
}

}  // namespace refraster::detail::lp
