// output_merge.hpp: what every model does with a fragment once it has its colour and depth:
// the depth clamp, quantisation and compare, the colour conversion to the target's format,
// blending and the colour write, and the clear colour's conversion.
//
// Implements, as llvmpipe's generated code computes them (softpipe's own differences live in
// its model, softpipe_fragment.hpp): the depth clamp (lp_build_depth_clamp), the compare
// functions as GL's mask of passing outcomes, rgba8 conversion RNE(fl(c * 255)) of the
// clamped colour (lp_build_conv) or its truncation, the two blend presets in 8-bit fixed point
// (lp_bld_blend) or in float, glClearColor's float_to_ubyte. Inline where the kernels'
// run-time variants use them: those must not call out of their instruction set.
//
// Deliberately does not: evaluate planes or decide coverage (the models do), or stencil,
// colour masks and blend equations other than the two presets.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "common/float_ops.hpp"
#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"

namespace refraster::detail {

// The output merge shared by both models: conversion, blending and the colour write; float
// blending flushes denormals when `flush_denormals` is set, as llvmpipe's rasterizer does.
void write_fragment_color(const Draw& draw, Framebuffer& fb, std::size_t i,
                          const std::array<float, 4>& c, bool flush_denormals);

// glClearColor into rgba8: float_to_ubyte (util/u_math.h), which util_pack_color uses for
// R8G8B8A8_UNORM: f * (255/256) + 32768 in float, then the low byte of the float's bits.
std::uint8_t clear_to_unorm8(float c);

// Fragment depth clamped to [0, 1] as llvmpipe's generated code does it (lp_state_fs.c,
// lp_build_depth_clamp: lp_build_clamp(z, 0, 1), which is lp_build_min(z, 1) then
// lp_build_max(., 0), lowered to x86 minps/maxps: each returns its second operand unless the
// first compares less (greater)). A NaN depth therefore becomes 1 (the far value, in every
// depth format), -0 becomes +0, and infinities clamp to the ends. Inline: the kernels'
// run-time variants must not call out of their instruction set.
[[gnu::always_inline]] inline float clamp_depth(float z) {
    const float lo = z < 1.0f ? z : 1.0f;
    return lo > 0.0f ? lo : 0.0f;
}

// Fragment colour into rgba8: clamp to [0, 1], then RNE(fl(c * 255)) (lp_build_conv;
// docs/precision.md "Colour output and blending").
[[gnu::always_inline]] inline std::uint8_t color_to_unorm8(float c) {
    if (!(c > 0.0f)) return 0;
    if (c >= 1.0f) return 255;
    return static_cast<std::uint8_t>(round_to_nearest_even(c * 255.0f));
}

// The same with truncation instead of RNE (a profile's color_rounding=truncate).
[[gnu::always_inline]] inline std::uint8_t color_to_unorm8_truncated(float c) {
    if (!(c > 0.0f)) return 0;
    if (c >= 1.0f) return 255;
    return static_cast<std::uint8_t>(c * 255.0f);
}

// llvmpipe's 8-bit product (lp_build_mul_norm): (x*y + ((x*y) >> 8) + 128) >> 8.
constexpr std::uint8_t unorm8_mul(std::uint32_t x, std::uint32_t y) {
    const std::uint32_t p = x * y;
    return static_cast<std::uint8_t>((p + (p >> 8) + 128) >> 8);
}

// GL's encoding of the compare functions is a mask of the outcomes that pass: 1 less, 2 equal,
// 4 greater (GL_NEVER 0x200 ... GL_ALWAYS 0x207); the enum keeps that order.
static_assert(
    static_cast<int>(CompareFunc::Never) == 0 && static_cast<int>(CompareFunc::Less) == 1 &&
    static_cast<int>(CompareFunc::Equal) == 2 && static_cast<int>(CompareFunc::Lequal) == 3 &&
    static_cast<int>(CompareFunc::Greater) == 4 && static_cast<int>(CompareFunc::NotEqual) == 5 &&
    static_cast<int>(CompareFunc::Gequal) == 6 && static_cast<int>(CompareFunc::Always) == 7);

// The outcome of comparing a fragment's depth with the stored one. z32f values are compared as
// floats (both are in [0, 1], so their bit patterns order the same way, but the intent is kept
// explicit); neither less nor equal counts as greater, as GREATER, NOTEQUAL and GEQUAL are
// decided (!lt && !eq, !eq, !lt). With `daz` a denormal compares as zero: llvmpipe's depth test
// runs under the rasterizer's denormals-are-zero mode (lp_rast.c), which a cleared depth such
// as 1e-40 meets (measured: the scene extreme.z32f_denormal_clear).
template <bool kFloat>
[[gnu::always_inline]] inline unsigned depth_outcome(std::uint32_t frag, std::uint32_t stored,
                                                     bool daz) {
    if constexpr (kFloat) {
        float f = std::bit_cast<float>(frag);
        float s = std::bit_cast<float>(stored);
        if (daz) {
            f = flush_denormal(f);
            s = flush_denormal(s);
        }
        return f < s ? 1u : f == s ? 2u : 4u;
    } else {
        (void)daz;
        return frag < stored ? 1u : frag == stored ? 2u : 4u;
    }
}

inline bool depth_passes(CompareFunc f, std::uint32_t frag, std::uint32_t stored, bool is_float) {
    const unsigned outcome = is_float ? depth_outcome<true>(frag, stored, false)
                                      : depth_outcome<false>(frag, stored, false);
    return (static_cast<unsigned>(f) & outcome) != 0;
}

// The source colour as the output merge receives it: rgba8 bytes (lp_build_conv) or floats.
template <ColorFormat C>
using SourceColor =
    std::conditional_t<C == ColorFormat::Rgba8, std::array<std::uint8_t, 4>, std::array<float, 4>>;

template <ColorFormat C>
[[gnu::always_inline]] inline SourceColor<C> source_color(bool truncate,
                                                          const std::array<float, 4>& c) {
    if constexpr (C == ColorFormat::Rgba8) {
        SourceColor<C> s{};
        for (std::size_t k = 0; k < 4; ++k)
            s[k] = truncate ? color_to_unorm8_truncated(c[k]) : color_to_unorm8(c[k]);
        return s;
    } else {
        return c;
    }
}

// Blending and the colour write of pixel `i` (lp_bld_blend; docs/precision.md "Colour output
// and blending").
template <ColorFormat C, BlendPreset B>
[[gnu::always_inline]] inline void store_color(Framebuffer& fb, std::size_t i,
                                               const SourceColor<C>& s, const Fp& fp) {
    if constexpr (C == ColorFormat::Rgba8) {
        std::uint8_t* d = fb.color8.data() + 4 * i;
        if constexpr (B == BlendPreset::None) {
            std::memcpy(d, s.data(), 4);
        } else if constexpr (B == BlendPreset::Alpha) {
            const std::uint32_t a = s[3];
            for (std::size_t k = 0; k < 4; ++k) {
                const std::uint32_t v =
                    std::uint32_t{unorm8_mul(s[k], a)} + unorm8_mul(d[k], 255 - a);
                d[k] = static_cast<std::uint8_t>(std::min<std::uint32_t>(v, 255));
            }
        } else {
            for (std::size_t k = 0; k < 4; ++k) {
                d[k] = static_cast<std::uint8_t>(
                    std::min<std::uint32_t>(std::uint32_t{s[k]} + d[k], 255));
            }
        }
    } else {
        // The blend runs in the rasterizer's threads under FTZ/DAZ (lp_rast.c), so a subnormal
        // source, alpha or destination counts as zero there; without blending the colour is
        // only moved and keeps its bits.
        float* d = fb.color32f.data() + 4 * i;
        if constexpr (B == BlendPreset::None) {
            std::copy(s.begin(), s.end(), d);
        } else if constexpr (B == BlendPreset::Alpha) {
            const float a = s[3];
            const float inv = fp.sub(1.0f, a);
            for (std::size_t k = 0; k < 4; ++k) d[k] = fp.add(fp.mul(s[k], a), fp.mul(d[k], inv));
        } else {
            for (std::size_t k = 0; k < 4; ++k) d[k] = fp.add(s[k], d[k]);
        }
    }
}

}  // namespace refraster::detail
