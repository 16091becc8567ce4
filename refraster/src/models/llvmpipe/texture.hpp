// texture.hpp: 2D RGBA8 texture sampling as llvmpipe's gallivm samples it.
//
// Implements (docs/precision.md, "Textures"; gallium/auxiliary/gallivm/lp_bld_sample*.c):
//  - the choice of path per draw (lp_build_sample_soa_code): the 8-bit AoS path when both
//    wraps are repeat or clamp-to-edge, the float SoA path otherwise;
//  - the LOD of a 2x2 quad (lp_build_rho, exact rho squared from the quad's bottom-left pixel
//    and its right and upper neighbours, in units of base-level texels; helper pixels count),
//    the per-quad choice between the min and mag filters, nearest mip level by the exponent
//    of rho squared, trilinear LOD by the piecewise-linear log2 (lp_build_fast_log2);
//  - per axis: nearest and bilinear texel coordinates and weights for repeat (power-of-two and
//    not), clamp-to-edge, mirrored repeat and clamp-to-border, in 8.8 fixed point (AoS) or
//    float (SoA), and the lerps: byte lerps (pmulhrsw rounding) or fused float ones;
//  - glGenerateMipmap's levels (util_gen_mipmap's linear blit through util_blitter: each
//    texel the AoS bilinear, clamp-to-edge sample of the level above at the coordinates the
//    blit's two triangles interpolate, fused as the shaders fuse).
//
// Deliberately does not: other formats, 1D/3D/cube textures, LOD bias or LOD clamps,
// anisotropy, shadow compares, texelFetch, or GALLIVM_PERF's approximations.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "refraster/draw.hpp"
#include "refraster/profile.hpp"
#include "refraster/trace.hpp"

namespace refraster::detail {

// A texture's levels one after another as 32-bit texels (r | g << 8 | b << 16 | a << 24,
// the bytes of TextureImage::rgba read as one little-endian word), the layout the vector
// sampler gathers from (vector_texture_body.hpp): texel (x, y) of level l at
// offset[l] + y * width[l] + x.
struct PackedLevels {
    // A level's size and offset are read per lane from tables of this many entries.
    static constexpr std::size_t kMaxLevels = 16;
    // Gather indices are int32 lanes.
    static constexpr std::size_t kMaxTexels = std::size_t{1} << 30;
    // The 8.8 coordinate scale n * 256 is a float made from an int32 lane: exact up to 2^24.
    static constexpr std::uint32_t kMaxSize = std::uint32_t{1} << 15;
    static_assert(std::uint64_t{kMaxSize} * 256 <= (std::uint64_t{1} << 24),
                  "n * 256 is exact in float and fits int32");
    std::vector<std::uint32_t> texels;
    std::array<std::int32_t, kMaxLevels> offset{};
    std::array<std::int32_t, kMaxLevels> width{};
    std::array<std::int32_t, kMaxLevels> height{};
    std::uint32_t count = 0;
};

// The packed form of `levels`, or nothing when they exceed kMaxLevels levels, kMaxTexels
// texels or kMaxSize texels a side (such a texture is sampled by the scalar sampler only).
std::optional<PackedLevels> pack_levels(const std::vector<TextureImage>& levels);

// A draw's texture unit with everything the sampler derives once per draw.
struct TextureUnit {
    const std::vector<TextureImage>* levels = nullptr;  // base first, every level present
    // The same levels packed for the vector sampler (null: the scalar sampler only).
    const PackedLevels* packed = nullptr;
    TextureState state;
    // lp_build_sample_soa_code: the 8-bit path needs both wraps repeat or clamp-to-edge, and
    // the profile's texture_filtering=fixed-point (GALLIVM_PERF=no_aos_sampling clears use_aos).
    bool aos = true;
    // Whether the base level's width (height) is a power of two: it decides the repeat code
    // of every level (the static texture state keys on width0 and height0).
    bool pot_s = true;
    bool pot_t = true;
    std::uint32_t last_level = 0;
    bool mipmapped = false;  // the min filter reads mip levels
    // No LOD is computed when the min and mag filters are the same image filter without mipmaps.
    bool needs_lod = false;
    // The float path with different min and mag image filters runs the shader's eight pixels
    // (two quads side by side, x and x + 2 of a 4x4 block) through one filter: nearest when
    // neither quad takes the linear filter, otherwise the linear one for both, a nearest quad's
    // weights rounded to 0 or 1 (w > 0.5: lp_build_sample_mipmap_both with a linear mask): its
    // nearest texel, except where u * size - 0.5 has a fraction of exactly one half.
    bool soa_nearest_as_linear = false;
    float base_width = 1.0f;
    float base_height = 1.0f;
    // The border colour is clamped to [0, 1] in the shader (lp_bld_sample.c,
    // lp_build_clamp_border_color: maxps, minps), which runs under the rasterizer's DAZ
    // (lp_rast.c, util_fpstate_set_denorms_to_zero): a denormal channel reads as 0. The
    // profile's flush_denormals decides.
    bool flush_border = true;
    // The LOD's rho by GALLIVM_PERF=rho_approx's rule (the profile's texture_rho=approx).
    bool rho_approx = false;
    // LINEAR_MIPMAP_LINEAR's blend by GALLIVM_PERF=brilinear's rule (texture_mip_blend).
    bool brilinear = false;
};

TextureUnit make_texture_unit(const TextureState& state, const std::vector<TextureImage>& levels,
                              TextureFiltering filtering = TextureFiltering::FixedPoint);

// One level of glGenerateMipmap: the blit of `src` to half its size (at least 1x1); `fma`
// says whether the blit's interpolation fuses, `filtering` which path its sampler takes.
TextureImage blit_level(const TextureImage& src, bool fma,
                        TextureFiltering filtering = TextureFiltering::FixedPoint);

// glGenerateMipmap of `base`: levels 1 to the 1x1 level.
std::vector<TextureImage> generate_mipmaps(
    const TextureImage& base, bool fma, TextureFiltering filtering = TextureFiltering::FixedPoint);

// The levels a texture is sampled from: the given ones, or the base and generated ones.
std::vector<TextureImage> resolve_levels(const Texture& texture, bool fma,
                                         TextureFiltering filtering);

// What sampling decided for one pixel (trace.hpp), for `explain`.
using TexelSample = TextureTrace;

// Samples the four pixels of a quad: s[p], t[p] are pixel p's coordinates after projection
// (pixel 0 at the quad's (x, y), 1 to its right, 2 above it, 3 above and right). `fma` says
// whether the float lerps fuse (gallivm's lp_build_fmuladd on an FMA CPU). Writes each pixel's
// RGBA as the shader sees it; `trace`, when given, records pixel `trace_pixel`'s decisions.
// `pair_linear`: whether the other quad of the pixels' eight-wide shader vector takes the
// linear image filter (quad_takes_linear); it matters only with
// TextureUnit::soa_nearest_as_linear.
void sample_quad(const TextureUnit& unit, const std::array<float, 4>& s,
                 const std::array<float, 4>& t, bool fma, std::array<std::array<float, 4>, 4>& out,
                 bool pair_linear = false, TexelSample* trace = nullptr, unsigned trace_pixel = 0);

// Whether a quad at these coordinates takes the linear image filter (its LOD decides between
// the min and mag filters).
bool quad_takes_linear(const TextureUnit& unit, const std::array<float, 4>& s,
                       const std::array<float, 4>& t);

// A byte as llvmpipe's shader sees it: fl(v * K), K the float nearest to 1/255.
float unorm8_to_float(std::uint8_t v);

}  // namespace refraster::detail
