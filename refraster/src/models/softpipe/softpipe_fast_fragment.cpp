// softpipe_fast_fragment.cpp: the fast path of softpipe's quad pipeline (softpipe_fragment.hpp).
//
// The same float operations as ScanlineKernel::shade, in the same order for every value, under
// the same floating-point mode (the pipeline sets the CPU's flush modes around a list where
// the profile flushes, and shade clears them for a primitive the draw pipeline's last batch
// hands on after draw_vbo); what differs is how often they run and where colours go:
//  - each plane of a quad is evaluated once (tgsi_exec.c eval_linear_coef: four values from
//    one (a0 + dadx*x0) + dady*y0), not once a pixel and channel;
//  - colours go through SoftpipeLazyTiles, whose loads and evictions cost nothing beyond the
//    pixels written (softpipe_lazy_tiles.hpp), fetched in the model's order: once a batch
//    with a surviving pixel, at its first quad.
//  - with SSE2, the depth test takes a quad's four pixels as one vector, and the colour
//    planes a pixel's four channels as one (each lane the scalar code's operations in its
//    order).
// The blend (ScanlineKernel::merge) is the model's own code; the sampler is the model's with
// the tile cache's emulation skipped where no entry can alias
// (SoftpipeSampler::sample_quad_direct).
#include <algorithm>
#include <bit>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "common/cpu.hpp"
#include "models/softpipe/softpipe_fragment.hpp"
#include "models/softpipe/softpipe_lazy_tiles.hpp"
#include "models/softpipe/softpipe_sampler.hpp"
#include "stages/output_merge.hpp"

namespace refraster::detail {

namespace {

// tgsi_exec.c eval_linear_coef, as scanline_quad: q = (a0 + dadx*x0) + dady*y0, then
// q + dadx, q + dady and (q + dadx) + dady. Unfused.
[[gnu::always_inline]] inline void quad_values(const ScanlinePlane& p, float fx, float fy,
                                               std::array<float, 4>& out) {
    const float q = (p.a0 + p.dadx * fx) + p.dady * fy;
    const float qx = q + p.dadx;
    out = {q, qx, q + p.dady, qx + p.dady};
}

#if !defined(__SSE2__)
// The values of one attribute channel's plane `a` at the quad's four pixels, as
// ScanlineKernel::attributes computes them (tgsi_exec.c eval_constant_coef, eval_linear_coef,
// eval_perspective_coef: the linear value divided by the quad's 1/w, `w`).
[[gnu::always_inline]] inline void channel_values(const ScanlinePlane& a, ScanlineInterp interp,
                                                  float fx, float fy, const std::array<float, 4>& w,
                                                  std::array<float, 4>& out) {
    switch (interp) {
        case ScanlineInterp::Constant:
            out.fill(a.a0);
            break;
        case ScanlineInterp::Linear:
            quad_values(a, fx, fy, out);
            break;
        case ScanlineInterp::Perspective:
            quad_values(a, fx, fy, out);
            for (std::size_t k = 0; k < 4; ++k) out[k] = out[k] / w[k];
            break;
    }
}
#endif

#if defined(__SSE2__)
// channel_values of planes a[0] to a[3] at once, pixel by pixel: c[k] gets pixel k's four
// channels. Lane ch computes what channel_values computes for a[ch], in the same order:
// q = (a0 + dadx*fx) + dady*fy, then q + dadx, q + dady and (q + dadx) + dady, each divided
// by w[k] when perspective.
[[gnu::always_inline]] inline void quad_channels(const ScanlinePlane* a, ScanlineInterp interp,
                                                 float fx, float fy, const std::array<float, 4>& w,
                                                 std::array<std::array<float, 4>, 4>& c) {
    const __m128 a0 = _mm_setr_ps(a[0].a0, a[1].a0, a[2].a0, a[3].a0);
    if (interp == ScanlineInterp::Constant) {
        for (auto& pixel : c) _mm_storeu_ps(pixel.data(), a0);
        return;
    }
    const __m128 dadx = _mm_setr_ps(a[0].dadx, a[1].dadx, a[2].dadx, a[3].dadx);
    const __m128 dady = _mm_setr_ps(a[0].dady, a[1].dady, a[2].dady, a[3].dady);
    const __m128 q = _mm_add_ps(_mm_add_ps(a0, _mm_mul_ps(dadx, _mm_set1_ps(fx))),
                                _mm_mul_ps(dady, _mm_set1_ps(fy)));
    const __m128 qx = _mm_add_ps(q, dadx);
    __m128 p0 = q;
    __m128 p1 = qx;
    __m128 p2 = _mm_add_ps(q, dady);
    __m128 p3 = _mm_add_ps(qx, dady);
    if (interp == ScanlineInterp::Perspective) {
        p0 = _mm_div_ps(p0, _mm_set1_ps(w[0]));
        p1 = _mm_div_ps(p1, _mm_set1_ps(w[1]));
        p2 = _mm_div_ps(p2, _mm_set1_ps(w[2]));
        p3 = _mm_div_ps(p3, _mm_set1_ps(w[3]));
    }
    _mm_storeu_ps(c[0].data(), p0);
    _mm_storeu_ps(c[1].data(), p1);
    _mm_storeu_ps(c[2].data(), p2);
    _mm_storeu_ps(c[3].data(), p3);
}
#endif

// cvttss2si with a 32-bit destination, as shade's: 0x80000000 for NaN and values outside
// int32's range.
std::int32_t truncate_to_int32(float v) {
    if (!(v >= -2147483648.0f && v < 2147483648.0f)) return INT32_MIN;
    return static_cast<std::int32_t>(v);
}

// cvttss2si with a 64-bit destination, as softpipe_fragment.cpp's: truncation towards zero,
// 0x8000000000000000 for NaN and values outside int64's range.
std::int64_t truncate_to_int64(float v) {
    if (!(v >= -9223372036854775808.0f && v < 9223372036854775808.0f)) return INT64_MIN;
    return static_cast<std::int64_t>(v);
}

// softpipe_depth_value (sp_quad_depth_test.c convert_quad_depth), here where it can be
// inlined: it runs once a pixel.
[[gnu::always_inline]] inline std::uint32_t depth_value(float z, DepthFormat format, bool nearest) {
    const auto convert = [nearest](float v) {
        return static_cast<std::uint32_t>(truncate_to_int64(nearest ? std::nearbyint(v) : v));
    };
    switch (format) {
        case DepthFormat::Z16:
            return convert(z * 65535.0f);
        case DepthFormat::Z24:
            return convert(z * 16777215.0f);
        case DepthFormat::Z32f:
            return std::bit_cast<std::uint32_t>(z);
        case DepthFormat::None:
            break;
    }
    return 0;
}

unsigned depth_outcome(std::uint32_t frag, std::uint32_t stored, bool is_float) {
    if (is_float) {
        const float f = std::bit_cast<float>(frag);
        const float s = std::bit_cast<float>(stored);
        return f < s ? 1u : f == s ? 2u : 4u;
    }
    return frag < stored ? 1u : frag == stored ? 2u : 4u;
}

#if defined(__SSE2__)
// What the depth test of a batch needs, as vectors: the compare function's outcomes, the
// conversion, and the z16 fast path's start.
struct DepthLanes {
    __m128i pass_lt;  // all ones where the function passes on frag < stored
    __m128i pass_eq;
    __m128i pass_gt;
    __m128i keep;  // the bits stored of a converted value
    __m128 scale;  // 65535.0f or 16777215.0f
    __m128i init;  // the z16 fast path's values at the batch's first quad
    __m128 depth_min;
    __m128 depth_max;
};

// One quad's depth test with its four pixels' depth values as one vector, for a quad whose
// four pixels lie inside the target (the pixel loop of depth_test_fast, lane k pixel k): the
// same operations on each lane in the same order (sp_quad_depth_test.c
// depth_test_quads_fallback, convert_quad_depth, depth_test_quad; the z16 fast path of
// sp_quad_depth_test_tmp.h), and the same writes. `z` the z plane's four quad values (not
// read on the z16 fast path), `dz16` that path's step times the quad's distance from the
// batch's first. Returns false, having changed nothing, when a converted value lies outside
// int32's range (cvttss2si to 64 bits then keeps other low bits than the 32-bit conversion
// gives): the pixel loop takes that quad.
bool depth_quad_sse(const DepthLanes& d, const std::array<float, 4>& z, std::int32_t dz16,
                    bool fast_z16, bool clamp, DepthFormat format, bool nearest, bool write,
                    std::uint32_t* row0, std::uint32_t* row1, std::uint16_t& mask) {
    auto* p0 = reinterpret_cast<__m128i*>(row0);
    auto* p1 = reinterpret_cast<__m128i*>(row1);
    const __m128i stored = _mm_unpacklo_epi64(_mm_loadl_epi64(p0), _mm_loadl_epi64(p1));
    // frag < stored unsigned: both with the sign bit flipped, compared signed.
    const __m128i flip = _mm_set1_epi32(INT32_MIN);
    __m128i store;  // what a passing lane writes
    __m128i lt;     // frag < stored
    __m128i eq;     // frag == stored
    if (fast_z16) {
        // (init[k] + dx * step) & 0xffff, compared and stored as it is.
        store = _mm_and_si128(_mm_add_epi32(d.init, _mm_set1_epi32(dz16)), _mm_set1_epi32(0xffff));
        lt = _mm_cmplt_epi32(_mm_xor_si128(store, flip), _mm_xor_si128(stored, flip));
        eq = _mm_cmpeq_epi32(store, stored);
    } else {
        __m128 v = _mm_loadu_ps(z.data());
        // std::min(std::max(zk, min), max): maxps(min, zk) is min > zk ? min : zk, which is
        // std::max(zk, min)'s zk < min ? min : zk (NaN and zeros included); minps(max, v)
        // likewise std::min(v, max).
        if (clamp) v = _mm_min_ps(d.depth_max, _mm_max_ps(d.depth_min, v));
        if (format == DepthFormat::Z32f) {
            // The float's bits, compared as floats: < and == as the scalar compares (NaN
            // neither), under the same denormal mode.
            store = _mm_castps_si128(v);
            lt = _mm_castps_si128(_mm_cmplt_ps(v, _mm_castsi128_ps(stored)));
            eq = _mm_castps_si128(_mm_cmpeq_ps(v, _mm_castsi128_ps(stored)));
        } else {
            const __m128 scaled = _mm_mul_ps(v, d.scale);
            // Inside [-2^31, 2^31) (NaN is not) the 64-bit truncation's low 32 bits are the
            // 32-bit conversion's, and nearbyint (in the current rounding mode) then the
            // truncation is cvtps2dq: a float of 2^23 or more is an integer already.
            const __m128 inside = _mm_and_ps(_mm_cmpge_ps(scaled, _mm_set1_ps(-2147483648.0f)),
                                             _mm_cmplt_ps(scaled, _mm_set1_ps(2147483648.0f)));
            if (_mm_movemask_ps(inside) != 0xf) return false;
            const __m128i value = nearest ? _mm_cvtps_epi32(scaled) : _mm_cvttps_epi32(scaled);
            // The unmasked value compared, the masked one stored.
            lt = _mm_cmplt_epi32(_mm_xor_si128(value, flip), _mm_xor_si128(stored, flip));
            eq = _mm_cmpeq_epi32(value, stored);
            store = _mm_and_si128(value, d.keep);
        }
    }
    // depth_outcome: less 1, equal 2, otherwise (greater, or unordered floats) 4.
    const __m128i gt = _mm_andnot_si128(_mm_or_si128(lt, eq), _mm_set1_epi32(-1));
    const __m128i pass =
        _mm_or_si128(_mm_or_si128(_mm_and_si128(lt, d.pass_lt), _mm_and_si128(eq, d.pass_eq)),
                     _mm_and_si128(gt, d.pass_gt));
    mask = static_cast<std::uint16_t>(mask & _mm_movemask_ps(_mm_castsi128_ps(pass)));
    if (!write || mask == 0) return true;
    const __m128i bits = _mm_setr_epi32(1, 2, 4, 8);
    const __m128i written = _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(mask), bits), bits);
    const __m128i out =
        _mm_or_si128(_mm_and_si128(written, store), _mm_andnot_si128(written, stored));
    _mm_storel_epi64(p0, out);
    _mm_storel_epi64(p1, _mm_unpackhi_epi64(out, out));
    return true;
}
#endif

}  // namespace

bool ScanlineKernel::depth_test_fast(const ScanlineList& list, const ScanlinePrimitive& p,
                                     std::span<const QuadPacket> quads, Framebuffer& fb,
                                     std::uint16_t* alive) const {
    bool any = false;
    if (!depth_) {
        for (std::size_t q = 0; q < quads.size(); ++q) {
            alive[q] = quads[q].mask & kSample0Pixels;
            any = any || alive[q] != 0;
        }
        return any;
    }
    const ScanlinePlane& zp = list.planes[p.planes + kScanlineZPlane];
    // sp_quad_depth_test_tmp.h: exact values at the batch's first quad, a truncated step on.
    const bool fast_z16 = z16_fast_path_ && !p.clamp_depth;
    std::array<std::int32_t, 4> init{};
    std::int32_t step = 0;
    if (fast_z16) {
        const auto z = scanline_quad(zp, quads[0].x, quads[0].y);
        for (std::size_t j = 0; j < 4; ++j) init[j] = truncate_to_int32(z[j] * 65535.0f) & 0xffff;
        step = truncate_to_int32(zp.dadx * 65535.0f) & 0xffff;
    }
#if defined(__GNUC__)
    // A hint, no value: the depth of the next 2-row block under this batch's first quad,
    // which the primitive's next batches there will likely test (a batch's quads lie in one
    // 16-pixel chunk: one cache line a row).
    const auto qx0 = static_cast<std::uint32_t>(quads[0].x);
    const auto qy0 = static_cast<std::uint32_t>(quads[0].y);
    if (qx0 < fb.width && qy0 + 3 < fb.height) {
        const std::uint32_t* next = fb.depth.data() + fb.index(qx0, qy0 + 2);
        __builtin_prefetch(next, 1);
        __builtin_prefetch(next + fb.width, 1);
    }
#endif
    const bool is_float = fb.depth_format == DepthFormat::Z32f;
    const std::uint32_t keep = fb.depth_format == DepthFormat::Z16   ? 0xffffu
                               : fb.depth_format == DepthFormat::Z24 ? 0xffffffu
                                                                     : 0xffffffffu;
#if defined(__SSE2__)
    const auto pass_if = [this](unsigned outcome) {
        return _mm_set1_epi32((depth_pass_ & outcome) != 0 ? -1 : 0);
    };
    const DepthLanes lanes{
        pass_if(1),
        pass_if(2),
        pass_if(4),
        _mm_set1_epi32(static_cast<std::int32_t>(keep)),
        _mm_set1_ps(fb.depth_format == DepthFormat::Z16 ? 65535.0f : 16777215.0f),
        _mm_setr_epi32(init[0], init[1], init[2], init[3]),
        _mm_set1_ps(depth_min_),
        _mm_set1_ps(depth_max_)};
#endif
    for (std::size_t q = 0; q < quads.size(); ++q) {
        const QuadPacket& quad = quads[q];
        std::uint16_t mask = quad.mask & kSample0Pixels;
        std::array<float, 4> z{};
        if (!fast_z16) quad_values(zp, static_cast<float>(quad.x), static_cast<float>(quad.y), z);
        const std::int32_t dz16 = (quad.x - quads[0].x) * step;
        bool done = mask == 0;
#if defined(__SSE2__)
        // A quad inside the target a vector at a time (its two rows' pixel pairs).
        if (!done && static_cast<std::uint32_t>(quad.x) + 1 < fb.width &&
            static_cast<std::uint32_t>(quad.y) + 1 < fb.height) {
            std::uint32_t* row0 = fb.depth.data() + fb.index(static_cast<std::uint32_t>(quad.x),
                                                             static_cast<std::uint32_t>(quad.y));
            done = depth_quad_sse(lanes, z, dz16, fast_z16, p.clamp_depth, fb.depth_format,
                                  depth_nearest_, depth_write_, row0, row0 + fb.width, mask);
        }
#endif
        for (unsigned k = 0; k < 4 && !done; ++k) {
            if ((mask & (1u << k)) == 0) continue;
            const auto x = static_cast<std::uint32_t>(quad.x + static_cast<int>(k & 1u));
            const auto y = static_cast<std::uint32_t>(quad.y + static_cast<int>(k >> 1));
            const std::size_t i = fb.index(x, y);
            std::uint32_t value = 0;
            std::uint32_t stored_value = 0;
            if (fast_z16) {
                value = static_cast<std::uint32_t>(init[k] + dz16) & 0xffffu;
                stored_value = value;
            } else {
                float zk = z[k];
                // depth_test_quads_fallback's clamp (the point sprites: depth clipping off).
                if (p.clamp_depth) zk = std::min(std::max(zk, depth_min_), depth_max_);
                value = depth_value(zk, fb.depth_format, depth_nearest_);
                stored_value = value & keep;
            }
            if ((depth_pass_ & depth_outcome(value, fb.depth[i], is_float)) == 0) {
                mask = static_cast<std::uint16_t>(mask & ~(1u << k));
            } else if (depth_write_) {
                fb.depth[i] = stored_value;
            }
        }
        alive[q] = mask;
        any = any || mask != 0;
    }
    return any;
}

void ScanlineKernel::quad_colors_fast(const ScanlineList& list, const ScanlinePrimitive& p, int x0,
                                      int y0, std::array<std::array<float, 4>, 4>& c) const {
    const ScanlinePlane* planes = list.planes.data() + p.planes;
    const auto fx = static_cast<float>(x0);
    const auto fy = static_cast<float>(y0);
    std::array<float, 4> w{};
    if (p.interp == ScanlineInterp::Perspective || p.point_coords)
        quad_values(planes[kScanlineWPlane], fx, fy, w);
    const ScanlinePlane* colour = planes + kScanlineFirstAttribute;
#if defined(__SSE2__)
    // The four channels of each pixel as one vector, lane ch the channel's value: the same
    // operations on each lane as the scalar quad_values and division give.
    quad_channels(colour, p.interp, fx, fy, w, c);
#else
    std::array<std::array<float, 4>, 4> by_channel{};  // [channel][pixel]
    for (std::size_t ch = 0; ch < 4; ++ch)
        channel_values(colour[ch], p.interp, fx, fy, w, by_channel[ch]);
    for (std::size_t k = 0; k < 4; ++k) {
        for (std::size_t ch = 0; ch < 4; ++ch) c[k][ch] = by_channel[ch][k];
    }
#endif
    if (sampler_ == nullptr) return;
    // ScanlineKernel::quad_colors: s/q and t/q (TXP), or the sprite coordinate over 1/w.
    std::array<float, 4> s{}, t{};
    if (p.point_coords) {
        const std::size_t pc = kScanlineFirstAttribute + list.attribute_floats;
        quad_values(planes[pc], fx, fy, s);
        quad_values(planes[pc + 1], fx, fy, t);
        for (std::size_t k = 0; k < 4; ++k) {
            s[k] = s[k] / w[k];
            t[k] = t[k] / w[k];
        }
    } else {
#if defined(__SSE2__)
        // The texture coordinate's four planes as the colour's (r computed and not read).
        std::array<std::array<float, 4>, 4> stq{};  // [pixel][s, t, r, q]
        quad_channels(colour + 4, p.interp, fx, fy, w, stq);
        for (std::size_t k = 0; k < 4; ++k) {
            s[k] = stq[k][0] / stq[k][3];
            t[k] = stq[k][1] / stq[k][3];
        }
#else
        std::array<float, 4> tq{};
        channel_values(colour[4], p.interp, fx, fy, w, s);
        channel_values(colour[5], p.interp, fx, fy, w, t);
        channel_values(colour[7], p.interp, fx, fy, w, tq);
        for (std::size_t k = 0; k < 4; ++k) {
            s[k] = s[k] / tq[k];
            t[k] = t[k] / tq[k];
        }
#endif
    }
    std::array<std::array<float, 4>, 4> texel{};
    sampler_->sample_quad_direct(s, t, texel);
    const bool replace = draw_.state.texture->env == TextureEnv::Replace;
    for (std::size_t k = 0; k < 4; ++k) {
        for (std::size_t ch = 0; ch < 4; ++ch)
            c[k][ch] = replace ? texel[k][ch] : c[k][ch] * texel[k][ch];
    }
}

void ScanlineKernel::shade_fast(const ScanlineList& list, const ScanlinePrimitive& p,
                                std::span<const QuadPacket> quads, Framebuffer& fb) const {
    if (quads.empty()) return;
    const ScopedDenormalMode plain(flush_ && !p.flush, false);
    std::array<std::uint16_t, 8> live{};
    std::vector<std::uint16_t> live_more;
    std::uint16_t* alive = live.data();
    if (quads.size() > live.size()) {
        live_more.resize(quads.size());
        alive = live_more.data();
    }
    // A batch none of whose pixels survives never reaches the blend stage: no tile is fetched.
    if (!depth_test_fast(list, p, quads, fb, alive)) return;
    // Every quad of a batch lies in the tile of its first: a batch is one quad of a line, or
    // quads of one 16-pixel aligned chunk of one 2-row block.
    SoftpipeLazyTiles::Slot& tile = lazy_->fetch(quads[0].x, quads[0].y);
    const bool blends = draw_.state.blend != BlendPreset::None;
    std::array<std::array<float, 4>, 4> colors{};
    for (std::size_t q = 0; q < quads.size(); ++q) {
        const QuadPacket& quad = quads[q];
        if (alive[q] == 0) continue;
        quad_colors_fast(list, p, quad.x, quad.y, colors);
        for (unsigned k = 0; k < 4; ++k) {
            if ((alive[q] & (1u << k)) == 0) continue;
            const int x = quad.x + static_cast<int>(k & 1u);
            const int y = quad.y + static_cast<int>(k >> 1);
            if (blends) {
                std::array<float, 4> dst{};
                lazy_->read(tile, x, y, dst.data());
                merge(colors[k], dst.data());
                std::copy(dst.begin(), dst.end(), SoftpipeLazyTiles::written(tile, x, y));
            } else {
                std::copy(colors[k].begin(), colors[k].end(),
                          SoftpipeLazyTiles::written(tile, x, y));
            }
            if (!fb.owner.empty())
                fb.owner[fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y))] =
                    p.owner;
        }
    }
}

}  // namespace refraster::detail
