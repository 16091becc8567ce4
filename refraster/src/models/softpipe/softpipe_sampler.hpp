// softpipe_sampler.hpp: 2D RGBA8 texture sampling as Mesa 22.3 softpipe samples it.
//
// Implements (gallium/drivers/softpipe/sp_tex_sample.c unless said otherwise), for one draw's
// texture unit 0 and 2x2 quads of projected coordinates:
//  - texels as softpipe's texture tile cache converts them: byte b becomes fl(b * fl(1/255))
//    (util/format/u_format_pack.py's unorm8 unpack), not b / 255;
//  - one LOD per quad (compute_gradient_2d, compute_lambda_2d_explicit_gradients,
//    compute_lambda_lod): rho = max(max(|s3-s2|, |s0-s2|) * W0, max(|t3-t2|, |t0-t2|) * H0),
//    the x differences from the quad's row y0 + 1 (pixels 2 and 3) and the y differences from
//    its column x0 (pixels 0 and 2; softpipe's QUAD_BOTTOM_LEFT is pixel 2), no square root;
//    W0 x H0 the base level's size; lod = clamp(util_fast_log2(rho), 0, 1000), util_fast_log2
//    being the exponent plus a 257-entry table of log2(1 + k/256) (util/u_math.h), not an
//    exact log2;
//  - the filter and level per pixel (mip_filter_none_no_filter_select, mip_filter_none,
//    mip_filter_nearest, mip_filter_linear, mip_filter_linear_2d_linear_repeat_POT): without
//    a mip filter and with min == mag, always that filter on the base; otherwise the mag
//    filter on the base when lod <= 0 (that is lod == 0), else the min filter: nearest level
//    min((int)(lod + 0.5f), last); linear levels (int)lod and the next blended by
//    lerp(lod - floor(lod), c0, c1), or `last` alone once (int)lod >= last; the power-of-two
//    repeat trilinear path (min = mag = linear) has no mag test and blends at lod 0 too;
//  - nearest and bilinear image filters (img_filter_2d_nearest, img_filter_2d_linear, and the
//    power-of-two repeat paths img_filter_2d_nearest_repeat_POT and
//    img_filter_2d_linear_repeat_POT taken when the base level is a power of two in both
//    directions and both wraps are repeat), with softpipe's wraps: repeat with its unsigned
//    (c + size*1024) % size, clamp-to-edge, mirrored repeat and clamp-to-border (the
//    wrap_nearest_* and wrap_linear_* functions), coordinates floored by util_ifloor (exact
//    below 2^22, softpipe's own result beyond); the bilinear weights are float, each channel
//    lerp(b, lerp(a, t00, t10), lerp(a, t01, t11)) with lerp(w, x, y) = x + w * (y - x);
//  - the border colour, each channel clamped to [0, 1] (a unorm view, sp_tgsi_get_samples),
//    returned for any texel outside the level (get_texel_2d);
//  - the texture tile cache's aliasing (sp_tex_tile_cache.c): 16 direct-mapped entries of
//    32x32 float tiles, entry (x/32 + 9*(y/32) + 7*level) % 16, tiles loaded clipped to the
//    level. A bilinear sample fetches its four texels (x0,y0) (x1,y0) (x0,y1) (x1,y1) as
//    pointers into the cache and reads them after the fourth fetch, so when a later fetch of
//    the same sample loads another tile into an earlier fetch's entry, the earlier pointer
//    reads the newer tile at the same offset (or, where the newer tile is clipped, what the
//    entry held before it). Only a repeat seam does that (x1 = 0 next to x0 = size-1, or the
//    same in t), with the two tiles mapping to one entry;
//  - glGenerateMipmap's levels (util_gen_mipmap: a linear blit per level, u_blitter.c): each
//    level drawn as softpipe draws the blitter's rectangle, two triangles (0,0) (W,0) (W,H)
//    and (0,0) (W,H) (0,H) of the new level through softpipe's triangle setup (sp_setup.c),
//    texture coordinates 0..1 interpolated per quad, each pixel a float bilinear,
//    clamp-to-edge sample of the level above (img_filter_2d_linear) stored with
//    float_to_ubyte: not llvmpipe's 8-bit cascade and not a box filter.
//
// The tile cache's state is not kept from one sample to the next because none of it can
// show: the texel a fetch asks for lies in the loaded part of its own tile, so its entry holds
// it once the fetch returns, and what the pointer reads afterwards depends only on the loads
// that the later fetches of the same bilinear sample make. A tile of another texture never
// hits either: softpipe marks every entry invalid when the sampler view changes or the
// texture's data does (sp_tex_tile_cache_set_sampler_view, sp_state_derived.c). So
// sample_quad is a pure function of its arguments, the same in any order of calls, and one
// sampler can serve several threads. (Checked against a literal, persistent 16-entry cache.)
//
// Deliberately does not: the shading around the sample (the caller interpolates the
// coordinates, divides s and t by q as TXP does, and multiplies by the colour for modulate;
// see sample_quad), other formats or targets, LOD bias or LOD clamps, texel offsets,
// anisotropy, shadow compares, texelFetch or gather; denormal inputs are taken under the
// caller's floating-point mode, which should be the shading's. Not measured: texture sizes
// above 1060 texels (1024 for powers of two), and infinite or NaN coordinates, which are
// handled without leaving the level table.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "refraster/draw.hpp"

namespace refraster::detail {

class SoftpipeSampler {
  public:
    // `levels`: DrawList::textures[i].levels (base first, each max(1, size >> level), the last
    // one GL_TEXTURE_MAX_LEVEL). `generate_mipmaps`: Texture::generate_mipmaps; then only the
    // base is read, and softpipe's glGenerateMipmap levels are made here, down to 1x1.
    SoftpipeSampler(const TextureState& state, const std::vector<TextureImage>& levels,
                    bool generate_mipmaps);

    // Samples the four pixels of a 2x2 quad whose pixels are, in order, (x0, y0),
    // (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1) (x0 and y0 even, y up: GL's and an FBO's
    // rows), at s[k], t[k] as the shader hands them to TEX: for textureProj the interpolated
    // s and t each divided by the interpolated q (one float division, TGSI TXP); for
    // gl_PointCoord the interpolated sprite coordinate as it is. All four pixels count, covered
    // or not (the LOD comes from pixels 0, 2 and 3); the caller evaluates them all. Writes
    // each pixel's RGBA as the shader sees the texel, before modulate (a float multiply by the
    // interpolated colour, channel by channel) or replace.
    void sample_quad(const std::array<float, 4>& s, const std::array<float, 4>& t,
                     std::array<std::array<float, 4>, 4>& out) const;
    // The same values as sample_quad, for the fast path (softpipe_fast_fragment.cpp): the
    // power-of-two repeat bilinear filter reads its four texels directly wherever no repeat
    // seam lies between them, where the tile cache's entries cannot alias (the proof is at
    // SoftpipeSampler::linear), and blends the four channels as one vector (bilinear_direct);
    // sample_quad, the model's, emulates the cache for every sample away from the level's
    // first tile column and row and blends channel by channel.
    void sample_quad_direct(const std::array<float, 4>& s, const std::array<float, 4>& t,
                            std::array<std::array<float, 4>, 4>& out) const;

    // The RGBA8 levels sampled, base first: the given ones, or the base and the generated
    // ones (what glGetTexImage reads back on softpipe).
    const std::vector<TextureImage>& levels() const { return images_; }

  private:
    enum class ImageFilter : std::uint8_t { Nearest, Linear };
    enum class MipFilter : std::uint8_t { None, Nearest, Linear };

    // sample_quad (kDirect false) and sample_quad_direct (true).
    template <bool kDirect>
    void sample(const std::array<float, 4>& s, const std::array<float, 4>& t,
                std::array<std::array<float, 4>, 4>& out) const;
    // The filtered texel of one level at (s, t), for one pixel.
    template <bool kDirect>
    void filter(ImageFilter f, std::uint32_t level, float s, float t, const float* border,
                float* rgba) const;
    void nearest(std::uint32_t level, float s, float t, const float* border, float* rgba) const;
    template <bool kDirect>
    void linear(std::uint32_t level, float s, float t, const float* border, float* rgba) const;

    std::vector<TextureImage> images_;
    std::vector<std::vector<float>> texels_;  // each level's channels as the tile cache holds them
    TextureWrap wrap_s_ = TextureWrap::Repeat;
    TextureWrap wrap_t_ = TextureWrap::Repeat;
    ImageFilter min_ = ImageFilter::Linear;
    ImageFilter mag_ = ImageFilter::Linear;
    MipFilter mip_ = MipFilter::None;
    std::array<float, 4> border_{};  // as given (sample_quad clamps it)
    // The base level is a power of two in both directions and both wraps are repeat: the
    // image filters take the _repeat_POT paths.
    bool pot_repeat_ = false;
    // ... and min = mag = linear with the linear mip filter:
    // mip_filter_linear_2d_linear_repeat_POT.
    bool pot_trilinear_ = false;
    float base_width_ = 1.0f;
    float base_height_ = 1.0f;
    std::uint32_t last_ = 0;  // the last level
};

}  // namespace refraster::detail
