#include "models/exact/exact_model.hpp"

#include <array>
#include <vector>

#include "stages/observer.hpp"
#include "refraster/assembly.hpp"
#include "stages/rules.hpp"
#include "trace/trace_observer.hpp"

namespace refraster::detail {

template <class Observer>
void ExactModel::setup(VertexStage& stage, Observer& obs, const ListSink<List>& sink) {
    const Draw& d = ctx_.draw;
    const bool first = ctx_.params.provoking_first;
    const auto tris = draw_triangles(ctx_);
    // Only for the trace: whether the triangle's vertex segment would go through the draw
    // pipeline (the oracle itself has no pipeline).
    const std::vector<bool> segment_clipped = clipped_segments(stage, d, tris);
    ExactList list;
    for (std::size_t p = 0; p < tris.size(); ++p) {
        if (list.full()) {
            sink(list);
            obs.list_done();
            list.clear();
        }
        const auto& at = tris[p];
        const std::array<std::uint32_t, 3> idx{d.element(at.element[0]), d.element(at.element[1]),
                                               d.element(at.element[2])};
        obs.begin_primitive("triangle", ctx_.index, p, idx, stage, segment_clipped[at.segment]);
        auto ex = std::make_unique<ExactCoverage>(
            std::array<std::array<float, 4>, 3>{
                stage.vertex(idx[0]).clip, stage.vertex(idx[1]).clip, stage.vertex(idx[2]).clip},
            d.state, ctx_.params.draw_region, ctx_.profile.gl.tie_rule);
        if (ex->degenerate()) {
            obs.note("degenerate (det = 0)");
            obs.end_primitive(KeepRecord::CoveredOrNear);
            continue;
        }
        // GL's cull decision on the exact orientation.
        const bool front = ex->front_facing() == (d.state.front_face == FrontFace::Ccw);
        const auto cull = d.state.cull;
        if (is_culled(cull, front)) {
            obs.note("culled");
            obs.end_primitive(KeepRecord::CoveredOrNear);
            continue;
        }
        ExactPrimitive& prim = list.primitives.emplace_back();
        prim.shader = std::make_unique<ExactShader>(
            *ex,
            std::array<StageVertex, 3>{stage.vertex(idx[0]), stage.vertex(idx[1]),
                                       stage.vertex(idx[2])},
            stage, d, ctx_.target, first);
        prim.coverage = std::move(ex);
        prim.owner = owner_id(ctx_.index, primitive_id(ctx_.draw, p));
        obs.exact_setup(*prim.coverage);
        obs.end_primitive(KeepRecord::CoveredOrNear);
    }
    if (!list.primitives.empty()) sink(list);
    obs.list_done();
}

template void ExactModel::setup(VertexStage&, NoObserver&, const ListSink<List>&);
template void ExactModel::setup(VertexStage&, TraceObserver&, const ListSink<List>&);

}  // namespace refraster::detail
