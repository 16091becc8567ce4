#include "models/llvmpipe/fragment.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "models/llvmpipe/vector_kernels.hpp"
#include "refraster/assert.hpp"
#include "stages/rules.hpp"
#include "stages/samples.hpp"

// Kernels also compiled for a wider instruction set, chosen at run time (GCC and clang on
// x86-64; elsewhere only the baseline kernels exist).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define REFRASTER_KERNEL_ISA_VARIANTS 1
#else
#define REFRASTER_KERNEL_ISA_VARIANTS 0
#endif

namespace refraster::detail {

namespace {

// One draw's per-pixel stage, for one combination of its state; D is DepthFormat::None when
// the draw has no depth test. Samples: one a pixel (sample 0 of each packet pixel), or four
// (a 4x target): colour once a pixel, depth, blending and stores a sample.
template <ShadeModel S, DepthFormat D, ColorFormat C, BlendPreset B, unsigned kSamples>
struct Kernel {
    static_assert(kSamples == 1 || kSamples == kMsaaSamples, "1 or 4 samples a pixel");

    // lp_bld_interp.c attribs_update_simple: fmuladd(dady, py, fmuladd(dadx, px, A0)).
    [[gnu::always_inline]] static float plane_at(const Plane& p, float px, float py,
                                                 const KernelState& k, const Fp& fp) {
        if (k.options.fma) return fp.fma(p.dady, py, fp.fma(p.dadx, px, p.a0));
        return fp.add(fp.mul(p.dady, py), fp.add(fp.mul(p.dadx, px), p.a0));
    }

    // z plus the offset, clamped, quantised (lp_bld_depth.c); `z` receives the clamped value.
    [[gnu::always_inline]] static std::uint32_t depth_value(const Plane* planes, float z_offset,
                                                            float px, float py,
                                                            const KernelState& k, const Fp& fp,
                                                            float& z) {
        z = clamp_depth(fp.add(plane_at(planes[kZPlane], px, py, k, fp), z_offset));
        if (k.options.depth_truncate) return truncate_depth(z, D);
        return quantise_depth(z, D);
    }

    // The first N attributes (the colour, then s, t, r, q for a textured draw) at (px, py):
    // flat ones the provoking vertex's, noperspective ones the plane, smooth ones the plane
    // times 1 / (the 1/w plane).
    template <std::size_t N>
    [[gnu::always_inline]] static std::array<float, N> attributes(const Plane* planes,
                                                                  const float* flat, float px,
                                                                  float py, const KernelState& k,
                                                                  const Fp& fp) {
        std::array<float, N> a{};
        if constexpr (S == ShadeModel::Flat) {
            std::copy(flat, flat + N, a.begin());
        } else if constexpr (S == ShadeModel::NoPerspective) {
            for (std::size_t j = 0; j < N; ++j)
                a[j] = plane_at(planes[kFirstAttributePlane + j], px, py, k, fp);
        } else {
            const float w = fp.div(
                1.0f, plane_at(planes[kWPlane], px, py, k, fp));  // lp_build_rcp: a true division
            for (std::size_t j = 0; j < N; ++j)
                a[j] = fp.mul(plane_at(planes[kFirstAttributePlane + j], px, py, k, fp), w);
        }
        return a;
    }

    [[gnu::always_inline]] static std::array<float, 4> color(const Plane* planes, const float* flat,
                                                             float px, float py,
                                                             const KernelState& k, const Fp& fp) {
        return attributes<4>(planes, flat, px, py, k, fp);
    }

    // The colours of a textured draw's quad: every pixel of the packet, covered or not (the
    // level of detail is the quad's, from helper pixels too: docs/precision.md, "Textures").
    // Coordinates are projected as textureProj does it: s and t times 1/q (lp_build_rcp, a
    // true division). Modulate multiplies the interpolated colour by the texel in float.
    // A textured draw's attribute floats: the colour, then s, t, r, q.
    static constexpr std::size_t kTexturedFloats = 8;

    static std::array<std::array<float, 4>, 4> textured_quad(const KernelState& k,
                                                             const Plane* planes, const float* flat,
                                                             std::int32_t qx, std::int32_t qy,
                                                             float centre, const Fp& fp,
                                                             TexelSample* trace = nullptr,
                                                             unsigned trace_pixel = 0) {
        std::array<float, 4> s{}, t{};
        std::array<std::array<float, 4>, 4> col{};
        const auto coords = [&](std::int32_t x0, std::array<float, 4>& ss, std::array<float, 4>& ts,
                                std::array<std::array<float, 4>, 4>* c) {
            for (unsigned p = 0; p < 4; ++p) {
                const float px =
                    static_cast<float>(x0 + static_cast<std::int32_t>(p & 1u)) + centre;
                const float py =
                    static_cast<float>(qy + static_cast<std::int32_t>(p >> 1)) + centre;
                if (k.point_coords) {
                    // Point sprite coordinates (point_planes): perspective planes after the
                    // attributes, sampled without projection (texture at gl_PointCoord).
                    constexpr std::size_t kSprite =
                        kFirstAttributePlane + (S == ShadeModel::Flat ? 0 : kTexturedFloats);
                    const float w = fp.div(1.0f, plane_at(planes[kWPlane], px, py, k, fp));
                    ss[p] = fp.mul(plane_at(planes[kSprite], px, py, k, fp), w);
                    ts[p] = fp.mul(plane_at(planes[kSprite + 1], px, py, k, fp), w);
                    if (c != nullptr) (*c)[p] = attributes<4>(planes, flat, px, py, k, fp);
                    continue;
                }
                const auto a = attributes<kTexturedFloats>(planes, flat, px, py, k, fp);
                const float rq = fp.div(1.0f, a[7]);
                ss[p] = fp.mul(a[4], rq);
                ts[p] = fp.mul(a[5], rq);
                if (c != nullptr) (*c)[p] = {a[0], a[1], a[2], a[3]};
            }
        };
        coords(qx, s, t, &col);
        // The other quad of the shader's eight-pixel vector (lp_state_fs.c: a 4x4 block in two
        // vectors of two quads side by side), covered or not.
        bool pair_linear = false;
        if (k.texture->soa_nearest_as_linear) {
            std::array<float, 4> ps{}, pt{};
            coords(qx ^ 2, ps, pt, nullptr);
            pair_linear = quad_takes_linear(*k.texture, ps, pt);
        }
        std::array<std::array<float, 4>, 4> out{};
        {
            // The sampler's plain operations run under the CPU's flush modes where the profile
            // flushes, as llvmpipe's rasterizer threads run (set for the whole kernel already
            // on the fast path, whose options then say no flushing).
            const ScopedDenormalsAreZero mode(k.options.flush_denormals &&
                                              cpu_flush_modes_available());
            sample_quad(*k.texture, s, t, k.options.fma, out, pair_linear, trace, trace_pixel);
        }
        if (trace != nullptr) trace->point_coord = k.point_coords;
        if (k.texture->state.env == TextureEnv::Modulate) {
            for (unsigned p = 0; p < 4; ++p)
                for (std::size_t c = 0; c < 4; ++c) out[p][c] = fp.mul(col[p][c], out[p][c]);
        }
        return out;
    }

    // A 4x target (docs/precision.md, "Multisampling (4x)"). With multisampling on, the
    // planes were set up with pixel offset 0: colour is evaluated once at the pixel centre
    // (px + 0.5, py + 0.5) and goes to every covered sample; depth is evaluated at each
    // covered sample's position (px + sx, py + sy), tested and written per sample; blending
    // reads each sample's own destination. With it off (a single-sample draw into a 4x
    // target), coverage, colour and depth are the single-sample ones, at the pixel: the depth
    // test reads and writes sample 0 only, and a pixel that passes is blended and written in
    // all four samples (measured: samples 1 to 3 keep their depth).
    static void shade_4x(const KernelState& k, const SetupList& list, const SetupPrimitive& prim,
                         std::span<const QuadPacket> quads, Framebuffer& fb) {
        const Fp fp{k.options.flush_denormals};
        const Plane* planes = list.planes.data() + prim.planes;
        const float* flat = list.flat.data() + prim.flat;
        const bool owners = !fb.owner.empty();
        const bool ms = k.options.multisample;
        const float centre = ms ? 0.5f : 0.0f;
        SourceColor<C> flat_source{};
        if constexpr (S == ShadeModel::Flat)
            flat_source =
                source_color<C>(k.options.color_truncate, color(planes, flat, 0, 0, k, fp));
        for (const QuadPacket& q : quads) {
            unsigned mask = q.mask;
            if (!ms) mask = (mask & kSample0Pixels) * 0x1111u;  // every sample of the pixel
            std::array<std::array<float, 4>, 4> textured{};
            if (k.texture != nullptr)
                textured = textured_quad(k, planes, flat, q.x, q.y, centre, fp);
            for (unsigned p = 0; p < 4; ++p) {
                if ((mask & (0x1111u << p)) == 0) continue;
                const auto x = static_cast<std::uint32_t>(q.x) + (p & 1u);
                const auto y = static_cast<std::uint32_t>(q.y) + (p >> 1);
                const float px = static_cast<float>(x);
                const float py = static_cast<float>(y);
                SourceColor<C> source{};
                if (k.texture != nullptr) {
                    source = source_color<C>(k.options.color_truncate, textured[p]);
                } else if constexpr (S == ShadeModel::Flat) {
                    source = flat_source;
                } else {
                    source = source_color<C>(k.options.color_truncate,
                                             color(planes, flat, px + centre, py + centre, k, fp));
                }
                if constexpr (D != DepthFormat::None) {
                    if (!ms) {
                        // One depth test for the pixel, at sample 0.
                        float z = 0.0f;
                        const std::uint32_t value =
                            depth_value(planes, prim.z_offset, px, py, k, fp, z);
                        const std::size_t i0 = fb.sample_index(x, y, 0);
                        if ((k.depth_pass & depth_outcome<D == DepthFormat::Z32f>(
                                                value, fb.depth[i0], k.options.flush_denormals)) ==
                            0)
                            continue;
                        if (k.depth_write) fb.depth[i0] = value;
                    }
                }
                for (unsigned s = 0; s < kMsaaSamples; ++s) {
                    if ((mask & (1u << quad_bit(p, s))) == 0) continue;
                    const std::size_t i = fb.sample_index(x, y, s);
                    if constexpr (D != DepthFormat::None) {
                        if (ms) {
                            float z = 0.0f;
                            const auto& pos = kSamplePositions4x[s];
                            const std::uint32_t value = depth_value(
                                planes, prim.z_offset, px + pos.x, py + pos.y, k, fp, z);
                            if ((k.depth_pass &
                                 depth_outcome<D == DepthFormat::Z32f>(
                                     value, fb.depth[i], k.options.flush_denormals)) == 0)
                                continue;
                            if (k.depth_write) fb.depth[i] = value;
                        }
                    }
                    store_color<C, B>(fb, i, source, fp);
                    if (owners) fb.owner[i] = prim.owner;
                }
            }
        }
    }

    static void shade(const KernelState& k, const SetupList& list, const SetupPrimitive& prim,
                      std::span<const QuadPacket> quads, Framebuffer& fb) {
        shade_body(k, list, prim, quads, fb);
    }

#if REFRASTER_KERNEL_ISA_VARIANTS
    // The same kernel compiled for CPUs with FMA and SSE4.1 (chosen at run time, never
    // assumed at build time): everything it calls is inlined into it (flatten), so that
    // std::fma becomes one fused instruction and std::nearbyint one roundss instead of
    // library calls. The operations and their order are the body's: the bytes do not change.
    [[gnu::target("fma,sse4.1,popcnt"), gnu::flatten]] static void shade_fma(
        const KernelState& k, const SetupList& list, const SetupPrimitive& prim,
        std::span<const QuadPacket> quads, Framebuffer& fb) {
        shade_body(k, list, prim, quads, fb);
    }
#endif

    [[gnu::always_inline]] static inline void shade_body(const KernelState& k,
                                                         const SetupList& list,
                                                         const SetupPrimitive& prim,
                                                         std::span<const QuadPacket> quads,
                                                         Framebuffer& fb) {
        if constexpr (kSamples == kMsaaSamples) {
            shade_4x(k, list, prim, quads, fb);
            return;
        }
        const Fp fp{k.options.flush_denormals};
        const PrimitiveInputs in(k, list, prim, fb, fp);
        if (k.texture != nullptr) {
            for (const QuadPacket& q : quads) {
                const auto colors = textured_quad(k, in.planes, in.flat, q.x, q.y, 0.0f, fp);
                for (unsigned p = 0; p < 4; ++p) {
                    if ((q.mask & (1u << quad_bit(p, 0))) == 0) continue;
                    shade_pixel_colored(k, in, prim, static_cast<std::uint32_t>(q.x) + (p & 1u),
                                        static_cast<std::uint32_t>(q.y) + (p >> 1), fb, fp,
                                        colors[p]);
                }
            }
            return;
        }
        for (const QuadPacket& q : quads) {
            for (unsigned p = 0; p < 4; ++p) {
                if ((q.mask & (1u << quad_bit(p, 0))) == 0) continue;
                shade_pixel(k, in, prim, static_cast<std::uint32_t>(q.x) + (p & 1u),
                            static_cast<std::uint32_t>(q.y) + (p >> 1), fb, fp);
            }
        }
    }

    // What every pixel of a primitive reads, fetched once.
    struct PrimitiveInputs {
        const Plane* planes;
        const float* flat;
        bool owners;
        SourceColor<C> flat_source{};
        [[gnu::always_inline]] PrimitiveInputs(const KernelState& k, const SetupList& list,
                                               const SetupPrimitive& prim, const Framebuffer& fb,
                                               const Fp& fp)
            : planes(list.planes.data() + prim.planes),
              flat(list.flat.data() + prim.flat),
              owners(!fb.owner.empty()) {
            if constexpr (S == ShadeModel::Flat)
                flat_source =
                    source_color<C>(k.options.color_truncate, color(planes, flat, 0, 0, k, fp));
        }
    };

    // One pixel of a single-sample target: depth test and write, colour, blending, owner.
    [[gnu::always_inline]] static inline void shade_pixel(const KernelState& k,
                                                          const PrimitiveInputs& in,
                                                          const SetupPrimitive& prim,
                                                          std::uint32_t x, std::uint32_t y,
                                                          Framebuffer& fb, const Fp& fp) {
        const float px = static_cast<float>(x);
        const float py = static_cast<float>(y);
        const std::size_t i = fb.index(x, y);
        if constexpr (D != DepthFormat::None) {
            float z = 0.0f;
            const std::uint32_t value = depth_value(in.planes, prim.z_offset, px, py, k, fp, z);
            if ((k.depth_pass & depth_outcome<D == DepthFormat::Z32f>(
                                    value, fb.depth[i], k.options.flush_denormals)) == 0)
                return;
            if (k.depth_write) fb.depth[i] = value;
        }
        if constexpr (S == ShadeModel::Flat) {
            store_color<C, B>(fb, i, in.flat_source, fp);
        } else {
            store_color<C, B>(
                fb, i,
                source_color<C>(k.options.color_truncate, color(in.planes, in.flat, px, py, k, fp)),
                fp);
        }
        if (in.owners) fb.owner[i] = prim.owner;
    }

    // One pixel of a single-sample target given its colour (a textured draw).
    static void shade_pixel_colored(const KernelState& k, const PrimitiveInputs& in,
                                    const SetupPrimitive& prim, std::uint32_t x, std::uint32_t y,
                                    Framebuffer& fb, const Fp& fp, const std::array<float, 4>& c) {
        const std::size_t i = fb.index(x, y);
        if constexpr (D != DepthFormat::None) {
            float z = 0.0f;
            const std::uint32_t value = depth_value(in.planes, prim.z_offset, static_cast<float>(x),
                                                    static_cast<float>(y), k, fp, z);
            if ((k.depth_pass & depth_outcome<D == DepthFormat::Z32f>(
                                    value, fb.depth[i], k.options.flush_denormals)) == 0)
                return;
            if (k.depth_write) fb.depth[i] = value;
        }
        store_color<C, B>(fb, i, source_color<C>(k.options.color_truncate, c), fp);
        if (in.owners) fb.owner[i] = prim.owner;
    }

    // The same per-pixel stage over row blocks (single-sample targets only).
    [[gnu::always_inline]] static inline void shade_rows_body(const KernelState& k,
                                                              const SetupList& list,
                                                              const SetupPrimitive& prim,
                                                              const RowBlock& b, Framebuffer& fb) {
        const Fp fp{k.options.flush_denormals};
        const PrimitiveInputs in(k, list, prim, fb, fp);
        for (int r = 0; r < b.rows; ++r) {
            std::uint64_t m = b.mask[r];
            const auto y = static_cast<std::uint32_t>(b.y0 + r);
            while (m != 0) {
                const auto x = static_cast<std::uint32_t>(b.x0 + std::countr_zero(m));
                shade_pixel(k, in, prim, x, y, fb, fp);
                m &= m - 1;
            }
        }
    }
    static void shade_rows(const KernelState& k, const SetupList& list, const SetupPrimitive& prim,
                           const RowBlock& b, Framebuffer& fb) {
        shade_rows_body(k, list, prim, b, fb);
    }
#if REFRASTER_KERNEL_ISA_VARIANTS
    [[gnu::target("fma,sse4.1,popcnt,bmi"), gnu::flatten]] static void shade_rows_fma(
        const KernelState& k, const SetupList& list, const SetupPrimitive& prim, const RowBlock& b,
        Framebuffer& fb) {
        shade_rows_body(k, list, prim, b, fb);
    }
#endif

    // Sample `sample` of the pixel (0 for a single-sample target).
    static FragmentTrace trace(const KernelState& k, const SetupList& list,
                               const SetupPrimitive& prim, int x, int y, unsigned sample,
                               const Framebuffer& fb_before) {
        const Fp fp{k.options.flush_denormals};
        const Plane* planes = list.planes.data() + prim.planes;
        const float* flat = list.flat.data() + prim.flat;
        const float px = static_cast<float>(x);
        const float py = static_cast<float>(y);
        const std::size_t i = fb_before.sample_index(static_cast<std::uint32_t>(x),
                                                     static_cast<std::uint32_t>(y), sample);
        // Where colour and depth are evaluated (shade_4x).
        const bool ms = kSamples == kMsaaSamples && k.options.multisample;
        const float centre = ms ? 0.5f : 0.0f;
        const float zx = ms ? px + kSamplePositions4x[sample].x : px;
        const float zy = ms ? py + kSamplePositions4x[sample].y : py;
        FragmentTrace t;
        const Plane& zp = planes[kZPlane];
        const Plane& wp = planes[kWPlane];
        t.z_plane = {zp.a0, zp.dadx, zp.dady};
        t.w_plane = {wp.a0, wp.dadx, wp.dady};
        t.z_offset = prim.z_offset;
        t.depth_tested = D != DepthFormat::None;
        if constexpr (D != DepthFormat::None) {
            t.depth_value = depth_value(planes, prim.z_offset, zx, zy, k, fp, t.z);
            // With multisampling off on a 4x target the test reads sample 0 (shade_4x).
            const std::size_t di = kSamples == kMsaaSamples && !ms
                                       ? fb_before.sample_index(static_cast<std::uint32_t>(x),
                                                                static_cast<std::uint32_t>(y), 0)
                                       : i;
            t.depth_stored = fb_before.depth[di];
            t.depth_pass =
                (k.depth_pass & depth_outcome<D == DepthFormat::Z32f>(
                                    t.depth_value, t.depth_stored, k.options.flush_denormals)) != 0;
        }
        if (k.texture != nullptr) {
            // The pixel's quad, helper pixels included.
            const unsigned p = static_cast<unsigned>((x & 1) | ((y & 1) << 1));
            t.textured = true;
            t.shader_color =
                textured_quad(k, planes, flat, x & ~1, y & ~1, centre, fp, &t.texture, p)[p];
        } else {
            t.shader_color = color(planes, flat, px + centre, py + centre, k, fp);
        }
        Framebuffer one(1, 1, fb_before.color_format, DepthFormat::None);
        for (std::size_t c = 0; c < 4; ++c) {
            if constexpr (C == ColorFormat::Rgba8) {
                one.color8[c] = fb_before.color8[4 * i + c];
                t.destination[c] = one.color8[c];
            } else {
                one.color32f[c] = fb_before.color32f[4 * i + c];
                t.destination[c] = one.color32f[c];
            }
        }
        if (t.depth_pass)
            store_color<C, B>(one, 0, source_color<C>(k.options.color_truncate, t.shader_color),
                              fp);
        for (std::size_t c = 0; c < 4; ++c) {
            t.written[c] = C == ColorFormat::Rgba8 ? one.color8[c] : one.color32f[c];
        }
        return t;
    }
};

template <ShadeModel S, DepthFormat D, ColorFormat C, BlendPreset B>
FragmentKernel make_kernel(KernelState state) {
    const KernelPath path = state.options.kernels;
    if (state.samples == kMsaaSamples) {
        using K4 = Kernel<S, D, C, B, kMsaaSamples>;
        if (path == KernelPath::Model) return {state, &K4::shade, &K4::trace};
        if constexpr (C == ColorFormat::Rgba8) {
            // 4x row blocks on the vector paths for untextured draws with multisampling on.
            if (state.texture == nullptr && state.options.multisample) {
                if (auto* fn = vector_shade_rows(path, S, D, B, kMsaaSamples))
                    return {state, &K4::shade, &K4::trace, fn, state.options.flush_denormals};
            }
        }
#if REFRASTER_KERNEL_ISA_VARIANTS
        if (host_runs_fma_sse41()) return {state, &K4::shade_fma, &K4::trace};
#endif
        return {state, &K4::shade, &K4::trace};
    }
    using K = Kernel<S, D, C, B, 1>;
    if (path == KernelPath::Model) return {state, &K::shade, &K::trace};
    if (state.texture != nullptr) {
        if constexpr (C == ColorFormat::Rgba8) {
            // Row blocks on the vector paths where the vector sampler serves the unit: each
            // lane evaluates its own quad's coordinates for the level of detail.
            if (vector_sampler_serves(*state.texture, state.point_coords)) {
                if (auto* fn = vector_textured_shade_rows(path, S, D, B))
                    return {state, &K::shade, &K::trace, fn, state.options.flush_denormals};
            }
        }
        // Otherwise quads: the level of detail is a quad's. Where the profile flushes and the CPU
        // has the modes, the kernel runs under them (hardware_denormals) with plain operations:
        // the same results as the emulated flushes, depth compares included (depth_outcome).
        KernelState plain = state;
        const bool hardware = state.options.flush_denormals && cpu_flush_modes_available();
        if (hardware) plain.options.flush_denormals = false;
#if REFRASTER_KERNEL_ISA_VARIANTS
        if (host_runs_fma_sse41()) return {plain, &K::shade_fma, &K::trace, nullptr, hardware};
#endif
        return {plain, &K::shade, &K::trace, nullptr, hardware};
    }
    if constexpr (C == ColorFormat::Rgba8) {
        // The vector kernels write rgba8; rgba32f targets take the scalar path.
        if (auto* fn = vector_shade_rows(path, S, D, B)) {
            return {state, &K::shade, &K::trace, fn, state.options.flush_denormals};
        }
    }
#if REFRASTER_KERNEL_ISA_VARIANTS
    if (host_runs_fma_sse41()) return {state, &K::shade_fma, &K::trace, &K::shade_rows_fma};
#endif
    return {state, &K::shade, &K::trace, &K::shade_rows};
}

template <ShadeModel S, DepthFormat D, ColorFormat C>
FragmentKernel pick_blend(const Draw& draw, KernelState state) {
    switch (draw.state.blend) {
        case BlendPreset::None:
            return make_kernel<S, D, C, BlendPreset::None>(state);
        case BlendPreset::Alpha:
            return make_kernel<S, D, C, BlendPreset::Alpha>(state);
        case BlendPreset::Add:
            return make_kernel<S, D, C, BlendPreset::Add>(state);
    }
    return make_kernel<S, D, C, BlendPreset::None>(state);
}

template <ShadeModel S, DepthFormat D>
FragmentKernel pick_color(const Draw& draw, const Target& target, KernelState state) {
    if (target.color == ColorFormat::Rgba8)
        return pick_blend<S, D, ColorFormat::Rgba8>(draw, state);
    return pick_blend<S, D, ColorFormat::Rgba32f>(draw, state);
}

template <ShadeModel S>
FragmentKernel pick_depth(const Draw& draw, const Target& target, KernelState state) {
    if (!draw.state.depth_test) return pick_color<S, DepthFormat::None>(draw, target, state);
    switch (target.depth) {
        case DepthFormat::Z16:
            return pick_color<S, DepthFormat::Z16>(draw, target, state);
        case DepthFormat::Z24:
            return pick_color<S, DepthFormat::Z24>(draw, target, state);
        case DepthFormat::Z32f:
            return pick_color<S, DepthFormat::Z32f>(draw, target, state);
        case DepthFormat::None:
            break;
    }
    return pick_color<S, DepthFormat::None>(draw, target, state);
}

}  // namespace

FragmentKernel choose_fragment_kernel(const Draw& draw, const Target& target,
                                      FragmentOptions options, const TextureUnit* texture) {
    KernelState state;
    state.options = options;
    state.texture = texture;
    state.point_coords = texture != nullptr && draw.samples_point_coords();
    state.samples = target.samples;
    if (draw.state.depth_test && target.depth != DepthFormat::None) {
        state.depth_pass = static_cast<std::uint8_t>(*draw.state.depth_test);
        state.depth_write = draw.state.depth_write;
    }
    switch (draw.state.shade) {
        case ShadeModel::Flat:
            return pick_depth<ShadeModel::Flat>(draw, target, state);
        case ShadeModel::NoPerspective:
            return pick_depth<ShadeModel::NoPerspective>(draw, target, state);
        case ShadeModel::Smooth:
            break;
    }
    return pick_depth<ShadeModel::Smooth>(draw, target, state);
}

}  // namespace refraster::detail
