// vector_kernels_avx512.cpp: the vector fragment kernel (vector_kernel_body.hpp) and row-mask
// builder (vector_row_masks_body.hpp) compiled for AVX-512 (F, BW, DQ, VL) and FMA, 16 lanes
// with mask registers, called only on CPUs that report them (vector_kernels.cpp).
//
// Every header is included before the target pragma, so that nothing but this file's own
// functions is compiled for AVX-512.
//
// GCC 12 reports its own _mm512_undefined_* helpers, inlined into the intrinsics used here,
// as maybe uninitialized: a known false positive, silenced for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <type_traits>

#include "models/llvmpipe/fragment.hpp"
#include "models/llvmpipe/vector_kernels.hpp"
#include "stages/rules.hpp"
#include "stages/samples.hpp"

#if REFRASTER_VECTOR_KERNELS
#if defined(__clang__)
#pragma clang attribute push(                                                                     \
    __attribute__((target("avx512f,avx512bw,avx512dq,avx512vl,avx2,fma,bmi,bmi2,popcnt,lzcnt"))), \
    apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512bw,avx512dq,avx512vl,avx2,fma,bmi,bmi2,popcnt,lzcnt")
#endif

namespace refraster::detail::avx512 {

// 16 lanes; a lane mask is a 16-bit mask register.
struct V {
    static constexpr int kLanes = 16;
    // A masked store writes only its lanes without reading the line first (AVX-512's
    // vmovdqu32 with a mask register), so replacing covered pixels needs no load.
    static constexpr bool kCheapMaskedStore = true;
    using F = __m512;
    using I = __m512i;
    using M = __mmask16;

    static F splat(float v) { return _mm512_set1_ps(v); }
    static I splati(std::int32_t v) { return _mm512_set1_epi32(v); }
    static I splat16(std::int16_t v) { return _mm512_set1_epi16(v); }
    static F lane_index() {
        return _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    }

    static F add(F a, F b) { return _mm512_add_ps(a, b); }
    static F mul(F a, F b) { return _mm512_mul_ps(a, b); }
    static F div(F a, F b) { return _mm512_div_ps(a, b); }
    static F fma(F a, F b, F c) { return _mm512_fmadd_ps(a, b, c); }
    // vminps/vmaxps: the first operand if it compares less (greater), else the second.
    static F min(F a, F b) { return _mm512_min_ps(a, b); }
    static F max(F a, F b) { return _mm512_max_ps(a, b); }
    // vcvtps2dq: rounds in the current mode (MXCSR), nearest-even.
    static I to_int_rne(F a) { return _mm512_cvtps_epi32(a); }
    static I as_int(F a) { return _mm512_castps_si512(a); }
    static F as_float(I a) { return _mm512_castsi512_ps(a); }

    static M gt_f(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
    static M ge_f(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ); }
    static M lt_i(I a, I b) { return _mm512_cmplt_epi32_mask(a, b); }
    static M eq_i(I a, I b) { return _mm512_cmpeq_epi32_mask(a, b); }

    static M mask_if(bool on) { return static_cast<M>(on ? 0xffff : 0); }
    static M from_bits(unsigned bits) { return static_cast<M>(bits); }
    static bool none(M m) { return m == 0; }
    static M m_and(M a, M b) { return static_cast<M>(a & b); }
    static M m_or(M a, M b) { return static_cast<M>(a | b); }
    static M m_andnot(M a, M b) { return static_cast<M>(~a & b); }
    // Lanes of `b` where the mask is set, of `a` elsewhere.
    static I select(M m, I a, I b) { return _mm512_mask_blend_epi32(m, a, b); }

    static I and_i(I a, I b) { return _mm512_and_si512(a, b); }
    static I or_i(I a, I b) { return _mm512_or_si512(a, b); }
    static I sub32(I a, I b) { return _mm512_sub_epi32(a, b); }
    static I add32(I a, I b) { return _mm512_add_epi32(a, b); }
    static I mullo32(I a, I b) { return _mm512_mullo_epi32(a, b); }
    static I lane_index_i() {
        return _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    }
    // Bit i: the sign bit of lane i.
    static unsigned sign_bits(I a) { return _mm512_movepi32_mask(a); }
    static I sll32(I a, int n) { return _mm512_sll_epi32(a, _mm_cvtsi32_si128(n)); }
    static I srl32(I a, int n) { return _mm512_srl_epi32(a, _mm_cvtsi32_si128(n)); }
    static I add16(I a, I b) { return _mm512_add_epi16(a, b); }
    static I sub16(I a, I b) { return _mm512_sub_epi16(a, b); }
    static I mullo16(I a, I b) { return _mm512_mullo_epi16(a, b); }
    static I min_u16(I a, I b) { return _mm512_min_epu16(a, b); }
    static I sll16(I a, int n) { return _mm512_sll_epi16(a, _mm_cvtsi32_si128(n)); }
    static I srl16(I a, int n) { return _mm512_srl_epi16(a, _mm_cvtsi32_si128(n)); }
    static I adds_u8(I a, I b) { return _mm512_adds_epu8(a, b); }

    static I load(const std::uint32_t* p) { return _mm512_loadu_si512(p); }
    static void store(std::uint32_t* p, I v) { _mm512_storeu_si512(p, v); }
    static I load_masked(const std::uint32_t* p, M m) { return _mm512_maskz_loadu_epi32(m, p); }
    static void store_masked(std::uint32_t* p, M m, I v) { _mm512_mask_storeu_epi32(p, m, v); }
    // The 4x kernel's operations (shade_rows_4x): a float load, and lane idx[i] of v in lane i.
    static F load_f(const float* p) { return _mm512_loadu_ps(p); }
    static I permute(I v, I idx) { return _mm512_permutexvar_epi32(idx, v); }
    // The textured kernel's operations (vector_texture_body.hpp).
    static F sub(F a, F b) { return _mm512_sub_ps(a, b); }
    static F floor(F a) {
        return _mm512_roundscale_ps(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
    }
    // vcvttps2dq: truncates; 0x80000000 where the result does not fit (NaN too).
    static I to_int_trunc(F a) { return _mm512_cvttps_epi32(a); }
    static F to_float(I a) { return _mm512_cvtepi32_ps(a); }
    static M lt_f(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
    // Not less or equal: true for NaN.
    static M nle_f(F a, F b) { return _mm512_cmp_ps_mask(a, b, _CMP_NLE_UQ); }
    static F select_f(M m, F a, F b) { return _mm512_mask_blend_ps(m, a, b); }
    static I sra32(I a, int n) { return _mm512_sra_epi32(a, _mm_cvtsi32_si128(n)); }
    static I min_i32(I a, I b) { return _mm512_min_epi32(a, b); }
    static I max_i32(I a, I b) { return _mm512_max_epi32(a, b); }
    static I mulhrs16(I a, I b) { return _mm512_mulhrs_epi16(a, b); }
    // Lane 2k's value in lanes 2k and 2k + 1 (dup_odd: lane 2k + 1's).
    static F dup_even(F a) { return _mm512_moveldup_ps(a); }
    static F dup_odd(F a) { return _mm512_movehdup_ps(a); }
    // table[idx] for idx in 0..15: one permute.
    static I lookup16(const std::int32_t* table, I idx) {
        return _mm512_permutexvar_epi32(idx, _mm512_loadu_si512(table));
    }
    // base[idx] in the lanes of the mask, 0 elsewhere (nothing read there).
    static I gather(const std::uint32_t* base, I idx, M m) {
        return _mm512_mask_i32gather_epi32(_mm512_setzero_si512(), m, idx, base, 4);
    }
    // base[idx] = v in the lanes of the mask, in lane order (no two lanes share an index here).
    static void scatter(std::uint32_t* base, I idx, M m, I v) {
        _mm512_mask_i32scatter_epi32(base, m, idx, v, 4);
    }
};

#include "models/llvmpipe/vector_kernel_body.hpp"
#include "models/llvmpipe/vector_row_masks_body.hpp"
#include "models/llvmpipe/vector_texture_body.hpp"

// Instantiated here, inside the target region.
FragmentKernel::ShadeRowsFn pick(ShadeModel s, DepthFormat d, BlendPreset b, unsigned samples) {
    return pick_vector_kernel<V>(s, d, b, samples);
}
FragmentKernel::ShadeRowsFn pick_textured(ShadeModel s, DepthFormat d, BlendPreset b) {
    return pick_vector_textured_kernel<V>(s, d, b);
}
RowMaskFn row_masks() {
    return &vector_row_masks<V>;
}

}  // namespace refraster::detail::avx512

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

namespace refraster::detail {

// The entry points vector_kernels.cpp calls once the CPU has reported the instructions.
FragmentKernel::ShadeRowsFn avx512_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b,
                                              unsigned samples) {
    return avx512::pick(s, d, b, samples);
}

FragmentKernel::ShadeRowsFn avx512_textured_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b) {
    return avx512::pick_textured(s, d, b);
}

RowMaskFn avx512_row_masks() {
    return avx512::row_masks();
}

}  // namespace refraster::detail
#endif
