#include "stages/polygon_draw.hpp"

#include "stages/draw_module.hpp"
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

std::optional<FillMask> outline_fill_mask(const DrawContext& ctx,
                                          std::vector<FillScanline>* trace) {
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
