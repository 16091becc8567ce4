// softpipe_fill.cpp: a fill rule's pixels under the scanline rules (softpipe_fill.hpp).
#include "models/softpipe/softpipe_fill.hpp"

#include <array>
#include <cstdint>
#include <vector>

#include "models/softpipe/scanline_setup.hpp"
#include "stages/draw_module.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

// The scanline (softpipe) rules: softpipe's own coverage of each of the polygon's triangles, as
// the clipper cuts them, counted as the stencil pass counts it (+1 for a front face, -1 for a
// back face). softpipe's float rules are no nudge of the centre (docs/precision.md, "Polygons and
// fill rules"), so no filler over the outline reproduces them; the count is the definition.
FillMask softpipe_fill_mask(const DrawContext& ctx) {
    const Draw& d = ctx.draw;
    const PixelRect& region = ctx.params.draw_region;
    FillMask mask(region);
    if (region.empty()) return mask;
    const auto width = static_cast<std::size_t>(region.x1 - region.x0 + 1);
    std::vector<std::int32_t> count(width * static_cast<std::size_t>(region.y1 - region.y0 + 1), 0);
    VertexStage stage(d, ctx.vertex_options());
    std::vector<StageTriangle> staged;
    ScanlineTriangle st;
    for (const auto& t : draw_triangles(ctx)) {
        staged.clear();
        stage.clip_triangle(
            {d.element(t.element[0]), d.element(t.element[1]), d.element(t.element[2])},
            ctx.params.provoking_first, staged, nullptr);
        for (const auto& tri : staged) {
            const std::array<std::array<float, 2>, 3> w{{{tri.v[0].window[0], tri.v[0].window[1]},
                                                         {tri.v[1].window[0], tri.v[1].window[1]},
                                                         {tri.v[2].window[0], tri.v[2].window[1]}}};
            st.rows.clear();
            if (setup_scanline_triangle(w, CullMode::None, ctx.params.front_ccw, region, st) !=
                ScanlineOutcome::Ok)
                continue;
            const std::int32_t step = st.front_facing ? 1 : -1;
            for (const auto& row : st.rows) {
                for (int x = row.x0; x < row.x1; ++x) {
                    count[static_cast<std::size_t>(row.y - region.y0) * width +
                          static_cast<std::size_t>(x - region.x0)] += step;
                }
            }
        }
    }
    const bool even_odd = *d.state.fill_rule == FillRule::EvenOdd;
    for (int y = region.y0; y <= region.y1; ++y) {
        for (int x = region.x0; x <= region.x1; ++x) {
            const std::int32_t c = count[static_cast<std::size_t>(y - region.y0) * width +
                                         static_cast<std::size_t>(x - region.x0)];
            if (even_odd ? (c & 1) != 0 : (c & 0xff) != 0) mask.set(x, y);
        }
    }
    return mask;
}

}  // namespace refraster::detail
