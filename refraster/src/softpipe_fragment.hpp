// softpipe_fragment.hpp: from softpipe's set-up primitives to bytes in the framebuffer.
//
// Implements, as Mesa 22.3 softpipe's quad pipeline does it (sp_quad_pipe.c: shade, depth
// test, blend/output):
//  - ScanlineList, the set-up primitives of the scanline model: each one's covered spans
//    (rows of pixels, bottom to top) and its planes, window z and 1/w first, then one per
//    attribute float, with how they are interpolated (constant, linear, perspective);
//  - evaluation a 2x2 quad at a time (tgsi_exec.c: eval_constant_coef, eval_linear_coef,
//    eval_perspective_coef; scanline_setup.hpp scanline_quad): perspective values divided by
//    the quad's interpolated 1/w;
//  - depth (sp_quad_depth_test.c): the z plane's quad value clamped and truncated
//    (scanline_depth_value), the eight compare functions on the stored values, the write;
//  - colour output (sp_quad_blend.c) into rgba8 and rgba32f, with the two blend presets in
//    float.
//
// Deliberately does not: textures (render() refuses textured draws under this model),
// multisampling (softpipe has none), stencil, colour masks.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "quad.hpp"
#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/trace.hpp"
#include "scanline_setup.hpp"

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
    std::uint32_t planes = 0;  // z, 1/w, then the attribute floats, from this plane
    ScanlineInterp interp = ScanlineInterp::Perspective;
    std::uint32_t owner = 0;
};

struct ScanlineList {
    static constexpr std::size_t kCapacity = 1024;
    std::vector<ScanlinePrimitive> primitives;
    std::vector<ScanlineRow> rows;
    std::vector<ScanlinePlane> planes;
    std::size_t attribute_floats = 0;

    bool full() const { return primitives.size() >= kCapacity; }
    void clear() {
        primitives.clear();
        rows.clear();
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

// The per-pixel stage of one draw under the scanline model.
class ScanlineKernel {
  public:
    ScanlineKernel(const Draw& draw, const Target& target);

    void shade(const ScanlineList& list, const ScanlinePrimitive& p,
               std::span<const QuadPacket> quads, Framebuffer& fb) const;
    bool hardware_denormals() const { return false; }
    // The decisions at pixel (x, y) of `p` (which covers it), with the framebuffer before it.
    FragmentTrace trace(const ScanlineList& list, const ScanlinePrimitive& p, int x, int y,
                        unsigned sample, const Framebuffer& fb) const;

  private:
    // The fragment at pixel k of the quad at (x0, y0): depth test and colour write; returns
    // the trace when `t` is given.
    void fragment(const ScanlineList& list, const ScanlinePrimitive& p, int x0, int y0,
                  unsigned k, Framebuffer& fb, FragmentTrace* t) const;

    const Draw& draw_;
    bool depth_ = false;  // the test is on and the target has depth
    std::uint8_t depth_pass_ = 7;
};

// softpipe's float blending of a converted source channel `s` over `d` (both in [0, 1] for
// rgba8), alpha `a`, for a preset (sp_quad_blend.c).
float softpipe_blend(BlendPreset preset, float s, float a, float d);

}  // namespace refraster::detail
