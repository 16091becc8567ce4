// llvmpipe_model_impl.hpp: the llvmpipe model's setup templates (llvmpipe_model.hpp),
// included where the model is instantiated for an observer: llvmpipe_model.cpp (no observer)
// and trace/traced_models.cpp (the trace).
#pragma once

#include <algorithm>
#include <array>

#include "models/llvmpipe/line_point.hpp"
#include "models/llvmpipe/llvmpipe_model.hpp"
#include "models/llvmpipe/vector_kernels.hpp"
#include "stages/observer.hpp"

namespace refraster::detail {

namespace llvmpipe_setup {

inline void copy_coverage(const TriangleSetup& t, SetupPrimitive& p, SetupList& list) {
    p.bits = t.bits;
    p.edge_count = 3;
    std::copy(t.edges.begin(), t.edges.end(), p.edges.begin());
    p.bbox = t.bbox;
    p.scissor_leak = t.scissor_leak;
    if (t.llvmpipe_walk) {
        p.walk = static_cast<std::int32_t>(list.walks.size());
        list.walks.push_back(t.walk);
    }
}

// A new primitive at the end of the list, copied from a constant: a block copy, where a
// value-initialised one is cleared with a string instruction whose start-up cost a line or a
// point notices.
inline SetupPrimitive& new_primitive(SetupList& list) {
    static constexpr SetupPrimitive kInitial{};
    return list.primitives.emplace_back(kInitial);
}

template <class Setup>
inline void copy_quad_coverage(const Setup& s, SetupPrimitive& p) {
    p.bits = s.bits;
    p.edge_count = 4;
    p.edges = s.edges;
    p.bbox = s.bbox;
    p.scissor_leak = s.scissor_leak;
}

// Asks for the colour and depth lines of a small box's rows, into the second-level cache: the
// list a triangle joins is shaded a few hundred triangles later, by when the lines are there
// rather than in memory (a small triangle's rows are a framebuffer row apart, a stride no
// hardware prefetcher follows). A prefetch changes no value.
inline void prefetch_rows(const PixelRect& box, const Framebuffer& fb) {
    constexpr int kMaxRows = 16;  // taller boxes prefetch their own rows as they are shaded
    if (box.empty() || box.y1 - box.y0 >= kMaxRows || fb.color8.empty()) return;
    const auto* color = reinterpret_cast<const std::uint32_t*>(fb.color8.data());
    for (int y = box.y0; y <= box.y1; ++y) {
        const std::size_t row = static_cast<std::size_t>(y) * fb.width;
        const std::size_t first = row + static_cast<std::size_t>(box.x0);
        const std::size_t last = row + static_cast<std::size_t>(box.x1);
        // Locality 2: into the second-level cache and the levels below it.
        prefetch_pixels<0, 2>(color, first, last);
        if (!fb.depth.empty()) prefetch_pixels<0, 2>(fb.depth.data(), first, last);
    }
}

}  // namespace llvmpipe_setup

// What the draw's fragment kernel reads (choose_fragment_kernel), or everything for an observer
// that records every plane.
template <class Observer>
PlaneNeeds LlvmpipeModel::plane_needs() const {
    const Draw& d = ctx_.draw;
    const bool depth = d.state.depth_test.has_value() && ctx_.target.depth != DepthFormat::None;
    return {depth || Observer::kReadsEveryPlane,
            d.state.shade == ShadeModel::Smooth || Observer::kReadsEveryPlane};
}

template <class Observer>
void LlvmpipeModel::setup(VertexStage& stage, Observer& obs, const ListSink<List>& sink) {
    begin_lists(sink, stage);
    list_.multisample = ctx_.params.multisample;
    // A full list's planes: z, 1/w and one per attribute float for each primitive.
    list_.capacity = ctx_.workers != nullptr ? SetupList::kThreadedCapacity : SetupList::kCapacity;
    list_.primitives.reserve(list_.capacity);
    fragment_options_ = fragment_options(ctx_);
    fragment_options_plain_ = fragment_options_;
    fragment_options_plain_.flush_denormals = false;
    list_.planes.reserve(list_.capacity * (kFirstAttributePlane + list_.attribute_floats));
    dispatch(stage, obs);
    end_lists(obs);
}

template <class Observer>
void LlvmpipeModel::triangles(VertexStage& stage, Observer& obs) {
    const Draw& d = ctx_.draw;
    const bool first = ctx_.params.provoking_first;
    const auto tris = draw_triangles(ctx_);

    // Segments with any vertex outside the view volume go through the draw pipeline.
    const std::vector<bool> segment_clipped = clipped_segments(stage, d, tris);
    if (nine_vertex_quirk_drops(stage, tris, segment_clipped)) {
        obs.dropped_draw(ctx_.index, "draw dropped by llvmpipe's nine-vertex rectangle analysis");
        return;
    }

    const std::vector<bool> setup_ftz =
        pipeline_batches_flushed(ctx_, stage, tris, segment_clipped);
    std::size_t pipeline_output = 0;  // the pipeline's output triangles so far, in order
    std::vector<StageTriangle> staged;
    // The fast paths let the CPU flush (FTZ and DAZ: the modes the model's emulation
    // reproduces operation by operation, float_ops.hpp) while triangles are set up; every
    // operation the model flushes gives the same result, the rest sees only flushed values.
    // The shading of full lists inside the loop sets its own mode.
    cpu_flushes_ = ctx_.cpu_flushes() && !Observer::kReadsEveryPlane;
    const ScopedDenormalsAreZero mode(cpu_flushes_);
    for (std::size_t p = 0; p < tris.size(); ++p) {
        next_primitive(p, obs);
        const auto& at = tris[p];
        const std::array<std::uint32_t, 3> idx{d.element(at.element[0]), d.element(at.element[1]),
                                               d.element(at.element[2])};
        const bool in_pipeline = segment_clipped[at.segment];
        obs.begin_primitive("triangle", ctx_.index, p, idx, stage, in_pipeline);
        if ((stage.clipmask(idx[0]) | stage.clipmask(idx[1]) | stage.clipmask(idx[2])) == 0 &&
            obs.clip_polygons() == nullptr) {
            // Inside the view volume: the clipper would hand the triangle on unchanged.
            const std::array<StageVertex, 3> sv{stage.vertex(idx[0], cpu_flushes_),
                                                stage.vertex(idx[1], cpu_flushes_),
                                                stage.vertex(idx[2], cpu_flushes_)};
            const std::array<const StageVertex*, 3> v{&sv[0], &sv[1], &sv[2]};
            obs.clipped(false);
            const bool ftz = !in_pipeline || setup_ftz.empty() || setup_ftz[pipeline_output];
            pipeline_output += in_pipeline;
            snapped_triangle(stage, v, false, in_pipeline, ftz, obs);
            obs.end_primitive(KeepRecord::CoveredOrNear);
            continue;
        }
        staged.clear();
        stage.clip_triangle(idx, first, staged, obs.clip_polygons());
        obs.clipped(staged.empty());
        for (const auto& st : staged) {
            const bool ftz = !in_pipeline || setup_ftz.empty() || setup_ftz[pipeline_output];
            pipeline_output += in_pipeline;
            snapped_triangle(stage, {&st.v[0], &st.v[1], &st.v[2]}, st.clipped, in_pipeline, ftz,
                             obs);
        }
        obs.end_primitive(KeepRecord::CoveredOrNear);
    }
}

template <class Observer>
void LlvmpipeModel::snapped_triangle(const VertexStage& stage,
                                     const std::array<const StageVertex*, 3>& v, bool clipped,
                                     bool in_pipeline, bool setup_ftz, Observer& obs) {
    const Draw& d = ctx_.draw;
    const SetupParams& params = ctx_.params;
    obs.triangle_start(v, clipped, params.bits);
    const auto culled_by_draw = [&] {
        // Its products are flushed as the model writes them, not by the CPU.
        const ScopedDenormalMode plain(cpu_flushes_, false);
        return !passes_draw_cull(v, d.state.cull, params.front_ccw);
    };
    if (in_pipeline && ctx_.profile.quirks.draw_pipeline_cull && d.state.cull != CullMode::None &&
        culled_by_draw()) {
        return obs.triangle_outcome("culled by the draw module's float cull");
    }
    TriangleSetup& t = triangle_;
    t.clear_except_walk();
    const std::array<std::array<float, 2>, 3> w{{{v[0]->window[0], v[0]->window[1]},
                                                 {v[1]->window[0], v[1]->window[1]},
                                                 {v[2]->window[0], v[2]->window[1]}}};
    const auto outcome = setup_triangle(w, params, t);
    obs.triangle_setup(t);
    switch (outcome) {
        case SetupOutcome::ZeroArea:
            return obs.triangle_outcome("zero area");
        case SetupOutcome::Culled:
            return obs.triangle_outcome("culled");
        case SetupOutcome::OutOfRange:
            return obs.triangle_outcome("snapped position out of range");
        case SetupOutcome::Outside:
            return obs.triangle_outcome("outside the draw region");
        case SetupOutcome::Ok:
            break;
    }
    // Attribute setup sees the vertices in setup's order, after the orientation swap; it runs
    // without FTZ for the draw pipeline's last batch (pipeline_batches_flushed, model.hpp).
    SetupPrimitive& prim = llvmpipe_setup::new_primitive(list_);
    llvmpipe_setup::copy_coverage(t, prim, list_);
    prim.owner = owner_;
    const FragmentOptions& fo = fragment_options_;
    // Setup flushes when the profile does and the triangle's batch sets FTZ; under the CPU's
    // flush modes the planes' operations run plain (the CPU flushes them), and a triangle the
    // model sets up without flushing runs with the modes cleared.
    const bool setup_flushes = fo.flush_denormals && setup_ftz && !cpu_flushes_;
    const ScopedDenormalMode plain(cpu_flushes_ && !setup_ftz, false);
    triangle_planes(
        {v[static_cast<std::size_t>(t.order[0])], v[static_cast<std::size_t>(t.order[1])],
         v[static_cast<std::size_t>(t.order[2])]},
        stage, d, ctx_.target, params.provoking_first,
        setup_flushes ? fragment_options_ : fragment_options_plain_, fo.flush_denormals,
        plane_needs<Observer>(), list_, prim);
    obs.triangle_drawn(t, list_.primitives.size() - 1);
    if (prefetch_fb_ != nullptr) llvmpipe_setup::prefetch_rows(t.bbox, *prefetch_fb_);
}

// One segment after clipping: try_setup_line and its planes.
template <class Observer>
void LlvmpipeModel::segment(const VertexStage& stage, const StageVertex& v1, const StageVertex& v2,
                            Observer& obs) {
    const float width = ctx_.draw.state.line_width;
    const auto setup = ctx_.params.multisample ? setup_rect_line(v1, v2, width, ctx_.params)
                                               : setup_line(v1, v2, width, ctx_.params);
    if (!setup) return;
    SetupPrimitive& prim = llvmpipe_setup::new_primitive(list_);
    llvmpipe_setup::copy_quad_coverage(*setup, prim);
    prim.owner = owner_;
    line_planes(v1, v2, stage, ctx_.draw, ctx_.params.provoking_first, fragment_options_, list_,
                prim);
    obs.line_drawn(v1, v2, *setup, list_.primitives.size() - 1);
}

// One point that survived clipping: try_setup_point and its planes.
template <class Observer>
void LlvmpipeModel::point(const VertexStage& stage, const StageVertex& v, Observer& obs) {
    const auto setup = setup_point(v, ctx_.draw.state.point_size, ctx_.params);
    if (!setup) return;
    SetupPrimitive& prim = llvmpipe_setup::new_primitive(list_);
    llvmpipe_setup::copy_quad_coverage(*setup, prim);
    prim.owner = owner_;
    point_planes(v, *setup, ctx_.params, stage, ctx_.draw, fragment_options_, list_, prim);
    obs.point_drawn(v, *setup, list_.primitives.size() - 1);
    if (prefetch_fb_ != nullptr) llvmpipe_setup::prefetch_rows(setup->bbox, *prefetch_fb_);
}

}  // namespace refraster::detail
