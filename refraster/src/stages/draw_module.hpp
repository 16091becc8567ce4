// draw_module.hpp: Mesa's draw module (gallium/auxiliary/draw), which llvmpipe and softpipe
// share, written once: what happens to a draw's primitives between the vertex stage and a
// driver's own setup.
//
// Implements: the draw's triangles in the driver's order with their vertex segments, which
// segments go through the draw pipeline (any vertex outside the view volume), the FTZ state of
// each batch the pipeline hands on (pipeline_batches_flushed, draw_batches.cpp), the unfilled
// stages (cull, offset, flat shade, draw_pipe_unfilled.c), and DrawModule: the walk over a
// draw's lines (do_clip_line), points (clip_point, by the centre) and unfilled polygons that
// both Mesa models run, handing each surviving segment, point and filled triangle to the
// driver's own setup (Driver::segment, Driver::point, Driver::triangles), and the lists of
// set-up primitives to the sink a List at a time.
//
// Deliberately does not: set anything up (each driver's setup does), or serve the exact
// model, which has no draw module.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "refraster/assembly.hpp"
#include "stages/model.hpp"
#include "stages/rules.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

// gl_PrimitiveID of a draw's primitive `p` (its triangle, line or point in assembly order),
// which the owner pass records: GL counts a polygon as one primitive whatever triangles it is
// split into, and llvmpipe gives all of them 0 (measured: the owner test over the polygon
// scenes).
inline std::size_t primitive_id(const Draw& d, std::size_t p) {
    return d.primitive == PrimitiveType::Polygon ? 0 : p;
}

// The draw's triangles in the driver's order with their vertex segments (assembly.hpp), for
// the segment sizes of the profile and of the draw's indexing.
inline std::vector<AssembledTriangle> draw_triangles(const DrawContext& ctx) {
    const Draw& d = ctx.draw;
    return assemble_triangles(d.primitive, d.element_count(), ctx.params.provoking_first,
                              ctx.profile.quirks.draw_segment_vertices, d.indices.has_value());
}

// Which vertex segments hold a vertex outside the view volume: the draw module sends exactly
// those through its pipeline (draw_pt_fetch_shade_pipeline_llvm.c).
inline std::vector<bool> clipped_segments(const VertexStage& stage, const Draw& d,
                                          const std::vector<AssembledTriangle>& tris) {
    std::vector<bool> clipped;
    for (const auto& t : tris) {
        if (t.segment >= clipped.size()) clipped.resize(t.segment + 1, false);
        for (auto e : t.element) {
            if (stage.clipmask(d.element(e)) != 0) clipped[t.segment] = true;
        }
    }
    return clipped;
}

// Whether the driver sets up each output triangle of the draw pipeline, in order, with
// denormals flushed (llvmpipe's setup; softpipe's setup and shading, both of which run when
// the vbuf stage hands a batch on). The pipeline's last stage (draw_pipe_vbuf.c, vbuf_tri and
// check_space) collects triangles and hands them to setup when the next one might not fit (vertices
// + 3 > 128: lp_setup_vbuf.c's and sp_prim_vbuf.c's 4096-byte buffers over 32-byte vertices of
// position and colour;
// or indices + 3 > 1024), when a segment that skips the pipeline is emitted (draw_pt_emit.c
// flushes first), and otherwise after draw_vbo has returned. draw_vbo (draw_pt.c) sets
// FTZ/DAZ for its own duration only, so a draw's last batch is set up without them. A
// vertex counts once per batch: the segment's own vertices are shared between its
// triangles, the clipper's new ones between the triangles of one polygon. Empty when no
// triangle needs telling apart (no pipeline segment, or no flushing at all).
std::vector<bool> pipeline_batches_flushed(const DrawContext& ctx, VertexStage& stage,
                                           const std::vector<AssembledTriangle>& tris,
                                           const std::vector<bool>& segment_clipped);

// The draw pipeline's stages after the clipper for polygon modes line and point, shared by
// both models (the same draw module): the float cull stage (draw_pipe_cull.c), the draw
// module's polygon offset (draw_pipe_offset.c), the flat-shade copy (draw_pipe_flatshade.c),
// then draw_pipe_unfilled.c's edges (v2,v0), (v0,v1), (v1,v2) or points v0, v1, v2, each only
// where the polygon's edge flag and the starting vertex's edge flag are set, so that clip-plane
// edges and fan diagonals are not drawn. `line(a, b)` and `point(v)` draw them.
template <class Observer, class Line, class Point>
void unfilled_stages(const DrawContext& ctx, VertexStage& stage, StageTriangle& t, Observer& obs,
                     Line&& line, Point&& point) {
    const Draw& d = ctx.draw;
    const bool first = ctx.params.provoking_first;
    if (!passes_draw_cull(t, d.state.cull, ctx.params.front_ccw)) return;
    if (d.state.polygon_offset) {
        const bool nan_to_zero = ctx.profile.quirks.draw_offset_nan_to_zero;
        if (apply_draw_offset(t, draw_determinant(t, ctx.profile.gl.flush_denormals),
                              *d.state.polygon_offset, ctx.target.depth,
                              ctx.profile.gl.flush_denormals, nan_to_zero,
                              ctx.profile.gl.offset_units_scale)) {
            obs.note(nan_to_zero ? "NaN depth from polygon offset: the draw module's offset of "
                                   "this zero-area triangle is NaN, and SATURATE makes every "
                                   "vertex depth 0"
                                 : "NaN depth from polygon offset: the draw module's offset of "
                                   "this zero-area triangle is NaN, kept as the vertex depth");
        }
    }
    if (d.state.shade == ShadeModel::Flat) {
        const StageVertex prov = t.v[first ? 0 : 2];
        for (std::size_t k = 0; k < 3; ++k) {
            if (k != (first ? 0u : 2u)) t.v[k] = stage.duplicate_with_flat(t.v[k], prov);
        }
    }
    const auto edge = [&](unsigned bit, std::size_t from) {
        return (t.edge_flags & bit) != 0 && t.v[from].edgeflag;
    };
    if (d.state.polygon_mode == PolygonMode::Line) {
        if (edge(4, 2)) line(t.v[2], t.v[0]);
        if (edge(1, 0)) line(t.v[0], t.v[1]);
        if (edge(2, 1)) line(t.v[1], t.v[2]);
    } else {
        if (edge(1, 0)) point(t.v[0]);
        if (edge(2, 1)) point(t.v[1]);
        if (edge(4, 2)) point(t.v[2]);
    }
}

// The draw module's walk over a draw, for a driver model `Driver` that sets primitives up into
// `List`s (CRTP: Driver derives from DrawModule<Driver, List>). The driver provides
//   template <class Observer> void triangles(VertexStage&, Observer&)   filled triangles
//   template <class Observer> void segment(const VertexStage&, const StageVertex&,
//                                          const StageVertex&, Observer&)  one clipped segment
//   template <class Observer> void point(const VertexStage&, const StageVertex&, Observer&)
// and calls begin_lists, dispatch and end_lists from its setup().
template <class Driver, class List>
class DrawModule {
  protected:
    explicit DrawModule(const DrawContext& ctx) : ctx_(ctx) {}

    // A draw's first list: empty, with the vertex stage's attribute count.
    void begin_lists(const ListSink<List>& sink, const VertexStage& stage) {
        sink_ = &sink;
        list_.clear();
        list_.attribute_floats = stage.attribute_floats();
    }

    // The draw's primitives by kind: points, lines, unfilled polygons or filled triangles.
    template <class Observer>
    void dispatch(VertexStage& stage, Observer& obs) {
        const Draw& d = ctx_.draw;
        if (d.primitive == PrimitiveType::Points) {
            points(stage, obs);
        } else if (d.primitive < PrimitiveType::Triangles) {
            lines(stage, obs);
        } else if (d.state.polygon_mode != PolygonMode::Fill) {
            unfilled(stage, obs);
        } else {
            driver().triangles(stage, obs);
        }
    }

    // The draw's last list handed on.
    template <class Observer>
    void end_lists(Observer& obs) {
        if (!list_.primitives.empty()) (*sink_)(list_);
        obs.list_done();
        list_.clear();
    }

    // Starts the next API primitive: hands a full list on first. The render may stop here.
    template <class Observer>
    void next_primitive(std::size_t p, Observer& obs) {
        ctx_.check_stop();
        owner_ = owner_id(ctx_.index, primitive_id(ctx_.draw, p));
        if (list_.full()) {
            (*sink_)(list_);
            obs.list_done();
            list_.clear();
        }
    }

    // Lines: assembly, clipping (do_clip_line), then the driver's segment. Lines are never
    // culled.
    template <class Observer>
    void lines(VertexStage& stage, Observer& obs) {
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
            driver().segment(stage, (*clipped)[0], (*clipped)[1], obs);
            obs.end_primitive(KeepRecord::CoveredOrNear);
        }
    }

    // Points: clipped by their centre (draw_pipe_clip.c clip_point), then the driver's point.
    template <class Observer>
    void points(VertexStage& stage, Observer& obs) {
        const Draw& d = ctx_.draw;
        for (std::size_t p = 0; p < d.element_count(); ++p) {
            const std::array<std::uint32_t, 1> i{d.element(p)};
            if (!stage.keeps_point(i[0])) continue;
            const StageVertex v = stage.vertex(i[0]);
            next_primitive(p, obs);
            obs.begin_primitive("point", ctx_.index, p, i, stage);
            driver().point(stage, v, obs);
            obs.end_primitive(KeepRecord::Covered);
        }
    }

    // Polygon modes line and point: always the draw pipeline (llvmpipe hands unfilled polygons
    // to it, lp_state_rasterizer.c; softpipe has no other path): clip, then unfilled_stages,
    // then the driver's lines and points.
    template <class Observer>
    void unfilled(VertexStage& stage, Observer& obs) {
        const Draw& d = ctx_.draw;
        const bool first = ctx_.params.provoking_first;
        const auto tris = draw_triangles(ctx_);
        const char* kind =
            d.state.polygon_mode == PolygonMode::Line ? "polygon edges" : "polygon vertices";
        std::vector<StageTriangle> staged;
        for (std::size_t p = 0; p < tris.size(); ++p) {
            next_primitive(p, obs);
            const auto& at = tris[p];
            const std::array<std::uint32_t, 3> idx{
                d.element(at.element[0]), d.element(at.element[1]), d.element(at.element[2])};
            obs.begin_primitive(kind, ctx_.index, p, idx, stage);
            staged.clear();
            stage.clip_triangle(idx, first, staged, nullptr, at.edge_flags);
            for (auto& t : staged) {
                unfilled_stages(
                    ctx_, stage, t, obs,
                    [&](const StageVertex& a, const StageVertex& b) {
                        driver().segment(stage, a, b, obs);
                    },
                    [&](const StageVertex& v) { driver().point(stage, v, obs); });
            }
            obs.end_primitive(KeepRecord::CoveredOrNear);
        }
    }

    const DrawContext& ctx_;
    const ListSink<List>* sink_ = nullptr;
    List list_;
    std::uint32_t owner_ = 0;  // of the primitive being set up

  private:
    Driver& driver() { return static_cast<Driver&>(*this); }
};

}  // namespace refraster::detail
