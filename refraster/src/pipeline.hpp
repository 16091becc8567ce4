// pipeline.hpp: the stage order of one draw, in the spirit of Mesa softpipe's quad pipeline
// (sp_quad_pipe.c): each stage is one call below, in the order the data flows.
//
//   vertex stage      fetch, viewport transform, clip masks      stages/vertex_stage.cpp (draw
//                                                                module: draw_llvm.c
//                                                                generate_viewport,
//                                                                generate_clipmask)
//   draw module       assembly (refraster/assembly.hpp), the     stages/draw_module.hpp,
//                     pipeline's clipper, cull and unfilled      stages/draw_batches.cpp
//                     stages, lines and points
//   model, chosen     setup into lists of set-up primitives      models/llvmpipe/ (setup.cpp:
//   once a draw       (edges, box, attribute planes, owner)      lp_setup_tri.c; line_point.cpp;
//                     in API order                               planes.cpp:
//                                                                lp_state_setup.c), or
//                                                                models/softpipe/ (sp_setup.c),
//                                                                or models/exact/ (the oracle)
//   traversal         quad packets of the covered pixels, or     models/llvmpipe/traverse.hpp
//                     row blocks for the fast kernels            (lp_rast_tri_tmp.h),
//                                                                stages/quad.hpp, row_block.hpp
//   fragment kernel,  depth, colour, blending, stores            models/llvmpipe/fragment.cpp
//   chosen once a                                                (lp_bld_interp.c,
//   draw                                                         lp_bld_depth.c), the output
//                                                                merge: stages/output_merge.hpp
//
// Each model meets the DriverModel contract (stages/model.hpp); ModelStates holds what each
// keeps for a whole render.
//
// An observer watches every stage: TraceObserver for `explain`, NoObserver (nothing at all)
// otherwise. RenderStage stops a draw after a stage, for `refraster bench`'s time split.
//
// Deliberately does not: clear the target or check what a profile can draw (render() does).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "models/exact/exact_model.hpp"
#include "models/llvmpipe/llvmpipe_model.hpp"
#include "models/llvmpipe/vector_kernels.hpp"
#include "models/softpipe/softpipe_fill.hpp"
#include "models/softpipe/softpipe_model.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/renderer.hpp"
#include "stages/model.hpp"
#include "stages/polygon_draw.hpp"
#include "stages/quad.hpp"
#include "stages/vertex_stage.hpp"

namespace refraster::detail {

static_assert(DriverModel<LlvmpipeModel>);
static_assert(DriverModel<SoftpipeModel>);
static_assert(DriverModel<ExactModel>);

// What every model keeps for the whole of one render.
struct ModelStates {
    LlvmpipeModel::RenderState llvmpipe;
    SoftpipeModel::RenderState softpipe;
    ExactModel::RenderState exact;

    // `fast_scanline`: the render's scanline draws take the softpipe model's fast path.
    ModelStates(const DrawList& list, const Profile& profile, Framebuffer& fb,
                bool fast_scanline = false)
        : llvmpipe(list, profile, fb),
          softpipe(list, profile, fb, fast_scanline),
          exact(list, profile, fb) {}

    // The render's end: whatever a model still holds is written back.
    void finish_render() { softpipe.flush_shared_tiles(); }
};

// The pixels a polygon's fill rule lights (polygon_draw.hpp): the stencil pass's count of
// softpipe's own coverage under the scanline rules, the filler over the snapped outline
// otherwise; nullopt when a position cannot be snapped.
inline std::optional<FillMask> fill_rule_mask(const DrawContext& ctx) {
    if (ctx.model == CoverageModel::Scanline) return softpipe_fill_mask(ctx);
    return outline_fill_mask(ctx);
}

// The primitives of a list by 64-row band: band b holds, in API order, every primitive whose
// box reaches one of its rows (a primitive llvmpipe's walk decides is put in every band).
struct BandBins {
    std::vector<std::uint32_t> start;  // band b's primitives: index[start[b] .. start[b + 1])
    std::vector<std::uint32_t> index;

    template <class List>
    void fill(const List& list, int bands) {
        start.assign(static_cast<std::size_t>(bands) + 1, 0);
        const auto range = [&](const SetupPrimitive& p) {
            if (p.walk >= 0) return std::pair{0, bands - 1};
            if (p.bbox.empty()) return std::pair{1, 0};
            return std::pair{std::max(p.bbox.y0, 0) / kBandRows,
                             std::min(p.bbox.y1 / kBandRows, bands - 1)};
        };
        for (const auto& p : list.primitives) {
            const auto [b0, b1] = range(p);
            for (int b = b0; b <= b1; ++b) ++start[static_cast<std::size_t>(b) + 1];
        }
        for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
        index.resize(start.back());
        std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
        for (std::uint32_t i = 0; i < list.primitives.size(); ++i) {
            const auto [b0, b1] = range(list.primitives[i]);
            for (int b = b0; b <= b1; ++b) index[next[static_cast<std::size_t>(b)]++] = i;
        }
    }
};

// Every primitive of `list` shaded band by band (64 rows of the target at a time, so that a
// band's colour and depth stay in the cache while every primitive reaching it is shaded), each
// band by one thread of ctx.workers (band_workers.hpp; all of them with no workers): within a
// band the primitives keep API order, so the bytes are those of primitive-by-primitive
// shading for any count of threads. `on_block(list, prim, block)` shades or counts.
template <class Model, class Kernel, class OnBlock>
void shade_by_band(const DrawContext& ctx, const typename Model::List& list, const Kernel& kernel,
                   RowMaskFn masks, bool float_mode, Framebuffer& fb, OnBlock&& on_block) {
    const int bands = static_cast<int>((fb.height + kBandRows - 1) / kBandRows);
    BandBins bins;
    bins.fill(list, bands);
    const auto run = [&](unsigned t, unsigned n) {
        // The float mode is each thread's own.
        const ScopedDenormalsAreZero mode(float_mode && kernel.hardware_denormals());
        std::uint64_t scratch[kMaxBlockRows];
        for (int b = static_cast<int>(t); b < bands; b += static_cast<int>(n)) {
            const auto bi = static_cast<std::size_t>(b);
            for (std::uint32_t k = bins.start[bi]; k < bins.start[bi + 1]; ++k) {
                // A stopping render: every thread returns, and the caller throws.
                if (ctx.stop_requested()) return;
                const auto& prim = list.primitives[bins.index[k]];
                Model::traverse_band(list, prim, masks, b * kBandRows, scratch,
                                     [&](const RowBlock& block) { on_block(prim, block); });
            }
        }
    };
    if (ctx.workers == nullptr) {
        run(0, 1);
    } else {
        ctx.workers->run([&](unsigned t) { run(t, ctx.workers->count()); });
    }
    ctx.check_stop();
}

// The cover pass of a fill rule (polygon_draw.hpp): of each packet the pixels the mask still
// holds, each cleared as it is taken, so that the first triangle to reach a pixel draws it.
// Single-sample packets only (a fill rule on a 4x target is refused).
inline std::span<const QuadPacket> claim_fill_pixels(FillMask& mask,
                                                     std::span<const QuadPacket> quads,
                                                     std::vector<QuadPacket>& out) {
    out.clear();
    for (const QuadPacket& q : quads) {
        std::uint16_t m = 0;
        for (unsigned p = 0; p < 4; ++p) {
            if ((q.mask & (1u << p)) == 0) continue;
            const int x = q.x + static_cast<int>(p & 1u);
            const int y = q.y + static_cast<int>(p >> 1);
            if (!mask.test(x, y)) continue;
            mask.reset(x, y);
            m = static_cast<std::uint16_t>(m | (1u << p));
        }
        if (m != 0) out.push_back({q.x, q.y, m});
    }
    return out;
}

// One draw through every stage of `Model`; returns the pixels traversal found covered when
// the render stops after traversal.
template <DriverModel Model, class Observer>
std::uint64_t draw(const DrawContext& ctx, typename Model::RenderState& state, Observer& obs,
                   RenderStage stop, Framebuffer& fb) {
    VertexStage stage(ctx.draw, ctx.vertex_options());
    if (stop == RenderStage::Load) return 0;
    Model model(ctx, state);
    const auto kernel = model.kernel();
    // A fill rule's cover pass claims pixels in API order, a quad packet at a time.
    [[maybe_unused]] bool row_blocks = false;
    if constexpr (Model::kRowBlocks) {
        row_blocks = ctx.fill == nullptr && kernel.shades_rows();
        // One thread shades each list of 256 primitives in the cache that set it up; with
        // shading threads the lists are longer than that cache and other cores shade them.
        if (row_blocks && stop == RenderStage::Fragment && ctx.workers == nullptr)
            model.prefetch_into(&fb);
    }
    std::vector<QuadPacket> claimed;
    // Row masks of small boxes by the vector builder of the kernel's path (the same rows as
    // the scalar one's), chosen once a draw.
    [[maybe_unused]] RowMaskFn masks = nullptr;
    if constexpr (Model::kRowBlocks) masks = vector_row_masks(kernel.path());
    std::uint64_t fragments = 0;
    model.setup(stage, obs, [&](const typename Model::List& list) {
        if (stop == RenderStage::Setup) return;
        // Traversal is integer arithmetic only: the float mode holds for the whole list.
        const ScopedDenormalsAreZero float_mode(kernel.hardware_denormals() &&
                                                stop == RenderStage::Fragment);
        if constexpr (Model::kRowBlocks) {
            if (row_blocks) {
                // The fast paths (never traced: no observer reads these fragments).
                shade_by_band<Model>(ctx, list, kernel, masks, stop == RenderStage::Fragment, fb,
                                     [&](const auto& prim, const RowBlock& block) {
                                         if (stop == RenderStage::Raster) {
                                             fragments +=
                                                 static_cast<std::uint64_t>(covered_pixels(block));
                                         } else {
                                             kernel.shade_rows(list, prim, block, fb);
                                         }
                                     });
                return;
            }
        }
        for (std::size_t i = 0; i < list.primitives.size(); ++i) {
            ctx.check_stop();
            const auto& prim = list.primitives[i];
            obs.before_fragments(i, list, prim, kernel, fb);
            Model::traverse(list, prim, [&](std::span<const QuadPacket> quads) {
                ctx.check_stop();
                if (ctx.fill != nullptr) quads = claim_fill_pixels(*ctx.fill, quads, claimed);
                if (stop == RenderStage::Raster) {
                    fragments += static_cast<std::uint64_t>(covered_pixels(quads));
                } else {
                    kernel.shade(list, prim, quads, fb);
                }
            });
        }
    });
    model.finish_draw();
    return fragments;
}

// The model, chosen once per draw from the profile.
// A draw of the other model's family than the render's tile cache (the profile's line or point
// rule) finds that cache written back and leaves it empty. So does a draw with a fill rule: its
// stencil pass starts with a clear of the stencil alone, which in softpipe writes every colour
// tile back (sp_clear.c softpipe_clear clears part of a combined depth-stencil buffer with
// util_clear_depth_stencil, whose map of the surface, sp_texture.c softpipe_transfer_map, calls
// sp_flush.c softpipe_flush_resource and so softpipe_flush), so blending over an earlier draw
// then reads its quantised bytes, not its floats.
template <class Observer>
std::uint64_t run_draw(const DrawContext& ctx, ModelStates& states, Observer& obs, RenderStage stop,
                       Framebuffer& fb) {
    if (ctx.model != CoverageModel::Scanline ||
        (ctx.draw.state.fill_rule && ctx.profile.quirks.fill_clear_writes_tiles))
        states.softpipe.flush_shared_tiles();
    switch (ctx.model) {
        case CoverageModel::Exact:
            return draw<ExactModel>(ctx, states.exact, obs, stop, fb);
        case CoverageModel::Scanline:
            return draw<SoftpipeModel>(ctx, states.softpipe, obs, stop, fb);
        case CoverageModel::Snapped:
            break;
    }
    return draw<LlvmpipeModel>(ctx, states.llvmpipe, obs, stop, fb);
}

}  // namespace refraster::detail
