// llvmpipe_model.hpp: the snapped model, llvmpipe 22.3's setup and traversal.
//
// Implements: from a draw's vertex stage to set-up primitives in API order, as Mesa's draw
// module and llvmpipe's setup produce them: triangle assembly and segments, the draw
// pipeline for segments that need clipping (clipper, float cull, the FTZ state each batch of
// its output is set up under), llvmpipe's nine-vertex rectangle analysis, fixed-point triangle
// setup (setup.hpp) and attribute planes (planes.hpp); lines (do_clip_line, try_setup_line)
// and points (clip_point, try_setup_point); polygon modes line and point through the draw
// pipeline's offset, flat-shade and unfilled stages. Traversal of a set-up primitive into
// quad packets (traverse.hpp), with llvmpipe's own walk where its integer widths decide
// (llvmpipe_walk.hpp). The draw module's own walk over lines, points and unfilled polygons is
// the one both Mesa models share (stages/draw_module.hpp); this model sets up what it hands on.
//
// Deliberately does not: shade (the fragment kernel does), or know about the other models.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "models/llvmpipe/fragment.hpp"
#include "models/llvmpipe/planes.hpp"
#include "models/llvmpipe/setup_list.hpp"
#include "models/llvmpipe/texture.hpp"
#include "models/llvmpipe/traverse.hpp"
#include "refraster/assembly.hpp"
#include "stages/band_workers.hpp"
#include "stages/draw_module.hpp"
#include "stages/model.hpp"

namespace refraster::detail {

// The per-pixel stage's options for a draw (fragment.hpp), from the draw's context.
inline FragmentOptions fragment_options(const DrawContext& ctx) {
    return {ctx.fma,
            ctx.profile.gl.flush_denormals,
            ctx.params.multisample,
            ctx.kernels,
            ctx.profile.gl.depth_rounding == Rounding::Truncate,
            ctx.profile.gl.color_rounding == Rounding::Truncate,
            ctx.profile.gl.offset_units_scale};
}

class LlvmpipeModel : public DrawModule<LlvmpipeModel, SetupList> {
  public:
    using List = SetupList;
    using Primitive = SetupPrimitive;

    // Every texture's levels for the whole render: the draw list's own, or (generated mipmaps)
    // the base and the levels made once, as glGenerateMipmap makes them (texture.hpp).
    class RenderState {
      public:
        RenderState(const DrawList& list, const Profile& profile, Framebuffer& fb);
        const std::vector<TextureImage>& levels(std::uint32_t texture) const;
        // The levels packed for the vector sampler, made at the first draw that asks (on the
        // thread that sets draws up) and kept for the render; null when they do not fit.
        const PackedLevels* packed(std::uint32_t texture);

      private:
        std::vector<std::vector<TextureImage>> generated_;
        std::vector<const std::vector<TextureImage>*> levels_;
        std::vector<std::optional<PackedLevels>> packed_;
        std::vector<bool> packed_tried_;
    };

    LlvmpipeModel(const DrawContext& ctx, RenderState& state);

    template <class Observer>
    void setup(VertexStage& stage, Observer& obs, const ListSink<List>& sink);

    template <class Emit>
    static void traverse(const SetupList& list, const SetupPrimitive& p, Emit&& emit) {
        const auto quads = [&](const std::uint64_t* rows, int tx, int ty) {
            emit_tile_quads(rows, tx, ty, emit);
        };
        if (list.multisample) {
            if (p.walk >= 0) {
                lp::walk_binned(list.walks[static_cast<std::size_t>(p.walk)],
                                [&](const lp::Walk& w) {
                                    emit_tile_quads_4x(w.rows, w.tile_x, w.tile_y, emit);
                                });
            } else if (p.edge_count == 3) {
                convex_quads_4x<3>(p, emit);
            } else {
                convex_quads_4x<4>(p, emit);
            }
        } else if (p.walk >= 0) {
            lp::walk_tiles(list.walks[static_cast<std::size_t>(p.walk)], quads);
        } else if (p.edge_count == 3) {
            convex_tiles<3>(p, quads);
        } else {
            convex_tiles<4>(p, quads);
        }
    }

    // Primitives can also be traversed into row blocks (row_block.hpp), which the fast fragment
    // kernels read: llvmpipe's walk a tile at a time, convex primitives through the small-box
    // path (with the vector row-mask builder `masks`, when given: the same rows) or a tile at a
    // time; on a multisample list, 4x blocks of the same samples traverse() finds.
    static constexpr bool kRowBlocks = true;
    template <class OnBlock>
    static void traverse_rows(const SetupList& list, const SetupPrimitive& p, RowMaskFn masks,
                              OnBlock&& on_block) {
        const int samples = list.multisample ? 4 : 1;
        if (p.walk >= 0) {
            lp::walk_binned(list.walks[static_cast<std::size_t>(p.walk)], [&](const lp::Walk& w) {
                on_block(RowBlock{w.tile_x, w.tile_y, kTileSize, &w.rows[0][0], samples});
            });
        } else if (list.multisample) {
            convex_blocks_4x(p, masks, p.bbox.x0, p.bbox.y0, on_block);
        } else if (p.edge_count == 3) {
            convex_row_blocks<3>(p, on_block, masks);
        } else {
            convex_row_blocks<4>(p, on_block, masks);
        }
    }

    // The covered pixels of `p` in the 64-row band from row y0 (band_workers.hpp), as row
    // blocks: a convex primitive's box clipped to the band (the same pixels, as coverage
    // does not depend on the box; the scissor leak stays at the whole box's first row),
    // llvmpipe's walk by its tiles in the band.
    template <class OnBlock>
    static void traverse_band(const SetupList& list, const SetupPrimitive& p, RowMaskFn masks,
                              int y0, std::uint64_t* scratch, OnBlock&& on_block) {
        (void)scratch;
        const int y1 = y0 + kBandRows - 1;
        const int samples = list.multisample ? 4 : 1;
        if (p.walk >= 0) {
            lp::walk_binned(list.walks[static_cast<std::size_t>(p.walk)], [&](const lp::Walk& w) {
                // Tiles and bands are both 64 rows from row 0.
                if (w.tile_y == y0)
                    on_block(RowBlock{w.tile_x, w.tile_y, kTileSize, &w.rows[0][0], samples});
            });
            return;
        }
        SetupPrimitive c = p;
        c.bbox.y0 = std::max(c.bbox.y0, y0);
        c.bbox.y1 = std::min(c.bbox.y1, y1);
        if (c.bbox.empty()) return;
        if (list.multisample) {
            convex_blocks_4x(c, masks, p.bbox.x0, p.bbox.y0, on_block);
        } else if (p.edge_count == 3) {
            convex_row_blocks<3>(c, on_block, masks);
        } else {
            convex_row_blocks<4>(c, on_block, masks);
        }
    }

    // The target shading will write: setup asks the caches for the lines of each small
    // triangle's rows as it sets the triangle up (nullptr: it does not).
    void prefetch_into(const Framebuffer* fb) { prefetch_fb_ = fb; }

    FragmentKernel kernel() const {
        return choose_fragment_kernel(ctx_.draw, ctx_.target, fragment_options(ctx_),
                                      unit_ ? &*unit_ : nullptr);
    }

    // Nothing is left to write back: llvmpipe's tiles are the framebuffer's.
    void finish_draw() {}

  private:
    friend class DrawModule<LlvmpipeModel, SetupList>;

    template <class Observer>
    void triangles(VertexStage& stage, Observer& obs);
    template <class Observer>
    void snapped_triangle(const VertexStage& stage, const std::array<const StageVertex*, 3>& v,
                          bool clipped, bool in_pipeline, bool setup_ftz, Observer& obs);
    template <class Observer>
    void segment(const VertexStage& stage, const StageVertex& v1, const StageVertex& v2,
                 Observer& obs);
    template <class Observer>
    void point(const VertexStage& stage, const StageVertex& v, Observer& obs);

    bool nine_vertex_quirk_drops(const VertexStage& stage,
                                 const std::vector<AssembledTriangle>& tris,
                                 const std::vector<bool>& segment_clipped) const;
    template <class Observer>
    PlaneNeeds plane_needs() const;

    template <class OnBlock>
    static void convex_blocks_4x(const SetupPrimitive& p, RowMaskFn masks, int leak_x, int leak_y,
                                 OnBlock&& on_block) {
        if (p.edge_count == 3) {
            convex_row_blocks_4x<3>(p, on_block, masks, leak_x, leak_y);
        } else {
            convex_row_blocks_4x<4>(p, on_block, masks, leak_x, leak_y);
        }
    }

    std::optional<TextureUnit> unit_;  // the draw's texture unit, if it samples one
    // Triangle setup runs with the CPU's flush modes set and plain float operations where
    // the model emulates the flushing (fast paths of a flushing profile only).
    bool cpu_flushes_ = false;
    // The draw's fragment options (fragment_options), and the same without flushing: a
    // triangle's attribute setup takes one or the other whole (set once a draw: building the
    // options a triangle cost a store-forwarding stall there).
    FragmentOptions fragment_options_{};
    FragmentOptions fragment_options_plain_{};
    TriangleSetup triangle_;  // the triangle being set up, kept to spare clearing its walk
    const Framebuffer* prefetch_fb_ = nullptr;
};

}  // namespace refraster::detail
