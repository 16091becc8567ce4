// resolve.cpp: a 4x framebuffer's resolve and its sample planes (framebuffer.hpp).
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "common/float_ops.hpp"
#include "refraster/framebuffer.hpp"
#include "stages/output_merge.hpp"

namespace refraster {

namespace {

// llvmpipe turns a unorm8 byte into a float as v * K, K the float nearest 1/255
// (lp_bld_conv.c: lp_build_unsigned_norm_to_float); cvt8(un8(v)) == v for every byte.
constexpr float kUnorm8ToFloat = 1.0f / 255.0f;

// The mean of one channel's four bytes, in the order and precision of the resolve shader
// below. Every value is 0 or at least 1/255 and every sum at most 4, so no operation meets a
// denormal: plain float arithmetic gives what the flushing one (Fp) gives.
std::uint8_t mean_of_bytes(std::uint8_t b0, std::uint8_t b1, std::uint8_t b2, std::uint8_t b3) {
    float sum = 0.0f;
    sum += static_cast<float>(b0) * kUnorm8ToFloat;
    sum += static_cast<float>(b1) * kUnorm8ToFloat;
    sum += static_cast<float>(b2) * kUnorm8ToFloat;
    sum += static_cast<float>(b3) * kUnorm8ToFloat;
    return detail::color_to_unorm8(sum * 0.25f);
}

// The resolve of an rgba8 target: a pixel whose four samples hold the same bytes (inside a
// primitive, the most of a picture) takes each channel's mean of four equal bytes from a table
// made by the same arithmetic; the others compute theirs.
void resolve_rgba8(const Framebuffer& ms, Framebuffer& out) {
    std::array<std::uint8_t, 256> same{};
    for (unsigned v = 0; v < 256; ++v) {
        const auto b = static_cast<std::uint8_t>(v);
        same[v] = mean_of_bytes(b, b, b, b);
    }
    const std::size_t n = ms.pixel_count();
    const std::uint8_t* in = ms.color8.data();
    std::uint8_t* to = out.color8.data();
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t* px = in + i * 16;
        std::uint32_t s[4];
        std::memcpy(s, px, sizeof s);
        if (s[0] == s[1] && s[0] == s[2] && s[0] == s[3]) {
            for (std::size_t c = 0; c < 4; ++c) to[i * 4 + c] = same[px[c]];
        } else {
            for (std::size_t c = 0; c < 4; ++c)
                to[i * 4 + c] = mean_of_bytes(px[c], px[4 + c], px[8 + c], px[12 + c]);
        }
    }
}

}  // namespace

Framebuffer resolve_samples(const Framebuffer& ms) {
    REFRASTER_ASSERT(ms.samples == 1 || ms.samples == 4, "a 1x or 4x framebuffer");
    if (ms.samples == 1) return ms;
    Framebuffer out(ms.width, ms.height, ms.color_format, ms.depth_format);
    const std::size_t n = ms.pixel_count();
    // The resolve shader runs inside llvmpipe's rasterizer, which flushes denormals
    // (lp_rast.c: util_fpstate_set_denorms_to_zero).
    const detail::Fp fp{true};
    if (ms.color_format == ColorFormat::Rgba8) {
        resolve_rgba8(ms, out);
    }
    for (std::size_t i = 0; i < n && ms.color_format != ColorFormat::Rgba8; ++i) {
        for (std::size_t c = 0; c < 4; ++c) {
            // Summed in sample order from +0, then scaled: ((((+0 + f0) + f1) + f2) + f3),
            // times 0.25 (u_simple_shaders.c: util_make_fs_msaa_resolve). Starting from +0
            // only shows when every sample is -0 (or a flushed negative denormal): the sum
            // is then +0, measured with rgba32f samples.
            float sum = 0.0f;
            for (std::size_t s = 0; s < 4; ++s) {
                const std::size_t k = (i * 4 + s) * 4 + c;
                const float f = ms.color_format == ColorFormat::Rgba8
                                    ? fp.mul(static_cast<float>(ms.color8[k]), kUnorm8ToFloat)
                                    : ms.color32f[k];
                sum = fp.add(sum, f);
            }
            const float mean = fp.mul(sum, 0.25f);
            if (ms.color_format == ColorFormat::Rgba8) {
                out.color8[i * 4 + c] = detail::color_to_unorm8(mean);
            } else {
                out.color32f[i * 4 + c] = mean;
            }
        }
    }
    if (ms.depth_format != DepthFormat::None) {
        for (std::size_t i = 0; i < n; ++i) out.depth[i] = ms.depth[i * 4];
    }
    if (!ms.owner.empty()) {
        out.owner.resize(n);
        for (std::size_t i = 0; i < n; ++i) out.owner[i] = ms.owner[i * 4];
    }
    return out;
}

Framebuffer sample_plane(const Framebuffer& ms, std::uint32_t s) {
    REFRASTER_ASSERT(s < ms.samples, "a sample of the framebuffer");
    Framebuffer out(ms.width, ms.height, ms.color_format, ms.depth_format);
    const std::size_t n = ms.pixel_count();
    const std::size_t k = ms.samples;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t from = i * k + s;
        for (std::size_t c = 0; c < 4; ++c) {
            if (ms.color_format == ColorFormat::Rgba8) {
                out.color8[i * 4 + c] = ms.color8[from * 4 + c];
            } else {
                out.color32f[i * 4 + c] = ms.color32f[from * 4 + c];
            }
        }
        if (ms.depth_format != DepthFormat::None) out.depth[i] = ms.depth[from];
    }
    if (!ms.owner.empty()) {
        out.owner.resize(n);
        for (std::size_t i = 0; i < n; ++i) out.owner[i] = ms.owner[i * k + s];
    }
    return out;
}

}  // namespace refraster
