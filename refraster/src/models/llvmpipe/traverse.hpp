// traverse.hpp: which pixels of a set-up triangle are covered, fast.
//
// Implements: tiled traversal over the triangle's box in 64x64 tiles, then 16x16 and 4x4
// blocks, each block trivially rejected when an edge is negative over all of it and an edge
// dropped from the block when it is positive over all of it (the hierarchy of
// llvmpipe's lp_rast_tri_tmp.h, rewritten); pixels of partially covered 4x4 blocks are
// stepped incrementally in int32. The result is the set `covers_pixel` gives pixel by pixel,
// which tests prove over random triangles. Each 64x64 tile's coverage is reported as quad
// packets (quad.hpp), for the fragment stage, or as row spans, for tests and traces.
//
// Deliberately does not: evaluate attributes or know about fragments.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <iterator>
#include <span>
#include <tuple>
#include <utility>

#include "models/llvmpipe/setup.hpp"
#include "stages/quad.hpp"
#include "stages/row_block.hpp"
#include "stages/samples.hpp"

namespace refraster::detail {

// int32 stepping inside a 4x4 block: an edge that crosses the block takes values within
// (|a| + |b|) * 3 << bits of zero there, so q = (E - 1) >> bits stays below
// 3 * 2^kEdgeDeltaBits < 2^27 in magnitude, and each step adds -a or +b (< 2^25).
static_assert(kEdgeDeltaBits + 2 + 1 < 31, "4x4 block stepping must fit int32");

// The covered pixels of the 64x64 tile at (tx, ty) (multiples of 64) inside the primitive's box,
// OR-ed into rows[0..64) (bit i of rows[r]: pixel tx + i of row ty + r); whether any is. `Setup`
// is any convex primitive with `edges` (EdgeFunction, the first kEdges of them used: 3 for
// triangles, 4 for lines and points), `bbox` and `bits`.
template <unsigned kEdges, class Setup>
bool convex_tile_rows(const Setup& t, int tx, int ty, std::uint64_t* rows) {
    constexpr unsigned kAll = (1u << kEdges) - 1;
    const PixelRect box = t.bbox;
    const int bits = t.bits;
    const std::int64_t one = std::int64_t{1} << bits;
    // Per-edge increase of E over `n` pixel steps in the worst direction, and in the best.
    const auto grow = [&](const EdgeFunction& e, int n) {
        return (e.a < 0 ? -wide_mul(e.a, n) : 0) * one + (e.b > 0 ? wide_mul(e.b, n) : 0) * one;
    };
    const auto shrink = [&](const EdgeFunction& e, int n) {
        return (e.a > 0 ? -wide_mul(e.a, n) : 0) * one + (e.b < 0 ? wide_mul(e.b, n) : 0) * one;
    };
    // Recursion over blocks, explicit: level sizes 64, 16, 4; `live` marks the edges still to
    // be tested inside the block.
    bool any = false;
    const auto block = [&](auto&& self, int bx, int by, int size, unsigned live) -> void {
        // Clip the block to the box: blocks outside it contribute nothing.
        if (bx > box.x1 || by > box.y1 || bx + size - 1 < box.x0 || by + size - 1 < box.y0) return;
        unsigned still = 0;
        for (unsigned i = 0; i < kEdges; ++i) {
            if (!(live & (1u << i))) continue;
            const EdgeFunction& e = t.edges[i];
            const std::int64_t e0 = e.at(bx, by, bits);
            if (e0 + grow(e, size - 1) <= 0) return;              // negative all over: reject
            if (e0 + shrink(e, size - 1) <= 0) still |= 1u << i;  // crosses the block
        }
        const int x_lo = std::max(bx, box.x0);
        const int x_hi = std::min(bx + size - 1, box.x1);
        const int y_lo = std::max(by, box.y0);
        const int y_hi = std::min(by + size - 1, box.y1);
        if (still == 0) {
            // Every remaining edge positive over the block: all of it is covered.
            const int n = x_hi - x_lo + 1;
            const std::uint64_t bitsrow =
                (n == 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << n) - 1)) << (x_lo - tx);
            for (int y = y_lo; y <= y_hi; ++y) rows[y - ty] |= bitsrow;
            any = true;
            return;
        }
        if (size > 4) {
            const int sub = size / 4;
            for (int j = 0; j < 4; ++j) {
                for (int i = 0; i < 4; ++i) self(self, bx + i * sub, by + j * sub, sub, still);
            }
            return;
        }
        // A 4x4 block that some edges cross: step q = (E - 1) >> bits in int32.
        std::int32_t q_row[kEdges] = {};
        std::int32_t step_x[kEdges] = {};
        std::int32_t step_y[kEdges] = {};
        unsigned n_edges = 0;
        for (unsigned i = 0; i < kEdges; ++i) {
            if (!(still & (1u << i))) continue;
            const EdgeFunction& e = t.edges[i];
            q_row[n_edges] = checked_narrow<std::int32_t>((e.at(x_lo, y_lo, bits) - 1) >> bits);
            step_x[n_edges] = -e.a;
            step_y[n_edges] = e.b;
            ++n_edges;
        }
        for (int y = y_lo; y <= y_hi; ++y) {
            std::int32_t q[kEdges];
            std::copy(std::begin(q_row), std::end(q_row), std::begin(q));
            std::uint64_t m = 0;
            for (int x = x_lo; x <= x_hi; ++x) {
                bool in = true;
                for (unsigned k = 0; k < n_edges; ++k) {
                    in = in && q[k] >= 0;
                    q[k] = checked_add(q[k], step_x[k]);
                }
                if (in) m |= std::uint64_t{1} << (x - tx);
            }
            if (m != 0) {
                rows[y - ty] |= m;
                any = true;
            }
            for (unsigned k = 0; k < n_edges; ++k) q_row[k] = checked_add(q_row[k], step_y[k]);
        }
    };
    block(block, tx, ty, kTileSize, kAll);
    return any;
}

// Calls on_tile(rows, tx, ty) for every 64x64 tile with covered pixels, tiles in raster
// order, rows[r] the mask of row ty + r (bit i: pixel tx + i); convex_tile_rows decides each.
template <unsigned kEdges, class Setup, class OnTile>
void convex_tiles(const Setup& t, OnTile&& on_tile) {
    const PixelRect box = t.bbox;
    if (box.empty()) return;
    std::uint64_t rows[kTileSize];
    const int tx0 = box.x0 & ~(kTileSize - 1);
    const int ty0 = box.y0 & ~(kTileSize - 1);
    for (int ty = ty0; ty <= box.y1; ty += kTileSize) {
        for (int tx = tx0; tx <= box.x1; tx += kTileSize) {
            for (auto& r : rows) r = 0;
            if (convex_tile_rows<kEdges>(t, tx, ty, rows))
                on_tile(static_cast<const std::uint64_t*>(rows), tx, ty);
        }
    }
}

// The rows of a convex primitive whose box (not empty) is at most 64 pixels wide and 64 rows
// high, into rows[0..h), their OR into `any`: every pixel of the box is decided by q = (E - 1) >>
// bits, exactly the test convex_tiles applies in its 4x4 blocks (E > 0 iff q >= 0), stepped in
// int32 over the whole box. Narrow boxes test pixel by pixel; wider ones take each row's span from
// each edge by one division (the pixels where q + s * i >= 0 form one interval of i). A vector
// builder `masks` (RowMaskFn, row_block.hpp), when given, computes the same rows many pixels at a
// time instead. Returns false, having done nothing, when the box is larger or an edge's values over
// it leave int32; the caller then takes convex_tiles. Small and medium primitives skip the tile
// hierarchy this way (small_convex_rows: the rows as one block).
template <unsigned kEdges, class Setup>
bool small_box_rows(const Setup& t, RowMaskFn masks, std::uint64_t* rows, std::uint64_t& any) {
    const PixelRect box = t.bbox;
    const int w = box.x1 - box.x0 + 1;
    const int h = box.y1 - box.y0 + 1;
    if (w > 64 || h > kMaxBlockRows) return false;
    std::int32_t q[kEdges];
    std::int32_t sx[kEdges];
    std::int32_t sy[kEdges];
    for (unsigned k = 0; k < kEdges; ++k) {
        const EdgeFunction& e = t.edges[k];
        const std::int64_t q0 = (e.at(box.x0, box.y0, t.bits) - 1) >> t.bits;
        const std::int64_t reach = (e.a < 0 ? -std::int64_t{e.a} : std::int64_t{e.a}) * w +
                                   (e.b < 0 ? -std::int64_t{e.b} : std::int64_t{e.b}) * h;
        if (q0 - reach <= INT32_MIN || q0 + reach >= INT32_MAX) return false;
        q[k] = static_cast<std::int32_t>(q0);
        sx[k] = -e.a;
        sy[k] = e.b;
    }
    if (masks != nullptr) {
        any |= masks(q, sx, sy, kEdges, w, h, rows);
        return true;
    }
    const std::uint64_t full = w == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << w) - 1;
    for (int r = 0; r < h; ++r) {
        std::uint64_t m = 0;
        if (w <= 16) {
            for (int i = 0; i < w; ++i) {
                bool in = true;
                for (unsigned k = 0; k < kEdges; ++k) in &= q[k] + sx[k] * i >= 0;
                m |= std::uint64_t{in} << i;
            }
        } else {
            std::int64_t lo = 0;
            std::int64_t hi = w - 1;
            for (unsigned k = 0; k < kEdges; ++k) {
                const std::int64_t qk = q[k];
                const std::int64_t s = sx[k];
                if (s == 0) {
                    if (qk < 0) hi = -1;
                } else if (s > 0) {
                    // q + s * i >= 0 from i = ceil(-q / s) on.
                    if (qk < 0) lo = std::max(lo, (-qk + s - 1) / s);
                } else {
                    // q + s * i >= 0 up to i = floor(q / -s).
                    hi = qk < 0 ? -1 : std::min(hi, qk / -s);
                }
            }
            if (lo <= hi) m = (full >> (w - 1 - hi)) & ~((std::uint64_t{1} << lo) - 1);
        }
        rows[r] = m;
        any |= m;
        for (unsigned k = 0; k < kEdges; ++k) q[k] += sy[k];
    }
    return true;
}

template <unsigned kEdges, class Setup, class OnBlock>
bool small_convex_rows(const Setup& t, OnBlock&& on_block, RowMaskFn masks = nullptr) {
    const PixelRect box = t.bbox;
    if (box.empty()) return true;
    std::uint64_t rows[kMaxBlockRows];
    std::uint64_t any = 0;
    if (!small_box_rows<kEdges>(t, masks, rows, any)) return false;
    if (any != 0)
        on_block(
            RowBlock{box.x0, box.y0, box.y1 - box.y0 + 1, static_cast<const std::uint64_t*>(rows)});
    return true;
}

// Every covered pixel of a convex primitive as row blocks: the small path above (with the
// vector builder `masks` when given), or each 64x64 tile of convex_tiles.
template <unsigned kEdges, class Setup, class OnBlock>
void convex_row_blocks(const Setup& t, OnBlock&& on_block, RowMaskFn masks = nullptr) {
    if (small_convex_rows<kEdges>(t, on_block, masks)) return;
    convex_tiles<kEdges>(t, [&](const std::uint64_t* rows, int tx, int ty) {
        on_block(RowBlock{tx, ty, kTileSize, rows});
    });
}

// The edges of `t` moved to each sample of the standard 4x pattern: E plus the sample's offset
// (EdgeFunction::sample_offset), so that a test of the pixel (x, y) against setup s is the test
// of its sample s. The positions are multiples of 1/8, so any grid of at least 3 bits holds
// them exactly.
template <unsigned kEdges, class Setup>
std::array<Setup, kMsaaSamples> per_sample_setups(const Setup& t) {
    std::array<Setup, kMsaaSamples> out;
    const float one = static_cast<float>(std::int64_t{1} << t.bits);
    for (unsigned s = 0; s < kMsaaSamples; ++s) {
        out[s] = t;
        const auto& pos = kSamplePositions4x[s];
        const auto sx = static_cast<std::int32_t>(pos.x * one);
        const auto sy = static_cast<std::int32_t>(pos.y * one);
        for (unsigned e = 0; e < kEdges; ++e)
            out[s].edges[e].c = checked_add(t.edges[e].c, t.edges[e].sample_offset(sx, sy));
    }
    return out;
}

// Per-sample coverage of a convex primitive set up without the pixel offset (multisampling) as
// 4x row blocks (row_block.hpp): the test convex_quads_4x applies, sample by sample, through
// the single-sample row builders (the small-box path with the vector builder `masks` when
// given, or the tiles) run on the edges moved to each sample. The scissor leak
// (multisample_scissor_leak) keeps samples 1 and 3 of the column leak_x and samples 2 and 3 of
// the row leak_y (leak_samples): the box's first column and row, which a band's box no longer
// starts at.
template <unsigned kEdges, class Setup, class OnBlock>
void convex_row_blocks_4x(const Setup& t, OnBlock&& on_block, RowMaskFn masks, int leak_x,
                          int leak_y) {
    const PixelRect box = t.bbox;
    if (box.empty()) return;
    const auto at = per_sample_setups<kEdges>(t);
    std::uint64_t rows[kMsaaSamples * kMaxBlockRows];
    // Clears the leaking column and row of a block at (x0, y0) from the samples that do not
    // reach past the draw region's edge.
    const auto leak = [&](int x0, int y0, int n_rows) {
        if ((t.scissor_leak & kLeakLeft) && leak_x >= x0 && leak_x < x0 + 64) {
            const std::uint64_t keep = ~(std::uint64_t{1} << (leak_x - x0));
            for (const int s : {0, 2}) {
                for (int r = 0; r < n_rows; ++r) rows[s * kMaxBlockRows + r] &= keep;
            }
        }
        if ((t.scissor_leak & kLeakBottom) && leak_y >= y0 && leak_y < y0 + n_rows) {
            for (const int s : {0, 1}) rows[s * kMaxBlockRows + (leak_y - y0)] = 0;
        }
    };
    std::uint64_t any = 0;
    bool small = true;
    for (unsigned s = 0; s < kMsaaSamples && small; ++s)
        small = small_box_rows<kEdges>(at[s], masks, rows + s * kMaxBlockRows, any);
    if (small) {
        const int h = box.y1 - box.y0 + 1;
        leak(box.x0, box.y0, h);
        if (any != 0)
            on_block(RowBlock{box.x0, box.y0, h, static_cast<const std::uint64_t*>(rows),
                              static_cast<std::int32_t>(kMsaaSamples)});
        return;
    }
    const int tx0 = box.x0 & ~(kTileSize - 1);
    const int ty0 = box.y0 & ~(kTileSize - 1);
    for (int ty = ty0; ty <= box.y1; ty += kTileSize) {
        for (int tx = tx0; tx <= box.x1; tx += kTileSize) {
            bool covered = false;
            for (unsigned s = 0; s < kMsaaSamples; ++s) {
                std::uint64_t* r = rows + s * kMaxBlockRows;
                std::fill(r, r + kTileSize, std::uint64_t{0});
                covered = convex_tile_rows<kEdges>(at[s], tx, ty, r) || covered;
            }
            if (!covered) continue;
            leak(tx, ty, kTileSize);
            on_block(RowBlock{tx, ty, kTileSize, static_cast<const std::uint64_t*>(rows),
                              static_cast<std::int32_t>(kMsaaSamples)});
        }
    }
}

// Per-sample coverage of a convex primitive set up without the pixel offset (multisampling):
// calls emit(span of quad packets) once for every 64x64 tile with covered samples, tiles in
// raster order, each packet's mask holding all four samples of its four pixels. A sample is
// covered iff every edge is positive at it: the edge at the pixel's origin plus the sample's
// offset (EdgeFunction::sample_offset), as llvmpipe's multisample rasterizer tests it
// (lp_rast_tri_tmp.h, MULTISAMPLE: c + (sy * dcdy - sx * dcdx) >> FIXED_ORDER); its tile and
// block rejections are conservative over the whole pixel area, so only the per-sample test
// decides. The box must hold every pixel with a covered sample.
template <unsigned kEdges, class Setup, class Emit>
void convex_quads_4x(const Setup& t, Emit&& emit) {
    const PixelRect box = t.bbox;
    if (box.empty()) return;
    const int bits = t.bits;
    const std::int64_t one = std::int64_t{1} << bits;
    // Sample offsets on the primitive's subpixel grid: the positions are multiples of 1/8, so
    // any grid of at least 3 bits holds them exactly.
    std::array<std::array<std::int64_t, kMsaaSamples>, kEdges> offset{};
    for (unsigned e = 0; e < kEdges; ++e) {
        for (unsigned s = 0; s < kMsaaSamples; ++s) {
            const auto& pos = kSamplePositions4x[s];
            const auto sx = static_cast<std::int32_t>(pos.x * static_cast<float>(one));
            const auto sy = static_cast<std::int32_t>(pos.y * static_cast<float>(one));
            offset[e][s] = t.edges[e].sample_offset(sx, sy);
        }
    }
    const auto grow = [&](const EdgeFunction& e, int n) {
        return (e.a < 0 ? -wide_mul(e.a, n) : 0) * one + (e.b > 0 ? wide_mul(e.b, n) : 0) * one;
    };
    std::array<QuadPacket, kQuadsPerTile> quads;
    const int tx0 = box.x0 & ~(kTileSize - 1);
    const int ty0 = box.y0 & ~(kTileSize - 1);
    for (int ty = ty0; ty <= box.y1; ty += kTileSize) {
        for (int tx = tx0; tx <= box.x1; tx += kTileSize) {
            // A tile no sample of which an edge reaches: the edge's largest value over the
            // tile's area is not positive.
            bool rejected = false;
            for (unsigned e = 0; e < kEdges && !rejected; ++e) {
                rejected = t.edges[e].at(tx, ty, bits) + grow(t.edges[e], kTileSize) <= 0;
            }
            if (rejected) continue;
            const int x_lo = std::max(tx, box.x0) & ~1;
            const int x_hi = std::min(tx + kTileSize - 1, box.x1);
            const int y_lo = std::max(ty, box.y0) & ~1;
            const int y_hi = std::min(ty + kTileSize - 1, box.y1);
            std::size_t n = 0;
            for (int qy = y_lo; qy <= y_hi; qy += 2) {
                for (int qx = x_lo; qx <= x_hi; qx += 2) {
                    unsigned mask = 0;
                    for (unsigned p = 0; p < 4; ++p) {
                        const int x = qx + static_cast<int>(p & 1u);
                        const int y = qy + static_cast<int>(p >> 1);
                        if (x < box.x0 || x > box.x1 || y < box.y0 || y > box.y1) continue;
                        unsigned in = leak_samples(t.scissor_leak, box, x, y);
                        for (unsigned e = 0; e < kEdges && in != 0; ++e) {
                            const std::int64_t v = t.edges[e].at(x, y, bits);
                            for (unsigned s = 0; s < kMsaaSamples; ++s) {
                                if (v + offset[e][s] <= 0) in &= ~(1u << s);
                            }
                        }
                        for (unsigned s = 0; s < kMsaaSamples; ++s) {
                            if (in & (1u << s)) mask |= 1u << quad_bit(p, s);
                        }
                    }
                    if (mask != 0) quads[n++] = {qx, qy, static_cast<std::uint16_t>(mask)};
                }
            }
            if (n != 0) emit(std::span<const QuadPacket>(quads.data(), n));
        }
    }
}

// Calls visit(y, x_begin, x_end) (x_end exclusive) for every run of covered pixels, row by
// row within each tile; tiles in raster order. Every edge of `t.edges` is used.
template <class Setup, class Visit>
void traverse_convex(const Setup& t, Visit&& visit) {
    constexpr auto kEdges = static_cast<unsigned>(std::tuple_size_v<decltype(t.edges)>);
    convex_tiles<kEdges>(t, [&](const std::uint64_t* rows, int tx, int ty) {
        emit_tile_spans(rows, tx, ty, visit);
    });
}

// Every tile of a set-up triangle, by the walk llvmpipe takes for it.
template <class OnTile>
void triangle_tiles(const TriangleSetup& t, OnTile&& on_tile) {
    if (t.llvmpipe_walk) {
        lp::walk_tiles(t.walk, std::forward<OnTile>(on_tile));
        return;
    }
    convex_tiles<3>(t, std::forward<OnTile>(on_tile));
}

template <class Visit>
void traverse_triangle(const TriangleSetup& t, Visit&& visit) {
    triangle_tiles(t, [&](const std::uint64_t* rows, int tx, int ty) {
        emit_tile_spans(rows, tx, ty, visit);
    });
}

}  // namespace refraster::detail
