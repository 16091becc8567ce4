// softpipe_fragment.hpp: from softpipe's set-up primitives to bytes in the framebuffer.
//
// Implements, as Mesa 22.3 softpipe's quad pipeline does it (sp_quad_pipe.c: early depth
// test, shading, blend/output), a batch of quads at a time:
//  - ScanlineList, the set-up primitives of the scanline model: each one's covered spans
//    (rows of pixels, bottom to top) or, for lines, its quads in the order they are plotted,
//    and its planes, window z and 1/w first, then one per attribute float, with how they are
//    interpolated (constant, linear, perspective);
//  - batches: a triangle's quads go to the pipeline a 2-row block and a 16-pixel aligned
//    column chunk at a time (sp_setup.c flush_spans), a line's one quad at a time
//    (clip_emit_quad);
//  - evaluation a 2x2 quad at a time (tgsi_exec.c: eval_constant_coef, eval_linear_coef,
//    eval_perspective_coef; scanline_setup.hpp scanline_quad): perspective values divided by
//    the quad's interpolated 1/w;
//  - depth (sp_quad_depth_test.c): the generic path, the z plane's quad value truncated
//    without a clamp (z16 and z24 wrap as cvttss2si converts), the z32f float as it is; the
//    z16 fast path (sp_quad_depth_test_tmp.h: exact values at the batch's first quad, then a
//    truncated integer step a quad); the eight compare functions; the write (never for
//    `equal`, whose write mask the state tracker clears);
//  - colour output (sp_quad_blend.c) into the colour tile cache (softpipe_tiles.hpp): rgba8
//    unclamped without blending, the two blend presets in float with the source and the
//    result clamped and the destination as the tile holds it; rgba32f never clamped.
//
// Deliberately does not: textures (render() refuses textured draws under this model),
// multisampling (softpipe has none), stencil, colour masks.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "models/softpipe/scanline_setup.hpp"
#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/trace.hpp"
#include "stages/quad.hpp"

namespace refraster::detail {

// How a primitive's attribute planes are evaluated (tgsi_exec.c's interpolators).
enum class ScanlineInterp : std::uint8_t {
    Constant,     // a0 alone (flat)
    Linear,       // a0 + dadx*x + dady*y (noperspective)
    Perspective,  // the linear value of a*(1/w), divided by the linear value of 1/w (smooth)
};

struct ScanlinePrimitive {
    std::uint32_t first_row = 0;  // rows [first_row, first_row + row_count) of the list
    std::uint32_t row_count = 0;
    // A line's quads, in plotting order, one batch each: quads [first_quad, first_quad +
    // quad_count) of the list; none for a triangle, whose batches come from its rows.
    std::uint32_t first_quad = 0;
    std::uint32_t quad_count = 0;
    std::uint32_t planes = 0;  // z, 1/w, then the attribute floats, from this plane
    ScanlineInterp interp = ScanlineInterp::Perspective;
    // Depth clamped to the depth range before it is stored: primitives drawn under a
    // rasterizer state with depth clipping off (the draw module's point sprites).
    bool clamp_depth = false;
    // Shaded under the flush modes (inside draw_vbo) or not (the draw pipeline's last batch).
    bool flush = true;
    // Two planes after the attributes hold the sprite coordinate (gl_PointCoord), always
    // perspective-correct.
    bool point_coords = false;
    std::uint32_t owner = 0;
};

struct ScanlineList {
    static constexpr std::size_t kCapacity = 1024;
    std::vector<ScanlinePrimitive> primitives;
    std::vector<ScanlineRow> rows;
    std::vector<QuadPacket> quads;
    std::vector<ScanlinePlane> planes;
    std::size_t attribute_floats = 0;
    // Set up for the fast path: SoftpipeModel::traverse makes the same batches with masks of
    // runs rather than pixel by pixel.
    bool fast = false;

    bool full() const { return primitives.size() >= kCapacity; }
    void clear() {
        primitives.clear();
        rows.clear();
        quads.clear();
        planes.clear();
    }
    std::span<const ScanlineRow> rows_of(const ScanlinePrimitive& p) const {
        return {rows.data() + p.first_row, p.row_count};
    }
};

// Index of the z, 1/w and first attribute plane of a primitive.
inline constexpr std::uint32_t kScanlineZPlane = 0;
inline constexpr std::uint32_t kScanlineWPlane = 1;
inline constexpr std::uint32_t kScanlineFirstAttribute = 2;

class SoftpipeTileCache;
class SoftpipeLazyTiles;
class SoftpipeSampler;

// The per-pixel stage of one draw under the scanline model; colours go through `tiles`.
class ScanlineKernel {
  public:
    // `flush_denormals`: shade with the CPU's flush-to-zero and denormals-are-zero modes on, as
    // softpipe shades inside draw_vbo (draw_pt.c sets them for its duration).
    // `depth_nearest`: a profile's depth_rounding=nearest instead of softpipe's truncation
    // (RNE(fl(z * (2^n - 1))), converted as the truncation is; no z16 fast path).
    // `sampler`: the draw's texture (a textured draw): the colour is the texel (replace) or the
    // interpolated colour times it (modulate), sampled a quad at a time at s/q and t/q (TXP) or
    // at the sprite coordinate.
    ScanlineKernel(const Draw& draw, const Target& target, SoftpipeTileCache& tiles,
                   bool flush_denormals, bool depth_nearest = false,
                   const SoftpipeSampler* sampler = nullptr);
    // The fast path (softpipe_fast_fragment.cpp): the same bytes, colours through the lazy
    // tile cache (softpipe_lazy_tiles.hpp) and each quad's planes evaluated once.
    ScanlineKernel(const Draw& draw, const Target& target, SoftpipeLazyTiles& tiles,
                   bool flush_denormals, bool depth_nearest = false,
                   const SoftpipeSampler* sampler = nullptr);

    // One batch of quads (SoftpipeModel::traverse hands them over a batch a call).
    void shade(const ScanlineList& list, const ScanlinePrimitive& p,
               std::span<const QuadPacket> quads, Framebuffer& fb) const;
    bool hardware_denormals() const { return flush_; }
    // The decisions at pixel (x, y) of `p` (which covers it), with the framebuffer before it
    // (depth as the generic path computes it: the trace does not know the z16 fast path's
    // batch).
    FragmentTrace trace(const ScanlineList& list, const ScanlinePrimitive& p, int x, int y,
                        unsigned sample, const Framebuffer& fb) const;

  private:
    // Attribute floats [first, first + 4) of pixel k of the quad at (x0, y0), interpolated as
    // the primitive says.
    std::array<float, 4> attributes(const ScanlineList& list, const ScanlinePrimitive& p,
                                    std::size_t first, int x0, int y0, unsigned k) const;
    // The shader's colour of the four pixels of the quad at (x0, y0), helper pixels included.
    std::array<std::array<float, 4>, 4> quad_colors(const ScanlineList& list,
                                                    const ScanlinePrimitive& p, int x0,
                                                    int y0) const;
    // The output merge of colour `c` into the tile cache's float pixel `dst`.
    void merge(const std::array<float, 4>& c, float* dst) const;
    // The fast path's shade and quad colours (softpipe_fast_fragment.cpp).
    void shade_fast(const ScanlineList& list, const ScanlinePrimitive& p,
                    std::span<const QuadPacket> quads, Framebuffer& fb) const;
    void quad_colors_fast(const ScanlineList& list, const ScanlinePrimitive& p, int x0, int y0,
                          std::array<std::array<float, 4>, 4>& c) const;
    // The depth test of a batch (as shade's), the surviving pixels of each quad in `alive`;
    // whether any survives.
    bool depth_test_fast(const ScanlineList& list, const ScanlinePrimitive& p,
                         std::span<const QuadPacket> quads, Framebuffer& fb,
                         std::uint16_t* alive) const;
    void init(const Draw& draw, const Target& target);

    const Draw& draw_;
    SoftpipeTileCache* tiles_ = nullptr;  // the model's cache, or
    SoftpipeLazyTiles* lazy_ = nullptr;   // the fast path's
    bool rgba8_ = true;
    bool flush_ = false;
    bool depth_nearest_ = false;
    const SoftpipeSampler* sampler_ = nullptr;
    // sp_quad_depth_test.c depth_test_quads_fallback: the depth range's ends as the viewport
    // stores them, near = translate - scale, far = (float)((double)near + (double)scale * 2).
    float depth_min_ = 0.0f;
    float depth_max_ = 1.0f;
    bool depth_ = false;  // the test is on and the target has depth
    bool depth_write_ = false;
    bool z16_fast_path_ = false;
    std::uint8_t depth_pass_ = 7;
};

// The value the generic depth path compares and stores for quad value z
// (convert_quad_depth): z16 and z24 (unsigned)(z * (2^n - 1)) as x86-64 converts it
// (cvttss2si to 64 bits, the low 32 kept: truncation towards zero, negative values wrapping,
// NaN and values beyond 2^63 giving 0), unclamped; z32f the float's bits.
std::uint32_t softpipe_depth_value(float z, DepthFormat format, bool nearest = false);

}  // namespace refraster::detail
