// model.hpp: what a coverage model is given for one draw, and what it hands on.
//
// Implements: DrawContext, the draw, its target and profile and the values derived from them
// once per draw (setup parameters, whether the viewport transform fuses), and the shape every
// model has, which the stage order (pipeline.hpp) relies on:
//   Model(const DrawContext&)
//   setup(VertexStage&, Observer&, sink)  set-up primitives in API order, a List at a time
//   traverse(list, primitive, emit)       quad packets of the pixels it covers, a tile at a time
//   kernel()                              the per-draw fragment kernel: shade(list, primitive,
//                                         quads, framebuffer) and trace(list, primitive, x, y, fb)
// Models today: LlvmpipeModel (llvmpipe_model.hpp), SoftpipeModel (softpipe_model.hpp) and
// ExactModel (exact_model.hpp).
//
// Deliberately does not: choose the model (pipeline.hpp does, once per draw).
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "stages/band_workers.hpp"
#include "models/llvmpipe/fragment.hpp"
#include "stages/polygon_fill.hpp"
#include "refraster/assembly.hpp"
#include "refraster/draw.hpp"
#include "refraster/profile.hpp"
#include "models/llvmpipe/setup.hpp"
#include "models/llvmpipe/vector_kernels.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

class SoftpipeTileCache;
class SoftpipeSampler;

struct DrawContext {
    std::size_t index = 0;  // of the draw in its DrawList
    const Draw& draw;
    const Target& target;
    const Profile& profile;
    SetupParams params;
    bool fma = false;                        // the viewport transform and plane evaluation fuse
    bool record_owners = false;              // Framebuffer::owner is filled
    KernelPath kernels = KernelPath::Model;  // resolved for this CPU (resolve_kernel_path)
    BandWorkers* workers = nullptr;          // more than one thread shades (band_workers.hpp)
    const TextureUnit* texture = nullptr;    // the draw's texture unit (texture.hpp), if any
    // The scanline model's colour tile cache, which lives for the whole render
    // (softpipe_tiles.hpp); null under the other models.
    SoftpipeTileCache* tiles = nullptr;
    // The model that draws it (draw_model).
    CoverageModel model = CoverageModel::Snapped;
    // The scanline model's sampler of the draw's texture (softpipe_sampler.hpp), if any.
    const SoftpipeSampler* sampler = nullptr;
    // A polygon drawn with a fill rule: the pixels the rule puts inside it (polygon_fill.hpp),
    // each cleared as the first of the polygon's triangles to reach it draws it, as the
    // stencil method's cover pass does (polygon_draw.hpp).
    FillMask* fill = nullptr;

    VertexStageOptions vertex_options() const {
        return {fma, profile.gl.flush_denormals, profile.gl.clipping == Clipping::GuardBand,
                cpu_flushes()};
    }
    // Whether the vertex stage and triangle setup run under the CPU's flush modes with plain
    // float operations instead of the model's emulation (fast paths of a flushing profile on a
    // CPU with the modes; the results are the same, vector_kernels.hpp).
    bool cpu_flushes() const {
        return kernels != KernelPath::Model && profile.gl.flush_denormals &&
               cpu_flush_modes_available();
    }
    FragmentOptions fragment_options() const {
        return {fma,
                profile.gl.flush_denormals,
                params.multisample,
                kernels,
                profile.gl.depth_rounding == Rounding::Truncate,
                profile.gl.color_rounding == Rounding::Truncate};
    }
};

// The model that draws `d` under `profile`: the profile's, except that lines (and polygon mode
// line) follow the line rule and points (and polygon mode point) the point rule, each of which
// belongs to one model's family (parallelogram and square: snapped; Bresenham and two
// triangles: scanline). The exact oracle draws only filled triangles.
inline CoverageModel draw_model(const Profile& profile, const Draw& d) {
    if (profile.model == CoverageModel::Exact) return CoverageModel::Exact;
    const bool triangles = d.primitive >= PrimitiveType::Triangles;
    const bool lines = (!triangles && d.primitive != PrimitiveType::Points) ||
                       (triangles && d.state.polygon_mode == PolygonMode::Line);
    if (lines) {
        return profile.gl.line_rule == LineRule::Bresenham ? CoverageModel::Scanline
                                                           : CoverageModel::Snapped;
    }
    if (d.rasterizes_points()) {
        return profile.gl.point_rule == PointRule::TwoTriangles ? CoverageModel::Scanline
                                                                : CoverageModel::Snapped;
    }
    return profile.model;
}

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
template <class Line, class Point>
void unfilled_stages(const DrawContext& ctx, VertexStage& stage, StageTriangle& t, Line&& line,
                     Point&& point) {
    const Draw& d = ctx.draw;
    const bool first = ctx.params.provoking_first;
    if (!passes_draw_cull(t, d.state.cull, ctx.params.front_ccw)) return;
    if (d.state.polygon_offset) {
        apply_draw_offset(t, draw_determinant(t, ctx.profile.gl.flush_denormals),
                          *d.state.polygon_offset, ctx.target.depth,
                          ctx.profile.gl.flush_denormals);
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

// Receives each full list of set-up primitives, and the last one, in API order.
template <class List>
using ListSink = std::function<void(const List&)>;

}  // namespace refraster::detail
