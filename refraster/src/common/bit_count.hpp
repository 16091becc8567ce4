// bit_count.hpp: the number of set bits in a coverage mask, inline on every x86-64.
//
// Implements: bit_count, the SWAR sum of bits (pairs, nibbles, bytes, then one multiply to add
// the eight byte counts; Hacker's Delight, section 5-1). Baseline x86-64 has no POPCNT
// instruction, so GCC compiles std::popcount outside the kernels' translation units into a call
// to libgcc's __popcountdi2, which took 3% of a medium-triangle render's samples when the
// traversal counted its pixels with it.
//
// Deliberately does not: choose POPCNT when the translation unit could use it. An inline
// function compiled two ways in two units is one symbol to the linker, which may keep the
// POPCNT copy for callers on a CPU without it.
#pragma once

#include <cstdint>

namespace refraster::detail {

constexpr int bit_count(std::uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555u);
    x = (x & 0x3333333333333333u) + ((x >> 2) & 0x3333333333333333u);
    x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fu;
    return static_cast<int>((x * 0x0101010101010101u) >> 56);
}

static_assert(bit_count(0) == 0 && bit_count(~std::uint64_t{0}) == 64 &&
              bit_count(0x8000000000000001u) == 2 && bit_count(0xf0f0u) == 8);

}  // namespace refraster::detail
