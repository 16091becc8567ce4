// softpipe_fill.hpp: the stencil pass of a fill rule under the scanline (softpipe) rules.
//
// Implements: the pixels a polygon's fill rule lights when softpipe draws its stencil pass:
// softpipe's own coverage of each of the polygon's triangles, as the clipper cuts them, counted
// +1 for a front face and -1 for a back face, then the rule applied to the count.
//
// Deliberately does not: the cover pass (stages/polygon_draw.hpp and pipeline.hpp do), or
// snap: softpipe's float rules are no nudge of the centre, so no filler over the outline
// reproduces them (docs/precision.md, "Polygons and fill rules").
#pragma once

#include "stages/model.hpp"
#include "stages/polygon_fill.hpp"

namespace refraster::detail {

FillMask softpipe_fill_mask(const DrawContext& ctx);

}  // namespace refraster::detail
