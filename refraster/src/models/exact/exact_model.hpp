// exact_model.hpp: the exact oracle as a model: filled triangles decided and shaded exactly.
//
// Implements: setup of a triangle draw into ExactPrimitives in API order (the exact coverage
// test of exact_coverage.hpp, GL's cull decision on its exact orientation, the exact shader
// of fragment.hpp), their traversal over the candidate pixels into quad packets, and the
// kernel that shades those packets.
//
// Deliberately does not: snap, clip, or reproduce any driver's rounding; draw lines, points
// or polygon modes (render() refuses those with NotSupported); trace fragments (the trace
// records the oracle's weights instead).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "models/exact/exact_coverage.hpp"
#include "models/exact/exact_shader.hpp"
#include "stages/draw_module.hpp"
#include "stages/model.hpp"
#include "stages/quad.hpp"
#include "stages/rules.hpp"

namespace refraster::detail {

struct ExactPrimitive {
    std::unique_ptr<ExactCoverage> coverage;
    std::unique_ptr<ExactShader> shader;  // reads *coverage
    std::uint32_t owner = 0;
};

struct ExactList {
    static constexpr std::size_t kCapacity = 1024;
    std::vector<ExactPrimitive> primitives;
    bool full() const { return primitives.size() >= kCapacity; }
    void clear() { primitives.clear(); }
};

class ExactKernel {
  public:
    void shade(const ExactList&, const ExactPrimitive& p, std::span<const QuadPacket> quads,
               Framebuffer& fb) const {
        for (const QuadPacket& q : quads) {
            for (unsigned i = 0; i < 4; ++i) {
                if ((q.mask & (1u << quad_bit(i, 0))) != 0) {
                    p.shader->shade(q.x + static_cast<int>(i & 1u), q.y + static_cast<int>(i >> 1),
                                    fb, p.owner);
                }
            }
        }
    }
    bool hardware_denormals() const { return false; }
    FragmentTrace trace(const ExactList&, const ExactPrimitive&, int, int, unsigned,
                        const Framebuffer&) const {
        return {};
    }
};

class ExactModel {
  public:
    using List = ExactList;
    using Primitive = ExactPrimitive;

    // The oracle keeps nothing for a whole render.
    struct RenderState {
        RenderState(const DrawList&, const Profile&, Framebuffer&) {}
    };

    ExactModel(const DrawContext& ctx, RenderState&) : ctx_(ctx) {}
    static constexpr bool kRowBlocks = false;  // quad packets only

    template <class Observer>
    void setup(VertexStage& stage, Observer& obs, const ListSink<List>& sink);

    // The candidate pixels, a row pair at a time, as quad packets of the covered ones.
    template <class Emit>
    static void traverse(const List&, const ExactPrimitive& p, Emit&& emit) {
        const PixelRect r = p.coverage->candidates();
        if (r.empty()) return;
        std::vector<QuadPacket> quads;
        for (int y = r.y0 & ~1; y <= r.y1; y += 2) {
            quads.clear();
            for (int x = r.x0 & ~1; x <= r.x1; x += 2) {
                std::uint16_t mask = 0;
                for (unsigned i = 0; i < 4; ++i) {
                    const int px = x + static_cast<int>(i & 1u);
                    const int py = y + static_cast<int>(i >> 1);
                    if (px >= r.x0 && px <= r.x1 && py >= r.y0 && py <= r.y1 &&
                        p.coverage->covers(px, py)) {
                        mask = static_cast<std::uint16_t>(mask | (1u << quad_bit(i, 0)));
                    }
                }
                if (mask != 0) quads.push_back({x, y, mask});
            }
            if (!quads.empty()) emit(std::span<const QuadPacket>(quads));
        }
    }

    ExactKernel kernel() const { return {}; }
    void finish_draw() {}

  private:
    const DrawContext& ctx_;
};

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
        ctx_.check_stop();
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
            stage, d, ctx_.target, first, ctx_.profile.gl.offset_units_scale);
        prim.coverage = std::move(ex);
        prim.owner = owner_id(ctx_.index, primitive_id(ctx_.draw, p));
        obs.exact_setup(*prim.coverage);
        obs.end_primitive(KeepRecord::CoveredOrNear);
    }
    if (!list.primitives.empty()) sink(list);
    obs.list_done();
}

}  // namespace refraster::detail
