// polygon_draw.hpp: a polygon drawn with a fill rule, as the stencil method draws it in GL.
//
// Implements the reference's side of scene extension "polygons" fill rules
// (docs/scene-format.md, "Fill rules"; docs/precision.md, "Polygons and fill rules"):
//  - which pixels the rule lights: the scanline filler (polygon_fill.hpp) over the polygon's
//    own vertices, snapped as llvmpipe's setup snaps them, with the profile's tie rule as the
//    nudge. When the clipper cuts any of the polygon's triangles (a vertex outside the view
//    volume), the filler runs over the contours of the triangles the clipper makes instead,
//    which is what the stencil pass counts; where nothing is clipped, their edges inside the
//    polygon cancel and the two agree exactly;
//  - under the scanline (softpipe) rules, whose float coverage is no nudge, the mask is the
//    stencil pass's own count of softpipe's coverage of the (clipped) triangles instead;
//  - the draw region (framebuffer and scissor) bounds the mask;
//  - the cover pass is the polygon's own triangles drawn again through the model, each pixel
//    of the mask taken by the first of them to reach it (DrawContext::fill, pipeline.hpp).
//
// Deliberately does not: fill rules on 4x targets, under the exact model, or with the tie rules
// None and All under the snapped one (render() answers NotSupported for those).
#pragma once

#include <optional>
#include <string>

#include "stages/model.hpp"
#include "stages/polygon_fill.hpp"

namespace refraster::detail {

// The contours the stencil pass counts for ctx's polygon draw: its vertices, or the clipped
// triangles when the clipper cuts one. nullopt when a position cannot be snapped.
std::optional<std::vector<Contour>> fill_contours(const DrawContext& ctx);

// The pixels ctx's fill rule lights (the draw region's) by the scanline filler over the snapped
// outline (fill_contours), the rule of every snapped model, or nullopt as fill_contours. The
// scanline (softpipe) model counts its own coverage instead (models/softpipe/softpipe_fill.hpp);
// pipeline.hpp chooses.
std::optional<FillMask> outline_fill_mask(const DrawContext& ctx,
                                          std::vector<FillScanline>* trace = nullptr);

// Why the reference cannot draw a fill rule in this draw and target under `profile`, or "".
std::string fill_rule_unsupported(const Draw& d, const Target& target, const Profile& profile);

}  // namespace refraster::detail
