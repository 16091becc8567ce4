// pipeline.hpp: the stage order of one draw, in the spirit of Mesa softpipe's quad pipeline
// (sp_quad_pipe.c): each stage is one call below, in the order the data flows.
//
//   vertex stage      fetch, viewport transform, clip masks      vertex_stage.cpp (draw module:
//                                                                draw_llvm.c generate_viewport,
//                                                                generate_clipmask)
//   model, chosen     assembly (refraster/assembly.hpp), then    llvmpipe_model.cpp: clipper,
//   once a draw       setup into lists of set-up primitives      float cull, polygon modes,
//                     (edges, box, attribute planes, owner)      setup.cpp (lp_setup_tri.c),
//                     in API order                               line_point.cpp (lp_setup_line.c,
//                                                                lp_setup_point.c), planes in
//                                                                fragment.cpp (lp_state_setup.c);
//                                                                or exact_model.cpp (the oracle)
//   traversal         quad packets of the covered pixels, or     traverse.hpp (lp_rast_tri_tmp.h),
//                     row blocks for the fast kernels            quad.hpp, row_block.hpp
//   fragment kernel,  depth, colour, blending, stores            fragment.cpp (lp_bld_interp.c,
//   chosen once a                                                lp_bld_depth.c, lp_bld_blend*.c)
//   draw
//
// An observer watches every stage: TraceObserver for `explain`, NoObserver (nothing at all)
// otherwise. RenderStage stops a draw after a stage, for `refraster bench`'s time split.
//
// Deliberately does not: clear the target or check what a profile can draw (render() does).
#pragma once

#include <cstdint>
#include <span>

#include "exact_model.hpp"
#include "llvmpipe_model.hpp"
#include "model.hpp"
#include "quad.hpp"
#include "refraster/framebuffer.hpp"
#include "refraster/renderer.hpp"
#include "vector_kernels.hpp"
#include "vertex_stage.hpp"

namespace refraster::detail {

// Every primitive of `list` shaded by every thread of ctx.workers, each in its own bands
// (band_workers.hpp): the same bytes as one thread.
template <class Model, class Kernel>
void shade_in_bands(const DrawContext& ctx, const typename Model::List& list, const Kernel& kernel,
                    Framebuffer& fb) {
    BandWorkers& workers = *ctx.workers;
    const unsigned n = workers.count();
    const RowMaskFn masks = vector_row_masks(kernel.path());
    workers.run([&](unsigned t) {
        // The float mode is each thread's own.
        const ScopedDenormalsAreZero float_mode(kernel.hardware_denormals());
        std::uint64_t scratch[kMaxBlockRows];
        for (const auto& prim : list.primitives) {
            Model::traverse_rows(list, prim, masks, [&](const RowBlock& block) {
                const RowBlock mine = band_rows(block, t, n, scratch);
                if (mine.rows != 0) kernel.shade_rows(list, prim, mine, fb);
            });
        }
    });
}

// One draw through every stage of `Model`; returns the pixels traversal found covered when
// the render stops after traversal.
template <class Model, class Observer>
std::uint64_t draw(const DrawContext& ctx, Observer& obs, RenderStage stop, Framebuffer& fb) {
    VertexStage stage(ctx.draw, ctx.vertex_options());
    if (stop == RenderStage::Load) return 0;
    Model model(ctx);
    const auto kernel = model.kernel();
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
        for (std::size_t i = 0; i < list.primitives.size(); ++i) {
            const auto& prim = list.primitives[i];
            obs.before_fragments(i, list, prim, kernel, fb);
            if constexpr (Model::kRowBlocks) {
                if (kernel.shades_rows() && ctx.workers != nullptr &&
                    stop == RenderStage::Fragment) {
                    shade_in_bands<Model>(ctx, list, kernel, fb);
                    break;
                }
                if (kernel.shades_rows()) {
                    Model::traverse_rows(list, prim, masks, [&](const RowBlock& block) {
                        if (stop == RenderStage::Raster) {
                            fragments += static_cast<std::uint64_t>(covered_pixels(block));
                        } else {
                            kernel.shade_rows(list, prim, block, fb);
                        }
                    });
                    continue;
                }
            }
            Model::traverse(list, prim, [&](std::span<const QuadPacket> quads) {
                if (stop == RenderStage::Raster) {
                    fragments += static_cast<std::uint64_t>(covered_pixels(quads));
                } else {
                    kernel.shade(list, prim, quads, fb);
                }
            });
        }
    });
    return fragments;
}

// The model, chosen once per draw from the profile.
template <class Observer>
std::uint64_t run_draw(const DrawContext& ctx, Observer& obs, RenderStage stop, Framebuffer& fb) {
    if (ctx.profile.model == CoverageModel::Exact) return draw<ExactModel>(ctx, obs, stop, fb);
    return draw<LlvmpipeModel>(ctx, obs, stop, fb);
}

}  // namespace refraster::detail
