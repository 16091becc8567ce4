// vector_kernels_avx2.cpp: the vector fragment kernel (vector_kernel_body.hpp) and row-mask
// builder (vector_row_masks_body.hpp) compiled for AVX2 and FMA, 8 lanes, called only on CPUs
// that report both (vector_kernels.cpp).
//
// Every header is included before the target pragma, so that nothing but this file's own
// functions is compiled for AVX2: inline functions of the headers keep the baseline
// instruction set and can never be picked for a CPU without AVX2.
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
#pragma clang attribute push(__attribute__((target("avx2,fma,bmi,bmi2,popcnt,lzcnt"))), \
                             apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2,fma,bmi,bmi2,popcnt,lzcnt")
#endif

namespace refraster::detail::avx2 {

// 8 lanes; a lane mask is a vector of all-ones or all-zeros lanes.
struct V {
    static constexpr int kLanes = 8;
    // vpmaskmovd's store form is microcoded on several AMD cores: a full store of a select
    // is kept where every lane lies in the row.
    static constexpr bool kCheapMaskedStore = false;
    using F = __m256;
    using I = __m256i;
    using M = __m256i;

    static F splat(float v) { return _mm256_set1_ps(v); }
    static I splati(std::int32_t v) { return _mm256_set1_epi32(v); }
    static I splat16(std::int16_t v) { return _mm256_set1_epi16(v); }
    static F lane_index() { return _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7); }

    static F add(F a, F b) { return _mm256_add_ps(a, b); }
    static F mul(F a, F b) { return _mm256_mul_ps(a, b); }
    static F div(F a, F b) { return _mm256_div_ps(a, b); }
    static F fma(F a, F b, F c) { return _mm256_fmadd_ps(a, b, c); }
    // minps/maxps: the first operand if it compares less (greater), else the second.
    static F min(F a, F b) { return _mm256_min_ps(a, b); }
    static F max(F a, F b) { return _mm256_max_ps(a, b); }
    // cvtps2dq: rounds in the current mode, nearest-even.
    static I to_int_rne(F a) { return _mm256_cvtps_epi32(a); }
    static I as_int(F a) { return _mm256_castps_si256(a); }
    static F as_float(I a) { return _mm256_castsi256_ps(a); }

    static M gt_f(F a, F b) { return as_int(_mm256_cmp_ps(a, b, _CMP_GT_OQ)); }
    static M ge_f(F a, F b) { return as_int(_mm256_cmp_ps(a, b, _CMP_GE_OQ)); }
    static M lt_i(I a, I b) { return _mm256_cmpgt_epi32(b, a); }
    static M eq_i(I a, I b) { return _mm256_cmpeq_epi32(a, b); }

    static M mask_if(bool on) { return _mm256_set1_epi32(on ? -1 : 0); }
    static M from_bits(unsigned bits) {
        const I sel = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(bits)), sel),
                                  sel);
    }
    static bool none(M m) { return _mm256_testz_si256(m, m) != 0; }
    static M m_and(M a, M b) { return _mm256_and_si256(a, b); }
    static M m_or(M a, M b) { return _mm256_or_si256(a, b); }
    static M m_andnot(M a, M b) { return _mm256_andnot_si256(a, b); }  // ~a & b
    // Lanes of `b` where the mask is set, of `a` elsewhere.
    static I select(M m, I a, I b) { return _mm256_blendv_epi8(a, b, m); }

    static I and_i(I a, I b) { return _mm256_and_si256(a, b); }
    static I or_i(I a, I b) { return _mm256_or_si256(a, b); }
    static I sub32(I a, I b) { return _mm256_sub_epi32(a, b); }
    static I add32(I a, I b) { return _mm256_add_epi32(a, b); }
    static I mullo32(I a, I b) { return _mm256_mullo_epi32(a, b); }
    static I lane_index_i() { return _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7); }
    // Bit i: the sign bit of lane i.
    static unsigned sign_bits(I a) {
        return static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(a)));
    }
    static I sll32(I a, int n) { return _mm256_sll_epi32(a, _mm_cvtsi32_si128(n)); }
    static I srl32(I a, int n) { return _mm256_srl_epi32(a, _mm_cvtsi32_si128(n)); }
    static I add16(I a, I b) { return _mm256_add_epi16(a, b); }
    static I sub16(I a, I b) { return _mm256_sub_epi16(a, b); }
    static I mullo16(I a, I b) { return _mm256_mullo_epi16(a, b); }
    static I min_u16(I a, I b) { return _mm256_min_epu16(a, b); }
    static I sll16(I a, int n) { return _mm256_sll_epi16(a, _mm_cvtsi32_si128(n)); }
    static I srl16(I a, int n) { return _mm256_srl_epi16(a, _mm_cvtsi32_si128(n)); }
    static I adds_u8(I a, I b) { return _mm256_adds_epu8(a, b); }

    static I load(const std::uint32_t* p) {
        return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
    }
    static void store(std::uint32_t* p, I v) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v);
    }
    static I load_masked(const std::uint32_t* p, M m) {
        return _mm256_maskload_epi32(reinterpret_cast<const int*>(p), m);
    }
    static void store_masked(std::uint32_t* p, M m, I v) {
        _mm256_maskstore_epi32(reinterpret_cast<int*>(p), m, v);
    }
    // The 4x kernel's operations (shade_rows_4x): a float load, and lane idx[i] of v in lane i.
    static F load_f(const float* p) { return _mm256_loadu_ps(p); }
    static I permute(I v, I idx) { return _mm256_permutevar8x32_epi32(v, idx); }
    // The textured kernel's operations (vector_texture_body.hpp).
    static F sub(F a, F b) { return _mm256_sub_ps(a, b); }
    static F floor(F a) { return _mm256_floor_ps(a); }
    // cvttps2dq: truncates; 0x80000000 where the result does not fit (NaN too).
    static I to_int_trunc(F a) { return _mm256_cvttps_epi32(a); }
    static F to_float(I a) { return _mm256_cvtepi32_ps(a); }
    static M lt_f(F a, F b) { return as_int(_mm256_cmp_ps(a, b, _CMP_LT_OQ)); }
    // Not less or equal: true for NaN.
    static M nle_f(F a, F b) { return as_int(_mm256_cmp_ps(a, b, _CMP_NLE_UQ)); }
    static F select_f(M m, F a, F b) { return _mm256_blendv_ps(a, b, as_float(m)); }
    static I sra32(I a, int n) { return _mm256_sra_epi32(a, _mm_cvtsi32_si128(n)); }
    static I min_i32(I a, I b) { return _mm256_min_epi32(a, b); }
    static I max_i32(I a, I b) { return _mm256_max_epi32(a, b); }
    static I mulhrs16(I a, I b) { return _mm256_mulhrs_epi16(a, b); }
    // Lane 2k's value in lanes 2k and 2k + 1 (dup_odd: lane 2k + 1's).
    static F dup_even(F a) { return _mm256_moveldup_ps(a); }
    static F dup_odd(F a) { return _mm256_movehdup_ps(a); }
    // table[idx] for idx in 0..15: a permute of each half, the half idx names.
    static I lookup16(const std::int32_t* table, I idx) {
        const I low = _mm256_permutevar8x32_epi32(
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(table)), idx);
        const I high = _mm256_permutevar8x32_epi32(
            _mm256_loadu_si256(reinterpret_cast<const __m256i*>(table + 8)), idx);
        return select(_mm256_cmpgt_epi32(idx, _mm256_set1_epi32(7)), low, high);
    }
    // base[idx] in the lanes of the mask, 0 elsewhere (nothing read there).
    static I gather(const std::uint32_t* base, I idx, M m) {
        return _mm256_mask_i32gather_epi32(_mm256_setzero_si256(),
                                           reinterpret_cast<const int*>(base), idx, m, 4);
    }
    // base[idx] = v in the lanes of the mask, in lane order (AVX2 has no scatter).
    static void scatter(std::uint32_t* base, I idx, M m, I v) {
        alignas(32) std::int32_t at[kLanes];
        alignas(32) std::uint32_t value[kLanes];
        store(reinterpret_cast<std::uint32_t*>(at), idx);
        store(value, v);
        for (unsigned bits = sign_bits(m); bits != 0; bits &= bits - 1) {
            const int l = std::countr_zero(bits);
            base[at[l]] = value[l];
        }
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

}  // namespace refraster::detail::avx2

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif

namespace refraster::detail {

// The entry points vector_kernels.cpp calls once the CPU has reported the instructions.
FragmentKernel::ShadeRowsFn avx2_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b,
                                            unsigned samples) {
    return avx2::pick(s, d, b, samples);
}

FragmentKernel::ShadeRowsFn avx2_textured_shade_rows(ShadeModel s, DepthFormat d, BlendPreset b) {
    return avx2::pick_textured(s, d, b);
}

RowMaskFn avx2_row_masks() {
    return avx2::row_masks();
}

}  // namespace refraster::detail
#endif
