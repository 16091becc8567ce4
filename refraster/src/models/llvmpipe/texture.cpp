#include "models/llvmpipe/texture.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "common/float_ops.hpp"
#include "models/llvmpipe/vector_kernels.hpp"
#include "refraster/assert.hpp"
#include "refraster/fixed.hpp"
#include "stages/output_merge.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define REFRASTER_SAMPLER_ISA_VARIANTS 1
#else
#define REFRASTER_SAMPLER_ISA_VARIANTS 0
#endif

namespace refraster::detail {

namespace {

constexpr std::int32_t kIndefinite = std::numeric_limits<std::int32_t>::min();

// cvttps2dq of floor(x) (lp_build_ifloor with SSE4.1 rounding): INT32_MIN when the result does
// not fit, as the instruction gives it.
std::int32_t ifloor(float x) {
    const float f = std::floor(x);
    if (!(f >= -2147483648.0f && f < 2147483648.0f)) return kIndefinite;
    return static_cast<std::int32_t>(f);
}

// cvttps2dq (lp_build_itrunc).
std::int32_t itrunc(float x) {
    const float f = std::trunc(x);
    if (!(f >= -2147483648.0f && f < 2147483648.0f)) return kIndefinite;
    return static_cast<std::int32_t>(f);
}

// 32-bit wrapping subtraction, as the vector integer instructions do it.
std::int32_t sub_wrap(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
}

// The largest float below 1 (lp_build_fract_safe's clamp).
constexpr float kBelowOne = 0x1.fffffep-1f;

bool is_pot(std::uint32_t v) {
    return v != 0 && (v & (v - 1)) == 0;
}

// The byte lerp of the 8-bit path: a + floor((w * (b - a) + 128) / 256) for a weight w in
// units of 1/256 (lp_build_lerp on 8.8 values, pmulhrsw's rounding: lp_bld_arit.c,
// lp_build_lerp_simple with the SSSE3 path; docs/precision.md "Textures").
std::int32_t lerp8(std::int32_t w, std::int32_t a, std::int32_t b) {
    return a + ((w * (b - a) + 128) >> 8);
}

// lp_bld_sample_soa.c, lp_build_coord_mirror: |2 * (u/2 - round(u/2))|, in float, round to
// nearest even, then a max with 0 that turns a NaN into 0 (GALLIVM_NAN_RETURN_OTHER_SECOND_NONNAN).
float mirror(float u) {
    const float h = u * 0.5f;
    const float d = h - round_to_nearest_even(h);
    const float m = std::fabs(d + d);
    return std::isnan(m) ? 0.0f : m;
}

// Texel coordinates and weights of one axis of one level.
struct AxisNearest {
    std::int32_t i = 0;
    bool border = false;
};
struct AxisLinear {
    std::int32_t i0 = 0;
    std::int32_t i1 = 0;
    bool border0 = false;
    bool border1 = false;
    std::int32_t w8 = 0;  // 8-bit path, units of 1/256
    float w = 0.0f;       // float path
};

// lp_bld_sample_aos.c, lp_build_sample_wrap_nearest_int / the float path's
// lp_build_sample_wrap_nearest for repeat and clamp-to-edge: the texel floor(u * n), wrapped.
// Repeat of a size that is not a power of two takes the fraction first.
std::int32_t nearest_repeat_or_edge(float u, std::int32_t n, bool pot, TextureWrap wrap) {
    const float nf = static_cast<float>(n);
    if (wrap == TextureWrap::Repeat) {
        if (pot) return ifloor(u * nf) & (n - 1);
        // lp_build_fract_safe: the fraction, then lp_build_min_ext with
        // GALLIVM_NAN_RETURN_OTHER (minps(f, 1 - 2^-24)): a NaN fraction becomes 1 - 2^-24,
        // the last texel.
        const float f0 = u - std::floor(u);
        const float f = f0 < kBelowOne ? f0 : kBelowOne;
        return itrunc(f * nf);
    }
    return std::clamp(ifloor(u * nf), 0, n - 1);
}

AxisNearest nearest_aos(float u, std::int32_t n, bool pot, TextureWrap wrap) {
    return {nearest_repeat_or_edge(u, n, pot, wrap), false};
}

// lp_bld_sample_aos.c, lp_build_sample_wrap_linear_int: 8.8 fixed point from
// cvtps2dq(u * (n * 256)) - 128 (round to nearest even), the texel its high part, the weight its
// low byte.
AxisLinear linear_aos(float u, std::int32_t n, bool pot, TextureWrap wrap) {
    AxisLinear a;
    if (wrap == TextureWrap::Repeat && !pot) {
        // lp_build_coord_repeat_npot_linear_int: the fraction scaled by n, then by 256.
        const float f = u - std::floor(u);
        const float scaled = (f * static_cast<float>(n)) * 256.0f;
        const std::int32_t s = sub_wrap(round_nearest_even_or_indefinite(scaled), 128);
        a.w8 = s & 255;
        std::int32_t i0 = s >> 8;
        if (i0 < 0) i0 = n - 1;
        i0 = std::min(i0, n - 1);
        a.i0 = i0;
        a.i1 = i0 == n - 1 ? 0 : i0 + 1;
        return a;
    }
    const float size256 = static_cast<float>(n * 256);  // exact: n <= 4096
    const std::int32_t s = sub_wrap(round_nearest_even_or_indefinite(u * size256), 128);
    a.w8 = s & 255;
    const std::int32_t i0 = s >> 8;
    if (wrap == TextureWrap::Repeat) {
        a.i0 = i0 & (n - 1);
        a.i1 = (i0 + 1) & (n - 1);
    } else {
        a.i0 = std::clamp(i0, 0, n - 1);
        a.i1 = std::clamp(i0 + 1, 0, n - 1);
    }
    return a;
}

// lp_bld_sample_soa.c, lp_build_sample_wrap_nearest.
AxisNearest nearest_soa(float u, std::int32_t n, bool pot, TextureWrap wrap) {
    const float nf = static_cast<float>(n);
    switch (wrap) {
        case TextureWrap::Repeat:
        case TextureWrap::ClampToEdge:
            return {nearest_repeat_or_edge(u, n, pot, wrap), false};
        case TextureWrap::MirroredRepeat:
            return {std::min(itrunc(mirror(u) * nf), n - 1), false};
        case TextureWrap::ClampToBorder: {
            // The texel floor(u * n), unclamped: outside the image it reads the border colour
            // (lp_build_sample_texel_soa's use_border).
            const std::int32_t i = ifloor(u * nf);
            return {i, i < 0 || i >= n};
        }
    }
    return {};
}

// lp_bld_sample_soa.c, lp_build_sample_wrap_linear.
AxisLinear linear_soa(float u, std::int32_t n, bool pot, TextureWrap wrap) {
    const float nf = static_cast<float>(n);
    AxisLinear a;
    float c = 0.0f;
    bool npot_repeat_below = false;
    switch (wrap) {
        case TextureWrap::Repeat:
            if (pot) {
                c = u * nf - 0.5f;
            } else {
                c = (u - std::floor(u)) * nf - 0.5f;
                npot_repeat_below = c < 0.0f;
            }
            break;
        case TextureWrap::ClampToEdge: {
            // lp_build_min_ext with NaN returning the size, then max with 0.
            const float x = u * nf;
            c = std::max((x < nf ? x : nf) - 0.5f, 0.0f);
            break;
        }
        case TextureWrap::MirroredRepeat:
            c = mirror(u) * nf - 0.5f;
            break;
        case TextureWrap::ClampToBorder:
            // No clamp: texels outside the image read the border colour.
            c = u * nf - 0.5f;
            break;
    }
    const float fl = std::floor(c);
    a.w = c - fl;
    std::int32_t i0 = ifloor(c);
    std::int32_t i1 = i0 + (i0 == kIndefinite ? 0 : 1);
    switch (wrap) {
        case TextureWrap::Repeat:
            if (pot) {
                i0 &= n - 1;
                i1 &= n - 1;
            } else {
                if (npot_repeat_below) i0 = n - 1;
                i1 = i0 == n - 1 ? 0 : i0 + 1;
            }
            break;
        case TextureWrap::ClampToEdge:
            i1 = std::min(i1, n - 1);
            break;
        case TextureWrap::MirroredRepeat:
            i0 = std::max(i0, 0);
            i1 = std::min(i1, n - 1);
            break;
        case TextureWrap::ClampToBorder:
            a.border0 = i0 < 0 || i0 >= n;
            a.border1 = i1 < 0 || i1 >= n;
            break;
    }
    a.i0 = i0;
    a.i1 = i1;
    return a;
}

struct LevelView {
    const TextureImage* image;
    std::int32_t w;
    std::int32_t h;
    // A texel's bytes. Coordinates outside the image happen only where the rules above leave
    // the driver reading memory it does not own (never for coordinates a wrap keeps inside);
    // they are clamped so that no read leaves the image.
    const std::uint8_t* texel(std::int32_t x, std::int32_t y) const {
        x = std::clamp(x, 0, w - 1);
        y = std::clamp(y, 0, h - 1);
        return image->rgba.data() + 4 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                                         static_cast<std::size_t>(x));
    }
};

// One level sampled by the 8-bit path: bytes.
std::array<std::uint8_t, 4> sample_level_aos(const TextureUnit& u, const LevelView& lv, float s,
                                             float t, bool linear, TexelSample* tr,
                                             std::size_t slot) {
    std::array<std::uint8_t, 4> out{};
    const auto& st = u.state;
    if (!linear) {
        const AxisNearest x = nearest_aos(s, lv.w, u.pot_s, st.wrap_s);
        const AxisNearest y = nearest_aos(t, lv.h, u.pot_t, st.wrap_t);
        const std::uint8_t* p = lv.texel(x.i, y.i);
        std::copy(p, p + 4, out.begin());
        if (tr != nullptr) tr->texels[slot] = {x.i, x.i, y.i, y.i};
        return out;
    }
    const AxisLinear x = linear_aos(s, lv.w, u.pot_s, st.wrap_s);
    const AxisLinear y = linear_aos(t, lv.h, u.pot_t, st.wrap_t);
    const std::uint8_t* t00 = lv.texel(x.i0, y.i0);
    const std::uint8_t* t10 = lv.texel(x.i1, y.i0);
    const std::uint8_t* t01 = lv.texel(x.i0, y.i1);
    const std::uint8_t* t11 = lv.texel(x.i1, y.i1);
    for (std::size_t c = 0; c < 4; ++c) {
        // Along s first, then along t (lp_build_lerp_2d).
        const std::int32_t r0 = lerp8(x.w8, t00[c], t10[c]);
        const std::int32_t r1 = lerp8(x.w8, t01[c], t11[c]);
        out[c] = static_cast<std::uint8_t>(lerp8(y.w8, r0, r1));
    }
    if (tr != nullptr) {
        tr->texels[slot] = {x.i0, x.i1, y.i0, y.i1};
        tr->weights[slot] = {static_cast<float>(x.w8), static_cast<float>(y.w8)};
    }
    return out;
}

// The shader's float lerp: a + w * (b - a), fused on an FMA CPU (lp_build_lerp through
// lp_build_fmuladd).
float lerp_float(float w, float a, float b, bool fma) {
    const float d = b - a;
    return fma ? fused_multiply_add(w, d, a) : a + w * d;
}

// One level sampled by the float path: floats.
std::array<float, 4> sample_level_soa(const TextureUnit& u, const LevelView& lv, float s, float t,
                                      bool linear, bool both, bool fma, TexelSample* tr,
                                      std::size_t slot) {
    const auto& st = u.state;
    // Texels as floats, the border colour where the wrap says so (lp_build_sample_texel_soa).
    const auto fetch = [&](std::int32_t x, std::int32_t y, bool border) {
        std::array<float, 4> v{};
        if (border) {
            for (std::size_t c = 0; c < 4; ++c) {
                const float b =
                    u.flush_border ? flush_denormal(st.border_color[c]) : st.border_color[c];
                // maxps(b, 0) then minps(., 1): the second operand unless the first compares
                // greater (smaller), so -0 becomes +0.
                const float lo = b > 0.0f ? b : 0.0f;
                v[c] = lo < 1.0f ? lo : 1.0f;
            }
            return v;
        }
        const std::uint8_t* p = lv.texel(x, y);
        for (std::size_t c = 0; c < 4; ++c) v[c] = unorm8_to_float(p[c]);
        return v;
    };
    if (!linear && !both) {
        const AxisNearest x = nearest_soa(s, lv.w, u.pot_s, st.wrap_s);
        const AxisNearest y = nearest_soa(t, lv.h, u.pot_t, st.wrap_t);
        if (tr != nullptr) {
            tr->texels[slot] = {x.i, x.i, y.i, y.i};
            tr->border[slot] = {x.border || y.border, false, false, false};
        }
        return fetch(x.i, y.i, x.border || y.border);
    }
    AxisLinear x = linear_soa(s, lv.w, u.pot_s, st.wrap_s);
    AxisLinear y = linear_soa(t, lv.h, u.pot_t, st.wrap_t);
    if (!linear) {
        // lp_build_sample_mipmap_both: a quad that takes the nearest filter runs the linear
        // one with each weight replaced by (weight > 0.5 ? 1 : 0).
        // (lp_build_cmp, unordered: a NaN weight becomes 1.)
        x.w = !(x.w <= 0.5f) ? 1.0f : 0.0f;
        y.w = !(y.w <= 0.5f) ? 1.0f : 0.0f;
    }
    const auto t00 = fetch(x.i0, y.i0, x.border0 || y.border0);
    const auto t10 = fetch(x.i1, y.i0, x.border1 || y.border0);
    const auto t01 = fetch(x.i0, y.i1, x.border0 || y.border1);
    const auto t11 = fetch(x.i1, y.i1, x.border1 || y.border1);
    std::array<float, 4> out{};
    for (std::size_t c = 0; c < 4; ++c) {
        const float r0 = lerp_float(x.w, t00[c], t10[c], fma);
        const float r1 = lerp_float(x.w, t01[c], t11[c], fma);
        out[c] = lerp_float(y.w, r0, r1, fma);
    }
    if (tr != nullptr) {
        tr->texels[slot] = {x.i0, x.i1, y.i0, y.i1};
        tr->weights[slot] = {x.w, y.w};
        tr->border[slot] = {x.border0 || y.border0, x.border1 || y.border0, x.border0 || y.border1,
                            x.border1 || y.border1};
    }
    return out;
}

LevelView level_view(const TextureUnit& u, std::uint32_t level) {
    const TextureImage& img = (*u.levels)[level];
    return {&img, static_cast<std::int32_t>(img.width), static_cast<std::int32_t>(img.height)};
}

// The LOD decisions of a quad (lp_bld_sample.c, lp_build_rho and lp_build_lod_selector, with
// GALLIVM_PERF's brilinear off, rho_approx as the profile says, no bias, no LOD clamps).
struct QuadLod {
    bool minified = false;
    std::uint32_t level0 = 0;
    std::uint32_t level1 = 0;
    float frac = 0.0f;       // between level0 and level1 (trilinear)
    std::int32_t frac8 = 0;  // the same in units of 1/256, truncated (8-bit path)
    float rho2 = 0.0f;
    float lod = 0.0f;
    std::array<float, 4> terms{};
};

// Whether a filter's image filter is linear.
bool is_linear(TextureFilter f) {
    return f == TextureFilter::Linear || f == TextureFilter::LinearMipmapNearest ||
           f == TextureFilter::LinearMipmapLinear;
}

// x86 maxps: the second operand unless the first compares greater.
float max_ps(float a, float b) {
    return a > b ? a : b;
}

// lp_build_linear_mip_levels: the two levels from the lod's integer part, both clamped to
// [0, last] with the weight zeroed there; then lp_build_sample_mipmap's clamp of a negative
// weight (brilinear's) to 0 before the levels blend.
void split_levels(const TextureUnit& u, QuadLod& q, std::int32_t level0, float frac) {
    const auto last = static_cast<std::int32_t>(u.last_level);
    std::int32_t l0 = level0;
    std::int32_t l1 = level0 + 1;
    if (level0 < 0) {
        l0 = l1 = 0;
        frac = 0.0f;
    } else if (level0 >= last) {
        l0 = l1 = last;
        frac = 0.0f;
    }
    frac = max_ps(frac, 0.0f);
    q.level0 = static_cast<std::uint32_t>(l0);
    q.level1 = static_cast<std::uint32_t>(l1);
    q.frac = frac;
    q.frac8 = itrunc(frac * 256.0f);
}

QuadLod quad_lod(const TextureUnit& u, const std::array<float, 4>& s,
                 const std::array<float, 4>& t) {
    QuadLod q;
    if (!u.needs_lod) return q;
    const bool nearest_level = u.state.min_filter == TextureFilter::NearestMipmapNearest ||
                               u.state.min_filter == TextureFilter::LinearMipmapNearest;
    const auto last = static_cast<std::int32_t>(u.last_level);
    if (u.rho_approx) {
        // lp_build_rho without no_rho_approx (the packed quad path, eight-wide vectors): the
        // absolute differences, the larger of x and y per coordinate (maxps), scaled to
        // base-level texels, then the larger of s and t. lp_build_lod_selector then takes
        // rho itself where no level is interpolated (ilog2: the exponent of rho * sqrt(2), and
        // minified when rho > 1), and squares it where one is (fast_log2(rho * rho) / 2).
        const float ds = max_ps(std::fabs(s[1] - s[0]), std::fabs(s[2] - s[0])) * u.base_width;
        const float dt = max_ps(std::fabs(t[1] - t[0]), std::fabs(t[2] - t[0])) * u.base_height;
        const float rho = max_ps(ds, dt);
        q.terms = {s[1] - s[0], t[1] - t[0], s[2] - s[0], t[2] - t[0]};
        const bool linear_levels = u.mipmapped && !nearest_level;
        if (!linear_levels) {
            q.rho2 = rho * rho;
            q.minified = !(rho <= 1.0f);
            if (!q.minified || !u.mipmapped) return q;
            constexpr float kSqrt2 = 1.41421356237309504880f;  // M_SQRT2 as a float constant
            const auto bits = std::bit_cast<std::uint32_t>(rho * kSqrt2);
            const std::int32_t level =
                std::clamp(static_cast<std::int32_t>((bits >> 23) & 0xffu) - 127, 0, last);
            q.level0 = q.level1 = static_cast<std::uint32_t>(level);
            return q;
        }
        q.rho2 = rho * rho;
        if (u.brilinear) {
            // lp_build_brilinear_rho (BRILINEAR_FACTOR 2), taken when rho is not squared: rho
            // scaled by (2 * 2 - 0.5) / (sqrt(2) * 2) (a double constant made float), the
            // exponent as the level, the mantissa m in [1, 2) as the weight 2m - 3 (the mad is
            // exact either way); minified when rho > 1.
            constexpr float kPre =
                static_cast<float>((2.0 * 2.0 - 0.5) / (1.41421356237309504880 * 2.0));
            q.minified = !(rho <= 1.0f);
            if (!q.minified) return q;
            const auto rb = std::bit_cast<std::uint32_t>(rho * kPre);
            const float m = std::bit_cast<float>((rb & 0x7fffffu) | 0x3f800000u);
            const std::int32_t ipart = static_cast<std::int32_t>((rb >> 23) & 0xffu) - 127;
            const float fpart = m * 2.0f - 3.0f;
            q.lod = static_cast<float>(ipart) + fpart;
            split_levels(u, q, ipart, fpart);
            return q;
        }
    } else {
        // Differences of the coordinates first, then scaled to base-level texels.
        const float dsdx = u.base_width * (s[1] - s[0]);
        const float dtdx = u.base_height * (t[1] - t[0]);
        const float dsdy = u.base_width * (s[2] - s[0]);
        const float dtdy = u.base_height * (t[2] - t[0]);
        q.terms = {dsdx, dtdx, dsdy, dtdy};
        const float rx = dsdx * dsdx + dtdx * dtdx;
        const float ry = dsdy * dsdy + dtdy * dtdy;
        q.rho2 = max_ps(rx, ry);
    }
    // lp_build_cmp compares unordered: a NaN rho counts as minified.
    q.minified = !(q.rho2 <= 1.0f);
    if (!q.minified || !u.mipmapped) return q;
    const auto bits = std::bit_cast<std::uint32_t>(q.rho2);
    const auto e = static_cast<std::int32_t>((bits >> 23) & 0xffu);
    if (nearest_level) {
        // The level nearest log2(rho) from the exponent of rho squared (lp_build_ilog2 of
        // rho squared, halved with an offset): level k for rho2 in [2^(2k-1), 2^(2k+1)).
        const std::int32_t level = std::clamp((e - 126) >> 1, 0, last);
        q.level0 = q.level1 = static_cast<std::uint32_t>(level);
        return q;
    }
    // lp_build_fast_log2: (exponent - 1) + mantissa in [1, 2), then halved for rho.
    const float mantissa = std::bit_cast<float>((bits & 0x7fffffu) | 0x3f800000u);
    q.lod = (static_cast<float>(e - 128) + mantissa) * 0.5f;
    if (u.brilinear) {
        // lp_build_brilinear_lod (BRILINEAR_FACTOR 2): the lod offset by (2 - 0.5) / 2 - 0.5,
        // its floor the level, its fraction f giving the weight 2f - 1 (exact).
        const float lod = q.lod + 0.25f;
        split_levels(u, q, ifloor(lod), (lod - std::floor(lod)) * 2.0f - 1.0f);
        return q;
    }
    split_levels(u, q, ifloor(q.lod), q.lod - std::floor(q.lod));
    return q;
}

}  // namespace

std::optional<PackedLevels> pack_levels(const std::vector<TextureImage>& levels) {
    if (levels.empty() || levels.size() > PackedLevels::kMaxLevels) return std::nullopt;
    std::size_t total = 0;
    for (const TextureImage& l : levels) {
        if (l.width > PackedLevels::kMaxSize || l.height > PackedLevels::kMaxSize)
            return std::nullopt;
        total += std::size_t{l.width} * l.height;
    }
    if (total > PackedLevels::kMaxTexels) return std::nullopt;
    PackedLevels p;
    p.texels.resize(total);
    std::size_t at = 0;
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const TextureImage& l = levels[i];
        const std::size_t n = std::size_t{l.width} * l.height;
        REFRASTER_ASSERT(l.rgba.size() == 4 * n, "a level of width * height texels");
        p.offset[i] = static_cast<std::int32_t>(at);
        p.width[i] = static_cast<std::int32_t>(l.width);
        p.height[i] = static_cast<std::int32_t>(l.height);
        for (std::size_t k = 0; k < n; ++k) {
            const std::uint8_t* t = l.rgba.data() + 4 * k;
            p.texels[at + k] = std::uint32_t{t[0]} | std::uint32_t{t[1]} << 8 |
                               std::uint32_t{t[2]} << 16 | std::uint32_t{t[3]} << 24;
        }
        at += n;
    }
    p.count = static_cast<std::uint32_t>(levels.size());
    return p;
}

float unorm8_to_float(std::uint8_t v) {
    constexpr float kInv255 = 1.0f / 255.0f;
    return static_cast<float>(v) * kInv255;
}

TextureUnit make_texture_unit(const TextureState& state, const std::vector<TextureImage>& levels,
                              TextureFiltering filtering) {
    REFRASTER_ASSERT(!levels.empty(), "a texture with a base level");
    TextureUnit u;
    u.levels = &levels;
    u.state = state;
    const auto edge_or_repeat = [](TextureWrap w) {
        return w == TextureWrap::Repeat || w == TextureWrap::ClampToEdge;
    };
    u.aos = filtering == TextureFiltering::FixedPoint && edge_or_repeat(state.wrap_s) &&
            edge_or_repeat(state.wrap_t);
    u.pot_s = is_pot(levels[0].width);
    u.pot_t = is_pot(levels[0].height);
    u.mipmapped = uses_mipmaps(state.min_filter);
    u.last_level = u.mipmapped ? static_cast<std::uint32_t>(levels.size() - 1) : 0;
    const auto image_filter = [](TextureFilter f) {
        return f == TextureFilter::Nearest || f == TextureFilter::NearestMipmapNearest ||
                       f == TextureFilter::NearestMipmapLinear
                   ? TextureFilter::Nearest
                   : TextureFilter::Linear;
    };
    u.needs_lod = u.mipmapped || image_filter(state.min_filter) != state.mag_filter;
    u.soa_nearest_as_linear = !u.aos && image_filter(state.min_filter) != state.mag_filter;
    u.base_width = static_cast<float>(levels[0].width);
    u.base_height = static_cast<float>(levels[0].height);
    return u;
}

bool quad_takes_linear(const TextureUnit& u, const std::array<float, 4>& s,
                       const std::array<float, 4>& t) {
    return is_linear(quad_lod(u, s, t).minified ? u.state.min_filter : u.state.mag_filter);
}

namespace {

[[gnu::always_inline]] inline void sample_quad_body(const TextureUnit& u,
                                                    const std::array<float, 4>& s,
                                                    const std::array<float, 4>& t, bool fma,
                                                    std::array<std::array<float, 4>, 4>& out,
                                                    bool pair_linear, TexelSample* trace,
                                                    unsigned trace_pixel) {
    const QuadLod lod = quad_lod(u, s, t);
    const bool linear = is_linear(lod.minified ? u.state.min_filter : u.state.mag_filter);
    // The float path with different image filters: the combined filter when this quad or
    // the other quad of its eight-pixel vector takes the linear one, nearest otherwise.
    const bool both = u.soa_nearest_as_linear && (linear || pair_linear);
    const bool two_levels = lod.minified && u.mipmapped && lod.level0 != lod.level1;
    const LevelView lv0 = level_view(u, lod.minified ? lod.level0 : 0);
    const LevelView lv1 = two_levels ? level_view(u, lod.level1) : lv0;
    for (unsigned p = 0; p < 4; ++p) {
        TexelSample* tr = trace != nullptr && p == trace_pixel ? trace : nullptr;
        if (u.aos) {
            auto c0 = sample_level_aos(u, lv0, s[p], t[p], linear, tr, 0);
            if (two_levels) {
                const auto c1 = sample_level_aos(u, lv1, s[p], t[p], linear, tr, 1);
                for (std::size_t c = 0; c < 4; ++c)
                    c0[c] = static_cast<std::uint8_t>(lerp8(lod.frac8, c0[c], c1[c]));
            }
            for (std::size_t c = 0; c < 4; ++c) out[p][c] = unorm8_to_float(c0[c]);
        } else {
            auto c0 = sample_level_soa(u, lv0, s[p], t[p], linear, both, fma, tr, 0);
            if (two_levels) {
                const auto c1 = sample_level_soa(u, lv1, s[p], t[p], linear, both, fma, tr, 1);
                for (std::size_t c = 0; c < 4; ++c) c0[c] = lerp_float(lod.frac, c0[c], c1[c], fma);
            }
            out[p] = c0;
        }
        if (tr != nullptr) {
            tr->aos = u.aos;
            tr->coord = {s[p], t[p]};
            tr->rho_terms = lod.terms;
            tr->rho2 = lod.rho2;
            tr->minified = lod.minified;
            tr->lod = lod.lod;
            tr->level0 = lod.minified ? lod.level0 : 0;
            tr->level1 = two_levels ? lod.level1 : tr->level0;
            tr->level_weight = two_levels ? lod.frac : 0.0f;
            tr->level_weight8 = two_levels ? static_cast<std::uint32_t>(lod.frac8) : 0;
            tr->linear = linear;
            tr->color = out[p];
        }
    }
}

}  // namespace

#if REFRASTER_SAMPLER_ISA_VARIANTS
// The same sampler compiled for CPUs with FMA and SSE4.1 (chosen at run time): floor, trunc and
// the rounding become single instructions and the fused lerps one instruction each, instead of
// library calls; the operations and their order are the body's, so the results are the same.
[[gnu::target("fma,sse4.1,popcnt"), gnu::flatten]] void sample_quad_fma(
    const TextureUnit& u, const std::array<float, 4>& s, const std::array<float, 4>& t, bool fma,
    std::array<std::array<float, 4>, 4>& out, bool pair_linear, TexelSample* trace,
    unsigned trace_pixel) {
    sample_quad_body(u, s, t, fma, out, pair_linear, trace, trace_pixel);
}
#endif

void sample_quad(const TextureUnit& u, const std::array<float, 4>& s, const std::array<float, 4>& t,
                 bool fma, std::array<std::array<float, 4>, 4>& out, bool pair_linear,
                 TexelSample* trace, unsigned trace_pixel) {
#if REFRASTER_SAMPLER_ISA_VARIANTS
    static const bool kVariant = host_runs_fma_sse41();
    if (kVariant) return sample_quad_fma(u, s, t, fma, out, pair_linear, trace, trace_pixel);
#endif
    sample_quad_body(u, s, t, fma, out, pair_linear, trace, trace_pixel);
}

namespace {

// One attribute plane of the blit's rectangle (lp_state_setup.c, calc_coef4, unfused): the
// value at pixel (0, 0)'s centre and the steps along x and y.
struct BlitPlane {
    float a0 = 0.0f;
    float dadx = 0.0f;
    float dady = 0.0f;
};

// The planes of one triangle of the blit for the attribute values a[0..2] at window
// positions p[0..2] (setup's order), as lp_state_setup.c's init_args and calc_coef4 compute
// them: x0c = x0 - 0.5, ooa = 1 / (dx01 * dy20 - dy01 * dx20), the deltas times ooa, then
// dadx = da01 * dy20o - da20 * dy01o, dady = da20 * dx01o - da01 * dx20o,
// A0 = a0 - (dadx * x0c + dady * y0c).
BlitPlane blit_plane(const std::array<std::array<float, 2>, 3>& p, const std::array<float, 3>& a) {
    const float dx01 = p[0][0] - p[1][0];
    const float dy01 = p[0][1] - p[1][1];
    const float dx20 = p[2][0] - p[0][0];
    const float dy20 = p[2][1] - p[0][1];
    const float e = dx01 * dy20;
    const float f = dy01 * dx20;
    const float ooa = 1.0f / (e - f);
    const float dx20o = dx20 * ooa;
    const float dy20o = dy20 * ooa;
    const float dx01o = dx01 * ooa;
    const float dy01o = dy01 * ooa;
    const float da01 = a[0] - a[1];
    const float da20 = a[2] - a[0];
    BlitPlane out;
    out.dadx = da01 * dy20o - da20 * dy01o;
    out.dady = da20 * dx01o - da01 * dx20o;
    const float x0c = p[0][0] - 0.5f;
    const float y0c = p[0][1] - 0.5f;
    out.a0 = a[0] - (out.dadx * x0c + out.dady * y0c);
    return out;
}

// lp_bld_interp.c, attribs_update_simple: fmuladd(dady, py, fmuladd(dadx, px, A0)).
float blit_eval(const BlitPlane& p, float px, float py, bool fma) {
    if (fma) return fused_multiply_add(p.dady, py, fused_multiply_add(p.dadx, px, p.a0));
    return p.dady * py + (p.dadx * px + p.a0);
}

}  // namespace

TextureImage blit_level(const TextureImage& src, bool fma, TextureFiltering filtering) {
    // util_gen_mipmap (gallium/auxiliary/util/u_gen_mipmap.c): each level a pipe->blit of
    // the one above with a linear filter. llvmpipe's blit is util_blitter_blit (u_blitter.c):
    // blitter_set_rectangle draws the destination as a triangle fan v0 (0, 0), v1 (w, 0),
    // v2 (w, h), v3 (0, h) (NDC x / w * 2 - 1 and the viewport 0.5 * w map it back exactly),
    // get_texcoords gives the source box's x / w_src and y / h_src: 0 and 1 here. Its fragment
    // shader samples the source level with an explicit LOD of 0, clamp-to-edge, through the
    // 8-bit path (the float one under texture_filtering=float, its colour then stored as a
    // fragment's), at coordinates interpolated from the triangles' planes (docs/precision.md,
    // "Generated mipmaps").
    TextureImage next;
    next.width = std::max(1u, src.width / 2);
    next.height = std::max(1u, src.height / 2);
    next.rgba.resize(std::size_t{next.width} * next.height * 4);
    TextureUnit u;
    u.state.wrap_s = u.state.wrap_t = TextureWrap::ClampToEdge;
    const LevelView lv{&src, static_cast<std::int32_t>(src.width),
                       static_cast<std::int32_t>(src.height)};
    const float w = static_cast<float>(next.width);
    const float h = static_cast<float>(next.height);
    // lp_setup_vbuf.c, lp_setup_draw_arrays: a four-vertex fan goes to setup->rect, which
    // for this shader (no linear rasterizer: its sampler takes BGRA formats only,
    // lp_linear_check_sampler) falls back to the triangles (v0, v1, v2) and (v0, v2, v3).
    // Both are clockwise in gallium's window space, so triangle_both swaps their first two
    // vertices (the last-vertex convention's rotation, setup.cpp swap_to_ccw): A = (v1, v0, v2)
    // and B = (v2, v0, v3). Each plane is anchored at its first vertex, so A and B give
    // slightly different coordinates to the pixels on either side of the diagonal v0-v2.
    const std::array<std::array<float, 2>, 3> pa = {{{w, 0.0f}, {0.0f, 0.0f}, {w, h}}};
    const std::array<std::array<float, 2>, 3> pb = {{{w, h}, {0.0f, 0.0f}, {0.0f, h}}};
    const BlitPlane sa = blit_plane(pa, {1.0f, 0.0f, 1.0f});
    const BlitPlane ta = blit_plane(pa, {0.0f, 0.0f, 1.0f});
    const BlitPlane sb = blit_plane(pb, {1.0f, 0.0f, 0.0f});
    const BlitPlane tb = blit_plane(pb, {1.0f, 0.0f, 1.0f});
    for (std::uint32_t j = 0; j < next.height; ++j) {
        for (std::uint32_t i = 0; i < next.width; ++i) {
            // A holds the centres with x / w > y / h; a centre exactly on the diagonal is
            // A's too: the diagonal is A's left edge and B's right one, and the fill rule
            // owns left edges.
            const std::uint64_t lhs = (2 * std::uint64_t{i} + 1) * next.height;
            const std::uint64_t rhs = (2 * std::uint64_t{j} + 1) * next.width;
            const bool in_a = lhs >= rhs;
            const float px = static_cast<float>(i);
            const float py = static_cast<float>(j);
            const float uu = blit_eval(in_a ? sa : sb, px, py, fma);
            const float v = blit_eval(in_a ? ta : tb, px, py, fma);
            auto* out = next.rgba.data() + 4 * (std::size_t{j} * next.width + i);
            if (filtering == TextureFiltering::FixedPoint) {
                const auto c = sample_level_aos(u, lv, uu, v, true, nullptr, 0);
                std::copy(c.begin(), c.end(), out);
            } else {
                const auto c = sample_level_soa(u, lv, uu, v, true, false, fma, nullptr, 0);
                for (std::size_t k = 0; k < 4; ++k) out[k] = color_to_unorm8(c[k]);
            }
        }
    }
    return next;
}

std::vector<TextureImage> generate_mipmaps(const TextureImage& base, bool fma,
                                           TextureFiltering filtering) {
    std::vector<TextureImage> out;
    const TextureImage* src = &base;
    while (src->width > 1 || src->height > 1) {
        out.push_back(blit_level(*src, fma, filtering));
        src = &out.back();
    }
    return out;
}

std::vector<TextureImage> resolve_levels(const Texture& texture, bool fma,
                                         TextureFiltering filtering) {
    REFRASTER_ASSERT(!texture.levels.empty(), "a texture with a base level");
    std::vector<TextureImage> levels;
    if (!texture.generate_mipmaps) return texture.levels;
    levels.push_back(texture.levels.front());
    for (auto& l : generate_mipmaps(texture.levels.front(), fma, filtering))
        levels.push_back(std::move(l));
    return levels;
}

}  // namespace refraster::detail
