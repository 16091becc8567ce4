// softpipe_fragment.cpp: softpipe's quad pipeline (softpipe_fragment.hpp).
#include "softpipe_fragment.hpp"

#include <algorithm>
#include <bit>

#include "fragment.hpp"

namespace refraster::detail {

namespace {

// The value of plane `p` at pixel k (0..3) of the quad at (x0, y0).
float at(const ScanlinePlane& p, int x0, int y0, unsigned k) {
    return scanline_quad(p, x0, y0)[k];
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

float softpipe_blend(BlendPreset preset, float s, float a, float d) {
    switch (preset) {
        case BlendPreset::Alpha:
            return s * a + d * (1.0f - a);
        case BlendPreset::Add:
            return s + d;
        case BlendPreset::None:
            break;
    }
    return s;
}

ScanlineKernel::ScanlineKernel(const Draw& draw, const Target& target) : draw_(draw) {
    depth_ = draw.state.depth_test.has_value() && target.depth != DepthFormat::None;
    if (depth_) depth_pass_ = static_cast<std::uint8_t>(*draw.state.depth_test);
}

void ScanlineKernel::fragment(const ScanlineList& list, const ScanlinePrimitive& p, int x0, int y0,
                              unsigned k, Framebuffer& fb, FragmentTrace* t) const {
    const auto x = static_cast<std::uint32_t>(x0 + static_cast<int>(k & 1u));
    const auto y = static_cast<std::uint32_t>(y0 + static_cast<int>(k >> 1));
    const std::size_t i = fb.index(x, y);
    const ScanlinePlane* planes = list.planes.data() + p.planes;
    if (t != nullptr) {
        const auto& z = planes[kScanlineZPlane];
        const auto& w = planes[kScanlineWPlane];
        t->z_plane = {z.a0, z.dadx, z.dady};
        t->w_plane = {w.a0, w.dadx, w.dady};
    }
    if (depth_) {
        // sp_quad_depth_test.c: the quad's z (the position input's linear plane), then
        // convert_quad_depth.
        const float z = at(planes[kScanlineZPlane], x0, y0, k);
        const std::uint32_t value = scanline_depth_value(z, fb.depth_format);
        const std::uint32_t stored = fb.depth[i];
        const bool pass =
            (depth_pass_ & depth_outcome(value, stored, fb.depth_format == DepthFormat::Z32f)) != 0;
        if (t != nullptr) {
            t->z = std::clamp(z, 0.0f, 1.0f);
            t->depth_tested = true;
            t->depth_value = value;
            t->depth_stored = stored;
            t->depth_pass = pass;
        }
        if (!pass) return;
        if (draw_.state.depth_write) fb.depth[i] = value;
    }
    // The colour: attributes 0..3 of the vertex (the "color" attribute).
    std::array<float, 4> c{};
    const float w = p.interp == ScanlineInterp::Perspective
                        ? at(planes[kScanlineWPlane], x0, y0, k)
                        : 1.0f;
    for (std::size_t ch = 0; ch < 4; ++ch) {
        const ScanlinePlane& a = planes[kScanlineFirstAttribute + ch];
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
    std::array<float, 4> written{};
    if (fb.color_format == ColorFormat::Rgba8) {
        std::uint8_t* px = fb.color8.data() + 4 * i;
        if (t != nullptr) {
            for (std::size_t ch = 0; ch < 4; ++ch) t->destination[ch] = px[ch] / 255.0f;
        }
        if (draw_.state.blend == BlendPreset::None) {
            for (std::size_t ch = 0; ch < 4; ++ch) px[ch] = color_to_unorm8(c[ch]);
        } else {
            const float a = std::clamp(c[3], 0.0f, 1.0f);
            for (std::size_t ch = 0; ch < 4; ++ch) {
                const float s = std::clamp(c[ch], 0.0f, 1.0f);
                const float d = static_cast<float>(px[ch]) / 255.0f;
                px[ch] = color_to_unorm8(softpipe_blend(draw_.state.blend, s, a, d));
            }
        }
        for (std::size_t ch = 0; ch < 4; ++ch) written[ch] = px[ch];
    } else {
        float* px = fb.color32f.data() + 4 * i;
        if (t != nullptr) std::copy(px, px + 4, t->destination.begin());
        for (std::size_t ch = 0; ch < 4; ++ch)
            px[ch] = softpipe_blend(draw_.state.blend, c[ch], c[3], px[ch]);
        std::copy(px, px + 4, written.begin());
    }
    if (!fb.owner.empty()) fb.owner[i] = p.owner;
    if (t != nullptr) {
        t->shader_color = c;
        t->written = written;
    }
}

void ScanlineKernel::shade(const ScanlineList& list, const ScanlinePrimitive& p,
                           std::span<const QuadPacket> quads, Framebuffer& fb) const {
    for (const QuadPacket& q : quads) {
        for (unsigned k = 0; k < 4; ++k) {
            if ((q.mask & (1u << quad_bit(k, 0))) != 0) fragment(list, p, q.x, q.y, k, fb, nullptr);
        }
    }
}

FragmentTrace ScanlineKernel::trace(const ScanlineList& list, const ScanlinePrimitive& p, int x,
                                    int y, unsigned, const Framebuffer& fb) const {
    FragmentTrace t;
    Framebuffer scratch = fb;  // the fragment is traced, not drawn
    const unsigned k = static_cast<unsigned>((x & 1) + 2 * (y & 1));
    fragment(list, p, x & ~1, y & ~1, k, scratch, &t);
    return t;
}

}  // namespace refraster::detail
