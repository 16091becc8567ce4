#include "stages/polygon_draw.hpp"

#include "models/softpipe/scanline_setup.hpp"
#include "models/llvmpipe/setup.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

std::optional<std::vector<Contour>> fill_contours(const DrawContext& ctx) {
    const Draw& d = ctx.draw;
    VertexStage stage(d, ctx.vertex_options());
    const auto snap = [&](const StageVertex& v) -> std::optional<SnappedPoint> {
        const auto p = snap_position(v.window[0], v.window[1], ctx.params);
        if (!p) return std::nullopt;
        return SnappedPoint{(*p)[0], (*p)[1]};
    };
    std::vector<Contour> contours;
    const std::size_t n = d.element_count();
    bool clipped = false;
    for (std::size_t i = 0; i < n; ++i) clipped = clipped || stage.clipmask(d.element(i)) != 0;
    if (!clipped) {
        // The polygon itself, in its vertex order.
        Contour& c = contours.emplace_back();
        for (std::size_t i = 0; i < n; ++i) {
            const auto p = snap(stage.vertex(d.element(i)));
            if (!p) return std::nullopt;
            c.push_back(*p);
        }
        return contours;
    }
    // The triangles the stencil pass rasterizes: the polygon's, as the clipper cuts them.
    std::vector<StageTriangle> staged;
    for (const auto& t : draw_triangles(ctx)) {
        staged.clear();
        stage.clip_triangle(
            {d.element(t.element[0]), d.element(t.element[1]), d.element(t.element[2])},
            ctx.params.provoking_first, staged, nullptr);
        for (const auto& st : staged) {
            Contour& c = contours.emplace_back();
            for (const auto& v : st.v) {
                const auto p = snap(v);
                if (!p) return std::nullopt;
                c.push_back(*p);
            }
        }
    }
    return contours;
}

namespace {

// The scanline (softpipe) rules: softpipe's own coverage of each of the polygon's triangles, as
// the clipper cuts them, counted as the stencil pass counts it (+1 for a front face, -1 for a
// back face). softpipe's float rules are no nudge of the centre (docs/precision.md, "Polygons and
// fill rules"), so no filler over the outline reproduces them; the count is the definition.
FillMask counted_fill_mask(const DrawContext& ctx) {
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

}  // namespace

std::optional<FillMask> fill_rule_mask(const DrawContext& ctx, std::vector<FillScanline>* trace) {
    if (ctx.model == CoverageModel::Scanline) return counted_fill_mask(ctx);
    const auto contours = fill_contours(ctx);
    if (!contours) return std::nullopt;
    return scanline_fill(*contours, *ctx.draw.state.fill_rule, ctx.params.tie_rule, ctx.params.bits,
                         ctx.params.draw_region, trace);
}

std::string fill_rule_unsupported(const Draw& d, const Target& target, const Profile& profile) {
    if (!d.state.fill_rule) return {};
    const CoverageModel model = draw_model(profile, d);
    if (model == CoverageModel::Exact) return "the exact profile draws no fill rules";
    if (target.samples != 1) return "fill rules on 4x targets are not modelled";
    if (model == CoverageModel::Scanline) return {};
    if (!has_nudge(profile.gl.tie_rule)) {
        return "a fill rule needs a tie rule that gives each edge one side, not " +
               to_string(profile.gl.tie_rule);
    }
    if (profile.gl.clipping == Clipping::GuardBand) {
        return "fill rules are modelled with the view-volume clipper only";
    }
    return {};
}

}  // namespace refraster::detail
