// line_point.hpp: lines and points as llvmpipe sets them up, kept apart from triangles.
//
// Implements (line assembly, in the order llvmpipe's vbuf path emits segments, is in
// refraster/assembly.hpp; a segment's provoking vertex is its second, or its first with the
// first-vertex convention, docs/precision.md "Lines"):
//  - line coverage (lp_setup_line.c, try_setup_line, the non-rectangular path GL uses): a
//    four-plane parallelogram around the line, its width util_iround(width) pixels in the
//    minor axis, its ends moved by half a pixel by the driver's diamond-exit heuristics
//    (including its quirk for y2diff == -0.5 with dy < 0), positions snapped with util_iround
//    (half away from zero), then the triangle plane and tie rules (docs/precision.md "Lines");
//  - line attribute planes (setup_line_coefficients, linear_coef, perspective_coef): plain C
//    float arithmetic, the gradient only along the major axis, scaled by 1 + slope^2;
//  - points as quads (lp_setup_point.c, try_setup_point with point sprites on): a square of
//    side max(1, util_iround(256 * size) / 256) around the snapped centre, left and bottom
//    edges inclusive (docs/precision.md "Points"); attributes constant over the point
//    (constant_coef, point_persp_coeff); with point sprite coordinates
//    (Draw::samples_point_coords) two more planes, s and t across the point (texcoord_coef,
//    perspective: premultiplied by the vertex's 1/w, docs/precision.md "Point sprites").
//
// Deliberately does not: smooth (antialiased) lines, stipple, legacy (non-sprite) points,
// per-vertex point size.
//
// Under multisampling (SetupParams::multisample) lines are rectangles (setup_rect_line) and
// points keep their quads, both snapped without the pixel offset and tested per sample.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "models/llvmpipe/fragment.hpp"
#include "models/llvmpipe/planes.hpp"
#include "models/llvmpipe/setup.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

struct LineSetup {
    int bits = 8;
    std::array<std::int32_t, 4> x{};
    std::array<std::int32_t, 4> y{};
    std::array<EdgeFunction, 4> edges;
    PixelRect bbox;
    bool x_major = true;
    std::uint8_t scissor_leak = 0;  // multisample_scissor_leak (setup.hpp)
};

// nullopt: a zero-length line, or one outside the draw region.
std::optional<LineSetup> setup_line(const StageVertex& v1, const StageVertex& v2, float width,
                                    const SetupParams& p);

// A line of a multisampled draw (lp_setup_line.c, the rectangular branch): the rectangle
// v1 - t, v2 - t, v2 + t, v1 + t with t = snap((-dy, dx) * (width / 2) / |v1 - v2|), every
// position snapped half away from zero without the pixel offset, edges and tie biases as a
// triangle's; nullopt as setup_line.
std::optional<LineSetup> setup_rect_line(const StageVertex& v1, const StageVertex& v2, float width,
                                         const SetupParams& p);

// The box a multisampled line is traversed in, and its scissor leak (line_point.cpp); false
// when nothing of it is rasterized.
bool multisample_line_box(std::int32_t xmin, std::int32_t xmax, std::int32_t ymin,
                          std::int32_t ymax, const SetupParams& p, LineSetup& L);

// The line's planes into `list` for `prim` (one per attribute float, or constants when flat).
void line_planes(const StageVertex& v1, const StageVertex& v2, const VertexStage& stage,
                 const Draw& draw, bool provoking_first, FragmentOptions options, SetupList& list,
                 SetupPrimitive& prim);

struct PointSetup {
    int bits = 8;
    std::array<EdgeFunction, 4> edges;  // left, right, bottom, top
    PixelRect bbox;
    std::uint8_t scissor_leak = 0;  // always 0: points show no scissor leak
    std::int32_t fixed_width = 0;   // the side in subpixels, at least one pixel
};

std::optional<PointSetup> setup_point(const StageVertex& v, float size, const SetupParams& p);

// The point's planes into `list` (constants when flat), then, when the draw samples point
// sprite coordinates, the planes of s and t (kernel: sprite_planes_at).
void point_planes(const StageVertex& v, const PointSetup& setup, const SetupParams& params,
                  const VertexStage& stage, const Draw& draw, FragmentOptions options,
                  SetupList& list, SetupPrimitive& prim);

}  // namespace refraster::detail
