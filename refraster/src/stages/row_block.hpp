// row_block.hpp: covered pixels as row masks, the unit of work traversal hands to the fast
// fragment kernels.
//
// Implements: RowBlock, up to 64 rows of up to 64 pixels each, one 64-bit mask a row (bit i
// of mask[r] is the pixel (x0 + i, y0 + r)); a 64x64 tile of the traversal is one block, a
// small primitive's box another. A kernel that reads row masks walks a row in runs of as many
// pixels as its vector holds and never rebuilds 2x2 quads.
//
// A 4x block (samples 4) holds one such set of rows per sample: the rows of sample s start at
// mask[s * kMaxBlockRows], so that a tile of llvmpipe's multisample walk (llvmpipe_walk.hpp,
// Walk::rows) is a block as it stands; sample 0's rows come first, where a single-sample
// reader looks.
//
// Deliberately does not: promise that x0 or y0 is aligned: every bit set names a pixel (or a
// sample of it) inside the framebuffer, nothing else.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include "common/bit_count.hpp"

namespace refraster::detail {

inline constexpr int kMaxBlockRows = 64;

struct RowBlock {
    std::int32_t x0 = 0;
    std::int32_t y0 = 0;
    std::int32_t rows = 0;  // at most 64
    const std::uint64_t* mask = nullptr;
    std::int32_t samples = 1;  // 1, or 4: the rows of sample s at mask + s * kMaxBlockRows

    const std::uint64_t* sample_rows(int s) const { return mask + s * kMaxBlockRows; }
};

// The row masks of a box of w <= 64 pixels by h <= kMaxBlockRows rows, from each of `edges`
// edges' q = (E - 1) >> bits at the box's first pixel and its int32 steps along a row (sx) and
// down the box (sy): bit i of rows[r] is set iff q[k] + sx[k] * i + sy[k] * r >= 0 for every
// edge k (the test small_convex_rows applies, traverse.hpp), which the caller has checked
// stays within int32 over the box. Returns the OR of the rows. The vector builders
// (vector_kernels.hpp) are of this type.
using RowMaskFn = std::uint64_t (*)(const std::int32_t* q, const std::int32_t* sx,
                                    const std::int32_t* sy, unsigned edges, int w, int h,
                                    std::uint64_t* rows);

// Asks the caches for the lines holding pixels first..last of a buffer of 32-bit pixels
// (colour or depth), as __builtin_prefetch's kWrite and kLocality say. A prefetch changes no
// value.
template <int kWrite, int kLocality>
inline void prefetch_pixels(const std::uint32_t* buffer, std::size_t first, std::size_t last) {
    constexpr std::size_t kLinePixels = 64 / sizeof(std::uint32_t);
    for (std::size_t i = first;; i += kLinePixels) {
        const std::size_t at = i < last ? i : last;
        __builtin_prefetch(buffer + at, kWrite, kLocality);
        if (at == last) break;
    }
}

// The covered pixels (sample 0's, on a 4x block: what covered_pixels of quad packets counts).
inline int covered_pixels(const RowBlock& b) {
    int n = 0;
    for (int r = 0; r < b.rows; ++r) n += bit_count(b.mask[r]);
    return n;
}

}  // namespace refraster::detail
