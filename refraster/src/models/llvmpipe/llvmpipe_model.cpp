#include "models/llvmpipe/llvmpipe_model.hpp"

#include <algorithm>
#include <array>

#include "models/llvmpipe/line_point.hpp"
#include "stages/observer.hpp"
#include "trace/trace_observer.hpp"
#include "models/llvmpipe/vector_kernels.hpp"

namespace refraster::detail {

namespace {

bool is_triangle(PrimitiveType p) {
    return p >= PrimitiveType::Triangles;
}

void copy_coverage(const TriangleSetup& t, SetupPrimitive& p, SetupList& list) {
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

template <class Setup>
void copy_quad_coverage(const Setup& s, SetupPrimitive& p) {
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
void prefetch_rows(const PixelRect& box, const Framebuffer& fb) {
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

}  // namespace

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
    sink_ = &sink;
    list_.clear();
    list_.attribute_floats = stage.attribute_floats();
    list_.multisample = ctx_.params.multisample;
    // A full list's planes: z, 1/w and one per attribute float for each primitive.
    list_.capacity = ctx_.workers != nullptr ? SetupList::kThreadedCapacity : SetupList::kCapacity;
    list_.primitives.reserve(list_.capacity);
    list_.planes.reserve(list_.capacity * (kFirstAttributePlane + list_.attribute_floats));
    const Draw& d = ctx_.draw;
    if (d.primitive == PrimitiveType::Points) {
        points(stage, obs);
    } else if (!is_triangle(d.primitive)) {
        lines(stage, obs);
    } else if (d.state.polygon_mode != PolygonMode::Fill) {
        unfilled(stage, obs);
    } else {
        triangles(stage, obs);
    }
    if (!list_.primitives.empty()) sink(list_);
    obs.list_done();
    list_.clear();
}

template <class Observer>
void LlvmpipeModel::next_primitive(std::size_t p, Observer& obs) {
    owner_ = owner_id(ctx_.index, primitive_id(ctx_.draw, p));
    if (list_.full()) {
        (*sink_)(list_);
        obs.list_done();
        list_.clear();
    }
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
    SetupPrimitive& prim = list_.primitives.emplace_back();
    copy_coverage(t, prim, list_);
    prim.owner = owner_;
    const FragmentOptions fo = ctx_.fragment_options();
    FragmentOptions setup_fo{fo.fma, fo.flush_denormals && setup_ftz, fo.multisample, fo.kernels};
    // Under the CPU's flush modes the planes' operations run plain (the CPU flushes them); a
    // triangle the model sets up without flushing runs with the modes cleared.
    if (cpu_flushes_ && setup_ftz) setup_fo.flush_denormals = false;
    const ScopedDenormalMode plain(cpu_flushes_ && !setup_ftz, false);
    triangle_planes(
        {v[static_cast<std::size_t>(t.order[0])], v[static_cast<std::size_t>(t.order[1])],
         v[static_cast<std::size_t>(t.order[2])]},
        stage, d, ctx_.target, params.provoking_first, setup_fo, fo.flush_denormals,
        plane_needs<Observer>(), list_, prim);
    obs.triangle_drawn(t, list_.primitives.size() - 1);
    if (prefetch_fb_ != nullptr) prefetch_rows(t.bbox, *prefetch_fb_);
}

// Lines: assembly, clipping (do_clip_line), then try_setup_line and its planes. Lines are
// never culled.
template <class Observer>
void LlvmpipeModel::lines(VertexStage& stage, Observer& obs) {
    const Draw& d = ctx_.draw;
    const bool first = ctx_.params.provoking_first;
    const auto segs = assemble_lines(d.primitive, d.element_count());
    for (std::size_t p = 0; p < segs.size(); ++p) {
        next_primitive(p, obs);
        const std::array<std::uint32_t, 2> ends{d.element(segs[p][0]), d.element(segs[p][1])};
        obs.begin_primitive("line", ctx_.index, p, ends, stage);
        const auto clipped = stage.clip_line(ends[0], ends[1], first);
        if (!clipped) {
            obs.note("clipped away entirely");
            obs.end_primitive(KeepRecord::Always);
            continue;
        }
        segment(stage, (*clipped)[0], (*clipped)[1], obs);
        obs.end_primitive(KeepRecord::CoveredOrNear);
    }
}

// One segment after clipping: try_setup_line and its planes.
template <class Observer>
void LlvmpipeModel::segment(const VertexStage& stage, const StageVertex& v1, const StageVertex& v2,
                            Observer& obs) {
    const float width = ctx_.draw.state.line_width;
    const auto setup = ctx_.params.multisample ? setup_rect_line(v1, v2, width, ctx_.params)
                                               : setup_line(v1, v2, width, ctx_.params);
    if (!setup) return;
    SetupPrimitive& prim = list_.primitives.emplace_back();
    copy_quad_coverage(*setup, prim);
    prim.owner = owner_;
    line_planes(v1, v2, stage, ctx_.draw, ctx_.params.provoking_first, ctx_.fragment_options(),
                list_, prim);
    obs.line_drawn(v1, v2, *setup, list_.primitives.size() - 1);
}

// One point that survived clipping: try_setup_point and its planes.
template <class Observer>
void LlvmpipeModel::point(const VertexStage& stage, const StageVertex& v, Observer& obs) {
    const auto setup = setup_point(v, ctx_.draw.state.point_size, ctx_.params);
    if (!setup) return;
    SetupPrimitive& prim = list_.primitives.emplace_back();
    copy_quad_coverage(*setup, prim);
    prim.owner = owner_;
    point_planes(v, *setup, ctx_.params, stage, ctx_.draw, ctx_.fragment_options(), list_, prim);
    obs.point_drawn(v, *setup, list_.primitives.size() - 1);
}

// Points: clipped by their centre (draw_pipe_clip.c clip_point), then quad points.
template <class Observer>
void LlvmpipeModel::points(VertexStage& stage, Observer& obs) {
    const Draw& d = ctx_.draw;
    for (std::size_t p = 0; p < d.element_count(); ++p) {
        const std::array<std::uint32_t, 1> i{d.element(p)};
        if (stage.clipmask(i[0]) != 0) continue;
        const StageVertex v = stage.vertex(i[0]);
        next_primitive(p, obs);
        obs.begin_primitive("point", ctx_.index, p, i, stage);
        point(stage, v, obs);
        obs.end_primitive(KeepRecord::Covered);
    }
}

// Polygon modes line and point: always the draw pipeline (llvmpipe hands unfilled
// polygons to it, lp_state_rasterizer.c): clip, the float cull stage, the draw module's
// polygon offset (draw_pipe_offset.c; llvmpipe's own is off then), the flat-shade copy
// (draw_pipe_flatshade.c), then draw_pipe_unfilled.c's edges or points (unfilled_stages,
// model.hpp).
template <class Observer>
void LlvmpipeModel::unfilled(VertexStage& stage, Observer& obs) {
    const Draw& d = ctx_.draw;
    const bool first = ctx_.params.provoking_first;
    const auto tris = draw_triangles(ctx_);
    const char* kind =
        d.state.polygon_mode == PolygonMode::Line ? "polygon edges" : "polygon vertices";
    std::vector<StageTriangle> staged;
    for (std::size_t p = 0; p < tris.size(); ++p) {
        next_primitive(p, obs);
        const auto& at = tris[p];
        const std::array<std::uint32_t, 3> idx{d.element(at.element[0]), d.element(at.element[1]),
                                               d.element(at.element[2])};
        obs.begin_primitive(kind, ctx_.index, p, idx, stage);
        staged.clear();
        stage.clip_triangle(idx, first, staged, nullptr, at.edge_flags);
        for (auto& t : staged) {
            unfilled_stages(
                ctx_, stage, t,
                [&](const StageVertex& a, const StageVertex& b) { segment(stage, a, b, obs); },
                [&](const StageVertex& v) { point(stage, v, obs); });
        }
        obs.end_primitive(KeepRecord::CoveredOrNear);
    }
}

// lp_setup_analyse_triangles (lp_setup_analysis.c), reached from lp_setup_draw_arrays for
// a non-indexed triangle list of exactly 9 vertices drawn without constant-interpolated
// inputs and without the draw pipeline: when the last triangle's three window y values are
// equal, the function claims the whole draw. It hands the first two triangles to
// lp_rect_cw when they form a rectangle and drops them otherwise; measured in an FBO,
// neither case draws anything (scenes triangles.coverage.nine_vertex_quirk_*).
bool LlvmpipeModel::nine_vertex_quirk_drops(const VertexStage& stage,
                                            const std::vector<AssembledTriangle>& tris,
                                            const std::vector<bool>& segment_clipped) const {
    // The owner pass reads gl_PrimitiveID, a constant-interpolated input, and so bypasses
    // the analysis in the driver; the reference's owner pass does the same.
    const Draw& d = ctx_.draw;
    if (!ctx_.profile.quirks.nine_vertex_quirk || ctx_.record_owners) return false;
    if (d.primitive != PrimitiveType::Triangles || d.indices || d.element_count() != 9)
        return false;
    if (d.state.shade == ShadeModel::Flat || tris.size() != 3 || segment_clipped[0]) return false;
    const auto y = [&](std::uint32_t i) { return stage.vertex(i).window[1]; };
    return y(8) == y(7) && y(8) == y(6);
}

template void LlvmpipeModel::setup(VertexStage&, NoObserver&, const ListSink<List>&);
template void LlvmpipeModel::setup(VertexStage&, TraceObserver&, const ListSink<List>&);

}  // namespace refraster::detail
