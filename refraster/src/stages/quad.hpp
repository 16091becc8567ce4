// quad.hpp: quad packets, the unit of work traversal hands to the fragment stage.
//
// Implements: QuadPacket, a 2x2 block of pixels at an even (x, y) with a 16-bit coverage
// mask, four samples for each of its four pixels (the shape llvmpipe's fragment shader works
// in, lp_rast_tri_tmp.h -> lp_rast_shade_quads_mask, and the shape derivatives and 4x
// multisampling need); the conversion of a 64x64 tile's row masks into packets.
//
// Deliberately does not: know which samples a multisampled pixel has (a single-sample render
// sets only sample 0), or shade anything.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <span>

#include "common/bit_count.hpp"

namespace refraster::detail {

inline constexpr unsigned kMaxSamples = 4;

// Mask bit of sample `s` of pixel `p` of a quad: bit s * 4 + p, with pixel 0 at (x, y),
// 1 at (x + 1, y), 2 at (x, y + 1), 3 at (x + 1, y + 1). Sample-major, so that a
// single-sample packet's mask is its low four bits.
constexpr unsigned quad_bit(unsigned pixel, unsigned sample) {
    return sample * 4 + pixel;
}
inline constexpr std::uint16_t kSample0Pixels = 0xf;

// No default member initializers: a tile's buffer of packets is filled, not cleared first.
struct QuadPacket {
    std::int32_t x;  // even
    std::int32_t y;  // even
    std::uint16_t mask;
};

// Pixels a packet of a single-sample render covers.
inline int covered_pixels(std::span<const QuadPacket> quads) {
    int n = 0;
    for (const auto& q : quads) n += bit_count(q.mask & kSample0Pixels);
    return n;
}

inline constexpr int kTileSize = 64;
inline constexpr std::size_t kQuadsPerTile = (kTileSize / 2) * (kTileSize / 2);

// The covered pixels of the tile at (tx, ty) (both multiples of 64), given as one 64-bit mask a
// row (bit i: pixel tx + i), as single-sample quad packets, handed to emit(span) in one call.
template <class Emit>
void emit_tile_quads(const std::uint64_t* rows, int tx, int ty, Emit&& emit) {
    std::array<QuadPacket, kQuadsPerTile> quads;
    std::size_t n = 0;
    for (int r = 0; r < kTileSize; r += 2) {
        const std::uint64_t lo = rows[r];
        const std::uint64_t hi = rows[r + 1];
        std::uint64_t m = lo | hi;
        while (m != 0) {
            const int i = std::countr_zero(m) & ~1;
            const auto mask =
                static_cast<std::uint16_t>(((lo >> i) & 3u) | (((hi >> i) & 3u) << 2));
            quads[n++] = {tx + i, ty + r, mask};
            m &= ~(std::uint64_t{3} << i);
        }
    }
    if (n != 0) emit(std::span<const QuadPacket>(quads.data(), n));
}

// Four samples' rows of the tile at (tx, ty) (rows[s][r]: sample s of row ty + r) as quad
// packets with every sample's bit, handed to emit(span) in one call.
template <class Emit>
void emit_tile_quads_4x(const std::uint64_t (&rows)[4][kTileSize], int tx, int ty, Emit&& emit) {
    std::array<QuadPacket, kQuadsPerTile> quads;
    std::size_t n = 0;
    for (int r = 0; r < kTileSize; r += 2) {
        std::uint64_t m = 0;
        for (const auto& sr : rows) m |= sr[r] | sr[r + 1];
        while (m != 0) {
            const int i = std::countr_zero(m) & ~1;
            unsigned mask = 0;
            for (unsigned s = 0; s < kMaxSamples; ++s) {
                const std::uint64_t lo = rows[s][r] >> i;
                const std::uint64_t hi = rows[s][r + 1] >> i;
                for (unsigned p = 0; p < 4; ++p) {
                    const std::uint64_t row = p < 2 ? lo : hi;
                    if ((row >> (p & 1u)) & 1u) mask |= 1u << quad_bit(p, s);
                }
            }
            quads[n++] = {tx + i, ty + r, static_cast<std::uint16_t>(mask)};
            m &= ~(std::uint64_t{3} << i);
        }
    }
    if (n != 0) emit(std::span<const QuadPacket>(quads.data(), n));
}

// The same rows as runs of covered pixels: visit(y, x_begin, x_end), x_end exclusive.
template <class Visit>
void emit_tile_spans(const std::uint64_t* rows, int tx, int ty, Visit&& visit) {
    for (int r = 0; r < kTileSize; ++r) {
        std::uint64_t m = rows[r];
        while (m != 0) {
            const int start = std::countr_zero(m);
            const int len = std::countr_one(m >> start);
            visit(ty + r, tx + start, tx + start + len);
            m = start + len >= 64 ? 0 : m & ~((std::uint64_t{1} << (start + len)) - 1);
        }
    }
}

}  // namespace refraster::detail
