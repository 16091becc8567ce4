// softpipe_fragment.cpp: softpipe's quad pipeline (softpipe_fragment.hpp).
#include "models/softpipe/softpipe_fragment.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "common/cpu.hpp"
#include "models/softpipe/softpipe_sampler.hpp"
#include "models/softpipe/softpipe_tiles.hpp"
#include "stages/output_merge.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

namespace {

// The value of plane `p` at pixel k (0..3) of the quad at (x0, y0).
float at(const ScanlinePlane& p, int x0, int y0, unsigned k) {
    return scanline_quad(p, x0, y0)[k];
}

// cvttss2si with a 64-bit destination: truncation towards zero, 0x8000000000000000 for NaN
// and values outside int64's range.
std::int64_t truncate_to_int64(float v) {
    if (!(v >= -9223372036854775808.0f && v < 9223372036854775808.0f)) return INT64_MIN;
    return static_cast<std::int64_t>(v);
}

// cvttss2si with a 32-bit destination: 0x80000000 for NaN and values outside int32's range.
std::int32_t truncate_to_int32(float v) {
    if (!(v >= -2147483648.0f && v < 2147483648.0f)) return INT32_MIN;
    return static_cast<std::int32_t>(v);
}

// sp_quad_blend.c clamp_colors: CLAMP(x, 0, 1) = x > 0 ? (x > 1 ? 1 : x) : 0, so NaN and -0
// become +0.
float clamp01(float v) {
    return v > 0.0f ? (v > 1.0f ? 1.0f : v) : 0.0f;
}

unsigned depth_outcome(std::uint32_t frag, std::uint32_t stored, bool is_float) {
    if (is_float) {
        const float f = std::bit_cast<float>(frag);
        const float s = std::bit_cast<float>(stored);
        return f < s ? 1u : f == s ? 2u : 4u;
    }
    return frag < stored ? 1u : frag == stored ? 2u : 4u;
}

}  // namespace

std::uint32_t softpipe_depth_value(float z, DepthFormat format, bool nearest) {
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

ScanlineKernel::ScanlineKernel(const Draw& draw, const Target& target, SoftpipeTileCache& tiles,
                               bool flush_denormals, bool depth_nearest,
                               const SoftpipeSampler* sampler)
    : draw_(draw),
      tiles_(&tiles),
      flush_(flush_denormals && cpu_flush_modes_available()),
      depth_nearest_(depth_nearest),
      sampler_(sampler) {
    init(draw, target);
}

ScanlineKernel::ScanlineKernel(const Draw& draw, const Target& target, SoftpipeLazyTiles& tiles,
                               bool flush_denormals, bool depth_nearest,
                               const SoftpipeSampler* sampler)
    : draw_(draw),
      lazy_(&tiles),
      flush_(flush_denormals && cpu_flush_modes_available()),
      depth_nearest_(depth_nearest),
      sampler_(sampler) {
    init(draw, target);
}

void ScanlineKernel::init(const Draw& draw, const Target& target) {
    rgba8_ = target.color == ColorFormat::Rgba8;
    depth_ = draw.state.depth_test.has_value() && target.depth != DepthFormat::None;
    if (depth_) {
        const CompareFunc f = *draw.state.depth_test;
        depth_pass_ = static_cast<std::uint8_t>(f);
        // st_atom_depth.c: the write mask is cleared for GL_EQUAL.
        depth_write_ = draw.state.depth_write && f != CompareFunc::Equal;
        // sp_quad_depth_test.c choose_depth_test: the z16 fast paths exist for every function
        // but never and equal, with writes on (no stencil, alpha test or queries here).
        z16_fast_path_ = target.depth == DepthFormat::Z16 && depth_write_ &&
                         f != CompareFunc::Never && !depth_nearest_;
    }
    const ViewportTransform vp = viewport_transform(draw.state);
    const float near = vp.translate[2] - vp.scale[2];
    const auto far =
        static_cast<float>(static_cast<double>(near) + static_cast<double>(vp.scale[2]) * 2.0);
    depth_min_ = std::min(near, far);
    depth_max_ = std::max(near, far);
}

std::array<float, 4> ScanlineKernel::attributes(const ScanlineList& list,
                                                const ScanlinePrimitive& p, std::size_t first,
                                                int x0, int y0, unsigned k) const {
    const ScanlinePlane* planes = list.planes.data() + p.planes;
    std::array<float, 4> c{};
    const float w =
        p.interp == ScanlineInterp::Perspective ? at(planes[kScanlineWPlane], x0, y0, k) : 1.0f;
    for (std::size_t ch = 0; ch < 4; ++ch) {
        const ScanlinePlane& a = planes[kScanlineFirstAttribute + first + ch];
        switch (p.interp) {
            case ScanlineInterp::Constant:
                c[ch] = a.a0;
                break;
            case ScanlineInterp::Linear:
                c[ch] = at(a, x0, y0, k);
                break;
            case ScanlineInterp::Perspective:
                c[ch] = at(a, x0, y0, k) / w;
                break;
        }
    }
    return c;
}

std::array<std::array<float, 4>, 4> ScanlineKernel::quad_colors(const ScanlineList& list,
                                                                const ScanlinePrimitive& p, int x0,
                                                                int y0) const {
    std::array<std::array<float, 4>, 4> c{};
    for (unsigned k = 0; k < 4; ++k) c[k] = attributes(list, p, 0, x0, y0, k);
    if (sampler_ == nullptr) return c;
    // The texture coordinates of all four pixels: textureProj's s/q and t/q (TXP divides), or
    // the sprite coordinate, always perspective-correct (tgsi_exec.c eval_perspective_coef).
    std::array<float, 4> s{}, t{};
    const ScanlinePlane* planes = list.planes.data() + p.planes;
    for (unsigned k = 0; k < 4; ++k) {
        if (p.point_coords) {
            const std::size_t pc = kScanlineFirstAttribute + list.attribute_floats;
            const float w = at(planes[kScanlineWPlane], x0, y0, k);
            s[k] = at(planes[pc], x0, y0, k) / w;
            t[k] = at(planes[pc + 1], x0, y0, k) / w;
        } else {
            const auto tc = attributes(list, p, 4, x0, y0, k);
            s[k] = tc[0] / tc[3];
            t[k] = tc[1] / tc[3];
        }
    }
    std::array<std::array<float, 4>, 4> texel{};
    sampler_->sample_quad(s, t, texel);
    for (unsigned k = 0; k < 4; ++k) {
        for (std::size_t ch = 0; ch < 4; ++ch) {
            c[k][ch] = draw_.state.texture->env == TextureEnv::Replace ? texel[k][ch]
                                                                       : c[k][ch] * texel[k][ch];
        }
    }
    return c;
}

void ScanlineKernel::merge(const std::array<float, 4>& c, float* dst) const {
    // sp_quad_blend.c: single_output_color, blend_single_add_src_alpha_inv_src_alpha,
    // blend_single_add_one_one; the source and result clamped for a unorm target only.
    switch (draw_.state.blend) {
        case BlendPreset::None:
            std::copy(c.begin(), c.end(), dst);
            break;
        case BlendPreset::Alpha: {
            std::array<float, 4> s = c;
            if (rgba8_) {
                for (auto& v : s) v = clamp01(v);
            }
            const float a = s[3];
            const float one_minus_a = 1.0f - a;
            for (std::size_t k = 0; k < 4; ++k) {
                const float v = s[k] * a + dst[k] * one_minus_a;
                dst[k] = rgba8_ ? clamp01(v) : v;
            }
            break;
        }
        case BlendPreset::Add:
            for (std::size_t k = 0; k < 4; ++k) {
                const float v = (rgba8_ ? clamp01(c[k]) : c[k]) + dst[k];
                dst[k] = rgba8_ ? clamp01(v) : v;
            }
            break;
    }
}

void ScanlineKernel::shade(const ScanlineList& list, const ScanlinePrimitive& p,
                           std::span<const QuadPacket> quads, Framebuffer& fb) const {
    if (lazy_ != nullptr) return shade_fast(list, p, quads, fb);
    if (quads.empty()) return;
    const ScopedDenormalMode plain(flush_ && !p.flush, false);
    const ScanlinePlane& zp = list.planes[p.planes + kScanlineZPlane];
    // The early depth test over the batch: the surviving pixels of each quad.
    std::array<std::uint16_t, 8> live{};
    std::vector<std::uint16_t> live_more;
    std::uint16_t* alive = live.data();
    if (quads.size() > live.size()) {
        live_more.resize(quads.size());
        alive = live_more.data();
    }
    bool any = false;
    // sp_quad_depth_test_tmp.h: exact values at the batch's first quad, a truncated step on.
    std::array<std::int32_t, 4> init{};
    std::int32_t step = 0;
    if (depth_ && z16_fast_path_ && !p.clamp_depth) {
        const auto z = scanline_quad(zp, quads[0].x, quads[0].y);
        for (std::size_t j = 0; j < 4; ++j) init[j] = truncate_to_int32(z[j] * 65535.0f) & 0xffff;
        step = truncate_to_int32(zp.dadx * 65535.0f) & 0xffff;
    }
    for (std::size_t q = 0; q < quads.size(); ++q) {
        const QuadPacket& quad = quads[q];
        std::uint16_t mask = quad.mask & kSample0Pixels;
        if (depth_) {
            std::array<float, 4> z{};
            if (!z16_fast_path_ || p.clamp_depth) z = scanline_quad(zp, quad.x, quad.y);
            for (unsigned k = 0; k < 4; ++k) {
                if ((mask & (1u << k)) == 0) continue;
                const auto x = static_cast<std::uint32_t>(quad.x + static_cast<int>(k & 1u));
                const auto y = static_cast<std::uint32_t>(quad.y + static_cast<int>(k >> 1));
                const std::size_t i = fb.index(x, y);
                std::uint32_t value = 0;
                std::uint32_t stored_value = 0;
                if (z16_fast_path_ && !p.clamp_depth) {
                    const std::int32_t dx = quad.x - quads[0].x;
                    value = static_cast<std::uint32_t>(init[k] + dx * step) & 0xffffu;
                    stored_value = value;
                } else {
                    float zk = z[k];
                    // depth_test_quads_fallback's clamp, for primitives drawn with depth
                    // clipping off (the point sprites).
                    if (p.clamp_depth) zk = std::min(std::max(zk, depth_min_), depth_max_);
                    value = softpipe_depth_value(zk, fb.depth_format, depth_nearest_);
                    stored_value = fb.depth_format == DepthFormat::Z16   ? value & 0xffffu
                                   : fb.depth_format == DepthFormat::Z24 ? value & 0xffffffu
                                                                         : value;
                }
                const bool pass =
                    (depth_pass_ &
                     depth_outcome(value, fb.depth[i], fb.depth_format == DepthFormat::Z32f)) != 0;
                if (!pass) {
                    mask = static_cast<std::uint16_t>(mask & ~(1u << k));
                } else if (depth_write_) {
                    fb.depth[i] = stored_value;
                }
            }
        }
        alive[q] = mask;
        any = any || mask != 0;
    }
    if (!any) return;  // the batch never reaches the blend stage: no tile is fetched
    tiles_->fetch(quads[0].x, quads[0].y);
    for (std::size_t q = 0; q < quads.size(); ++q) {
        const QuadPacket& quad = quads[q];
        if (alive[q] == 0) continue;
        const auto colors = quad_colors(list, p, quad.x, quad.y);
        for (unsigned k = 0; k < 4; ++k) {
            if ((alive[q] & (1u << k)) == 0) continue;
            const int x = quad.x + static_cast<int>(k & 1u);
            const int y = quad.y + static_cast<int>(k >> 1);
            merge(colors[k], tiles_->pixel(x, y));
            if (!fb.owner.empty())
                fb.owner[fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y))] =
                    p.owner;
        }
    }
}

FragmentTrace ScanlineKernel::trace(const ScanlineList& list, const ScanlinePrimitive& p, int x,
                                    int y, unsigned, const Framebuffer& fb) const {
    // The batch's float mode, as shade sets it (the border colour's clamp reads it).
    const ScopedDenormalMode plain(flush_ && !p.flush, false);
    FragmentTrace t;
    const ScanlinePlane* planes = list.planes.data() + p.planes;
    const auto& zp = planes[kScanlineZPlane];
    const auto& wp = planes[kScanlineWPlane];
    t.z_plane = {zp.a0, zp.dadx, zp.dady};
    t.w_plane = {wp.a0, wp.dadx, wp.dady};
    const int x0 = x & ~1;
    const int y0 = y & ~1;
    const auto k = static_cast<unsigned>((x & 1) + 2 * (y & 1));
    const std::size_t i = fb.index(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
    if (depth_) {
        float z = at(zp, x0, y0, k);
        if (p.clamp_depth) z = std::min(std::max(z, depth_min_), depth_max_);
        t.z = z;
        t.depth_tested = true;
        t.depth_value = softpipe_depth_value(z, fb.depth_format, depth_nearest_);
        t.depth_stored = fb.depth[i];
        t.depth_pass = (depth_pass_ & depth_outcome(t.depth_value, t.depth_stored,
                                                    fb.depth_format == DepthFormat::Z32f)) != 0;
    }
    t.shader_color = quad_colors(list, p, x0, y0)[k];
    t.textured = sampler_ != nullptr;
    t.destination = tiles_->peek(x, y);
    std::array<float, 4> written = t.destination;
    if (t.depth_pass) merge(t.shader_color, written.data());
    if (rgba8_) {
        for (auto& v : written) v = color_to_unorm8(v);
    }
    t.written = written;
    return t;
}

}  // namespace refraster::detail
