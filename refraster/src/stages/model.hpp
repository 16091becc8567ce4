// model.hpp: what a coverage model is given for one draw, and what it hands on.
//
// Implements: DrawContext, the draw, its target and profile and the values derived from them
// once per draw (setup parameters, whether the viewport transform fuses), the same for every
// model; and the contract every driver model meets, checked by the compiler (DriverModel):
//   Model::RenderState(list, profile, fb)  what the model keeps for a whole render (texture
//                                          levels, a tile cache), made once per render
//   Model(const DrawContext&, RenderState&) the model's per-draw state (its texture unit, its
//                                          sampler), made once per draw
//   setup(VertexStage&, Observer&, sink)   set-up primitives in API order, a List at a time
//   traverse(list, primitive, emit)        quad packets of the pixels it covers
//   kernel()                               the per-draw fragment kernel: shade(list, primitive,
//                                          quads, framebuffer), trace(...)
//   finish_draw()                          what the draw leaves to write back
// Models today: LlvmpipeModel (models/llvmpipe/), SoftpipeModel (models/softpipe/) and
// ExactModel (models/exact/).
//
// Deliberately does not: choose the model (pipeline.hpp does, once per draw), or name any
// model's types: a model's own state lives in the model.
#pragma once

#include <concepts>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "common/cpu.hpp"
#include "common/stop.hpp"
#include "refraster/assembly.hpp"
#include "refraster/draw.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/profile.hpp"
#include "refraster/renderer.hpp"
#include "stages/band_workers.hpp"
#include "stages/edge_rules.hpp"
#include "stages/observer.hpp"
#include "stages/polygon_fill.hpp"
#include "stages/quad.hpp"
#include "stages/rules.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

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
    // The model that draws it (draw_model).
    CoverageModel model = CoverageModel::Snapped;
    // A polygon drawn with a fill rule: the pixels the rule puts inside it (polygon_fill.hpp),
    // each cleared as the first of the polygon's triangles to reach it draws it, as the
    // stencil method's cover pass does (polygon_draw.hpp).
    FillMask* fill = nullptr;
    // The render's stop signal (common/stop.hpp); null: the render cannot be stopped.
    const StopSignal* stop = nullptr;

    // Throws RenderStopped when the render must stop (the calling thread only; a shading
    // thread tests stop_requested and returns instead).
    void check_stop() const {
        if (stop != nullptr) stop->throw_if_requested();
    }
    bool stop_requested() const { return stop != nullptr && stop->requested(); }

    VertexStageOptions vertex_options() const {
        return {.fma = fma,
                .flush_denormals = profile.gl.flush_denormals,
                .guard_band = clips_by_guard_band(profile, draw.primitive, draw.state),
                .keep_points_past_xy = keeps_points_past_xy(profile, draw.primitive),
                .cpu_flushes = cpu_flushes()};
    }
    // Whether the vertex stage and triangle setup run under the CPU's flush modes with plain
    // float operations instead of the model's emulation (fast paths of a flushing profile on a
    // CPU with the modes; the results are the same, vector_kernels.hpp).
    bool cpu_flushes() const {
        return kernels != KernelPath::Model && profile.gl.flush_denormals &&
               cpu_flush_modes_available();
    }
};

// The model that draws `d` under `profile`: the profile's, except that lines (and polygon mode
// line) follow the line rule and points (and polygon mode point) the point rule, each of which
// belongs to one model's family (parallelogram and square: snapped; Bresenham and two
// triangles: scanline). The exact oracle draws only filled triangles.
inline CoverageModel draw_model(const Profile& profile, const Draw& d) {
    if (profile.model == CoverageModel::Exact) return CoverageModel::Exact;
    if (d.rasterizes_lines()) {
        return profile.gl.line_rule == LineRule::Bresenham ? CoverageModel::Scanline
                                                           : CoverageModel::Snapped;
    }
    if (d.rasterizes_points()) {
        return profile.gl.point_rule == PointRule::TwoTriangles ? CoverageModel::Scanline
                                                                : CoverageModel::Snapped;
    }
    return profile.model;
}

// Receives each full list of set-up primitives, and the last one, in API order.
template <class List>
using ListSink = std::function<void(const List&)>;

// The contract of a driver model (the shape pipeline.hpp's stage order relies on), checked
// where the pipeline instantiates each model.
template <class M>
concept DriverModel = requires(M model, const M& cmodel, const DrawContext& ctx,
                               typename M::RenderState& state, VertexStage& stage, NoObserver& obs,
                               const ListSink<typename M::List>& sink, const typename M::List& list,
                               const typename M::Primitive& prim,
                               void (*emit)(std::span<const QuadPacket>),
                               std::span<const QuadPacket> quads, Framebuffer& fb,
                               const Profile& profile, const DrawList& draws) {
    typename M::RenderState;
    { M::kRowBlocks } -> std::convertible_to<bool>;
    requires std::constructible_from<typename M::RenderState, const DrawList&, const Profile&,
                                     Framebuffer&>;
    requires std::constructible_from<M, const DrawContext&, typename M::RenderState&>;
    model.setup(stage, obs, sink);
    M::traverse(list, prim, emit);
    cmodel.kernel().shade(list, prim, quads, fb);
    { cmodel.kernel().hardware_denormals() } -> std::convertible_to<bool>;
    model.finish_draw();
};

}  // namespace refraster::detail
