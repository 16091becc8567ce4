// fragment.hpp: from a set-up primitive to bytes in the framebuffer, as llvmpipe computes them.
//
// Implements (the planes it evaluates are set up in planes.hpp):
//  - per-pixel evaluation (lp_bld_interp.c, attribs_update_simple) at the pixel's integer
//    coordinates: fmuladd(dady, py, fmuladd(dadx, px, A0)), fused when FMA is on; smooth
//    values times 1 / (the 1/w plane's value), a true division.
//  - depth: z plus the offset, clamped to [0, 1] (lp_build_depth_clamp: min with 1, then max
//    with 0, with x86 minps/maxps semantics, so NaN becomes 1), quantised
//    RNE(fl(z * (2^n - 1))) for z16 and z24 (lp_build_clamped_float_to_unsigned_norm) or kept
//    as float for z32f, the eight compare functions on those values, writes when enabled.
//  - colour output: rgba8 RNE(fl(c * 255)) of the clamped colour (lp_build_conv); rgba32f
//    unclamped; blending per scene format's presets: on rgba8 in 8-bit fixed point with
//    M(x, y) = (x*y + ((x*y) >> 8) + 128) >> 8 and saturating adds (lp_bld_blend; measured,
//    docs/precision.md "Colour output and blending"); on rgba32f in float, unfused.
//  - fragment kernels: the per-pixel stage compiled for one draw's state (shade model, depth
//    format with the test on or off, colour format, blend preset, sample count), chosen once
//    per draw, so that a pixel meets no switch on that state; the depth function becomes the
//    draw's mask of passing outcomes (less, equal, greater: GL's own encoding of the eight
//    functions). A draw without a depth test does no depth work, a flat draw evaluates no
//    attribute plane, and a flat colour is converted once per primitive.
//
//  - 4x targets: kernels for four samples a pixel (colour once at the centre, depth and the
//    output merge per sample), or the single-sample result repeated into every sample when
//    the draw turns multisampling off; on the vector paths, untextured multisampled draws
//    into rgba8 read 4x row blocks (vector_kernel_body.hpp, shade_rows_4x).
//
// Deliberately does not: stencil, colour masks, blend equations other than the two presets,
// sample shading or centroid interpolation.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "common/float_ops.hpp"
#include "models/llvmpipe/setup_list.hpp"
#include "models/llvmpipe/texture.hpp"
#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/renderer.hpp"
#include "refraster/trace.hpp"
#include "stages/output_merge.hpp"
#include "stages/quad.hpp"
#include "stages/row_block.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

struct FragmentOptions {
    bool fma = true;
    bool flush_denormals = true;
    // SetupParams::multisample: planes are set up with pixel offset 0 (A0 at the pixel's
    // corner) and evaluated at the pixel centre for colour, at each sample for depth.
    bool multisample = false;
    KernelPath kernels = KernelPath::Model;  // resolved (resolve_kernel_path)
    // The profile's depth_rounding and color_rounding are truncation (the Model path only: the
    // renderer chooses it for such profiles).
    bool depth_truncate = false;
    bool color_truncate = false;
    // The profile's offset_units_scale: polygon offset's units are multiplied by it first.
    float offset_units_scale = 1.0f;
};

// The draw's state as a fragment kernel reads it at run time.
struct KernelState {
    // The draw's texture unit (texture.hpp), or null for an untextured draw: the fragment's
    // colour is then the texel (replace) or the colour times it (modulate), sampled a quad at
    // a time at the texture coordinates (attributes 4 to 7) divided by q.
    const TextureUnit* texture = nullptr;
    // Draw::samples_point_coords: s and t come from the two planes after the attributes
    // (point_planes), as a perspective input, and are not divided by q.
    bool point_coords = false;
    std::uint8_t depth_pass = 7;  // outcomes that pass: 1 less, 2 equal, 4 greater
    bool depth_write = false;
    std::uint32_t samples = 1;  // of the target: 1 or 4
    FragmentOptions options;
};

// The per-pixel stage of one draw: shades quad packets of a set-up primitive into the
// framebuffer (depth test, colour, blending, owner), or traces one pixel of it.
class FragmentKernel {
  public:
    using ShadeFn = void (*)(const KernelState&, const SetupList&, const SetupPrimitive&,
                             std::span<const QuadPacket>, Framebuffer&);
    using ShadeRowsFn = void (*)(const KernelState&, const SetupList&, const SetupPrimitive&,
                                 const RowBlock&, Framebuffer&);
    using TraceFn = FragmentTrace (*)(const KernelState&, const SetupList&, const SetupPrimitive&,
                                      int, int, unsigned, const Framebuffer&);
    FragmentKernel(KernelState state, ShadeFn shade_fn, TraceFn trace_fn,
                   ShadeRowsFn shade_rows_fn = nullptr, bool hardware_denormals = false)
        : state_(state),
          shade_(shade_fn),
          trace_(trace_fn),
          shade_rows_(shade_rows_fn),
          hardware_denormals_(hardware_denormals) {}

    void shade(const SetupList& list, const SetupPrimitive& prim, std::span<const QuadPacket> quads,
               Framebuffer& fb) const {
        shade_(state_, list, prim, quads, fb);
    }
    // Whether the kernel reads row blocks (single-sample targets on every path but the model;
    // 4x row blocks for untextured multisampled draws into rgba8 on the vector paths);
    // shade_rows then replaces shade.
    bool shades_rows() const { return shade_rows_ != nullptr; }
    void shade_rows(const SetupList& list, const SetupPrimitive& prim, const RowBlock& block,
                    Framebuffer& fb) const {
        shade_rows_(state_, list, prim, block, fb);
    }
    // Whether the kernel must run with the CPU's flush-to-zero and denormals-are-zero modes
    // on (ScopedDenormalsAreZero, float_env.hpp): the vector kernels flush as llvmpipe's
    // rasterizer threads do, by the hardware, instead of testing every result.
    bool hardware_denormals() const { return hardware_denormals_; }
    // The kernel path the kernel was chosen for (resolved).
    KernelPath path() const { return state_.options.kernels; }
    // The decisions about sample `sample` of pixel (x, y) of `prim` (which must cover it),
    // given the framebuffer before the primitive is shaded.
    FragmentTrace trace(const SetupList& list, const SetupPrimitive& prim, int x, int y,
                        unsigned sample, const Framebuffer& fb_before) const {
        return trace_(state_, list, prim, x, y, sample, fb_before);
    }

  private:
    KernelState state_;
    ShadeFn shade_;
    TraceFn trace_;
    ShadeRowsFn shade_rows_;
    bool hardware_denormals_;
};

// The kernel for a draw's state into `target`; `options` are the per-pixel stage's; `texture`
// the draw's texture unit (null without one), which must outlive the kernel. A textured draw
// shades row blocks on the vector paths where the vector sampler serves its unit
// (vector_kernels.hpp), quad packets otherwise (its level of detail is a quad's).
FragmentKernel choose_fragment_kernel(const Draw& draw, const Target& target,
                                      FragmentOptions options,
                                      const TextureUnit* texture = nullptr);

}  // namespace refraster::detail
