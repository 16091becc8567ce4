// softpipe_model.hpp: the scanline model, Mesa 22.3 softpipe's setup and traversal.
//
// Implements: from a draw's vertex stage to set-up primitives in API order, as Mesa's draw
// module and softpipe's setup (gallium/drivers/softpipe/sp_setup.c) produce them: triangle
// assembly and the draw module's clipper and float cull (the same draw module as llvmpipe's:
// vertex_stage.hpp), then softpipe's float scanline setup (scanline_setup.hpp: no snapping,
// the vertices sorted by y, truncating spans, its own facing and cull) and attribute planes;
// lines as Bresenham segments of the truncated end points (sp_setup_line), wide ones as the
// draw module's two triangles (draw_pipe_wide_line.c); points as the
// draw module's point sprites, two triangles each (draw_pipe_wide_point.c). Traversal of a set-up
// primitive's rows into quad packets. The draw module's walk over lines, points and unfilled
// polygons is the one both Mesa models share (stages/draw_module.hpp). The fragment stage:
// softpipe_fragment.hpp.
//
// Deliberately does not: snap, multisample (softpipe has no multisampling: render() answers
// NotSupported), texture (refused the same way), or reproduce llvmpipe's quirks.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "models/softpipe/softpipe_fragment.hpp"
#include "models/softpipe/softpipe_lazy_tiles.hpp"
#include "models/softpipe/softpipe_sampler.hpp"
#include "models/softpipe/softpipe_tiles.hpp"
#include "stages/draw_module.hpp"
#include "stages/model.hpp"
#include "stages/quad.hpp"

namespace refraster::detail {

class SoftpipeModel : public DrawModule<SoftpipeModel, ScanlineList> {
  public:
    using List = ScanlineList;
    using Primitive = ScanlinePrimitive;
    static constexpr bool kRowBlocks = false;  // quad packets only

    // What softpipe keeps for a whole render: under a scanline profile its colour tile cache,
    // in which colours stay float until written back (softpipe_tiles.hpp); the levels its
    // sampler generates for a texture with generated mipmaps, made once a texture. `fast`:
    // the render's scanline draws take the fast path, whose tile cache is SoftpipeLazyTiles.
    class RenderState {
      public:
        RenderState(const DrawList& list, const Profile& profile, Framebuffer& fb,
                    bool fast = false);
        // Writes the render's tile cache back before a draw of another model's family (the
        // profile's line or point rule) reads or writes the surface, and at the render's end.
        void flush_shared_tiles() {
            if (tiles_) tiles_->flush();
            if (lazy_) lazy_->flush();
        }

      private:
        friend class SoftpipeModel;
        const DrawList& list_;
        Framebuffer& fb_;
        bool truncate_colors_ = false;
        bool fast_ = false;
        std::optional<SoftpipeTileCache> tiles_;
        std::optional<SoftpipeLazyTiles> lazy_;
        std::vector<std::vector<TextureImage>> generated_levels_;
    };

    SoftpipeModel(const DrawContext& ctx, RenderState& state);

    template <class Observer>
    void setup(VertexStage& stage, Observer& obs, const ListSink<List>& sink);

    // The primitive's quads a batch at a time, as softpipe hands them to its quad pipeline:
    // a line's quads one by one in plotting order (clip_emit_quad); a triangle's a 2-row block
    // (an even row and the one above it) at a time, bottom to top, each block in 16-pixel
    // aligned column chunks from (min(left) & ~15) to max(right), left to right, each chunk's
    // non-empty quads one batch (sp_setup.c flush_spans).
    template <class Emit>
    static void traverse(const ScanlineList& list, const ScanlinePrimitive& p, Emit&& emit) {
        if (p.quad_count != 0) {
            for (std::uint32_t q = 0; q < p.quad_count; ++q)
                emit(std::span<const QuadPacket>(&list.quads[p.first_quad + q], 1));
            return;
        }
        const auto rows = list.rows_of(p);
        if (list.fast) return traverse_fast(rows, emit);
        std::array<QuadPacket, 8> batch;
        std::size_t r = 0;
        while (r < rows.size()) {
            const int y0 = rows[r].y & ~1;
            // The (at most two) rows of this block; rows are sorted bottom to top, one a y.
            const ScanlineRow* lo = nullptr;
            const ScanlineRow* hi = nullptr;
            if (rows[r].y == y0) {
                lo = &rows[r++];
                if (r < rows.size() && rows[r].y == y0 + 1) hi = &rows[r++];
            } else {
                hi = &rows[r++];
            }
            const int left =
                std::min(lo != nullptr ? lo->x0 : hi->x0, hi != nullptr ? hi->x0 : lo->x0);
            const int right =
                std::max(lo != nullptr ? lo->x1 : hi->x1, hi != nullptr ? hi->x1 : lo->x1);
            for (int chunk = left & ~15; chunk < right; chunk += 16) {
                std::size_t n = 0;
                for (int x = chunk; x < chunk + 16; x += 2) {
                    unsigned mask = 0;
                    for (unsigned k = 0; k < 4; ++k) {
                        const ScanlineRow* row = k < 2 ? lo : hi;
                        const int px = x + static_cast<int>(k & 1u);
                        if (row != nullptr && px >= row->x0 && px < row->x1)
                            mask |= 1u << quad_bit(k, 0);
                    }
                    if (mask != 0) batch[n++] = {x, y0, static_cast<std::uint16_t>(mask)};
                }
                if (n != 0) emit(std::span<const QuadPacket>(batch.data(), n));
            }
        }
    }

    // traverse's batches of a triangle's rows, each chunk's quads from two 16-bit masks of the
    // rows' runs: the same packets in the same order.
    template <class Emit>
    static void traverse_fast(std::span<const ScanlineRow> rows, Emit&& emit) {
        std::array<QuadPacket, 8> batch;
        std::size_t r = 0;
        // The pixels of [chunk, chunk + 16) in `row` (none for no row), bit i for chunk + i.
        const auto run_bits = [](const ScanlineRow* row, int chunk) -> std::uint32_t {
            if (row == nullptr) return 0;
            const int a = std::max(row->x0, chunk) - chunk;
            const int b = std::min(row->x1, chunk + 16) - chunk;
            if (a >= b) return 0;
            return ((1u << b) - 1u) & ~((1u << a) - 1u);
        };
        while (r < rows.size()) {
            const int y0 = rows[r].y & ~1;
            const ScanlineRow* lo = nullptr;
            const ScanlineRow* hi = nullptr;
            if (rows[r].y == y0) {
                lo = &rows[r++];
                if (r < rows.size() && rows[r].y == y0 + 1) hi = &rows[r++];
            } else {
                hi = &rows[r++];
            }
            const int left =
                std::min(lo != nullptr ? lo->x0 : hi->x0, hi != nullptr ? hi->x0 : lo->x0);
            const int right =
                std::max(lo != nullptr ? lo->x1 : hi->x1, hi != nullptr ? hi->x1 : lo->x1);
            for (int chunk = left & ~15; chunk < right; chunk += 16) {
                const std::uint32_t lo_bits = run_bits(lo, chunk);
                const std::uint32_t hi_bits = run_bits(hi, chunk);
                std::size_t n = 0;
                for (unsigned j = 0; j < 8; ++j) {
                    // Pixels 0 and 1 of the quad on the lower row, 2 and 3 on the upper one
                    // (quad_bit(k, 0) = k).
                    const std::uint32_t mask =
                        ((lo_bits >> (2 * j)) & 3u) | (((hi_bits >> (2 * j)) & 3u) << 2);
                    if (mask != 0)
                        batch[n++] = {chunk + 2 * static_cast<int>(j), y0,
                                      static_cast<std::uint16_t>(mask)};
                }
                if (n != 0) emit(std::span<const QuadPacket>(batch.data(), n));
            }
        }
    }

    ScanlineKernel kernel() const {
        if (lazy_ != nullptr) {
            return {ctx_.draw,
                    ctx_.target,
                    *lazy_,
                    ctx_.profile.gl.flush_denormals,
                    ctx_.profile.gl.depth_rounding == Rounding::Nearest,
                    sampler_ ? &*sampler_ : nullptr};
        }
        return {ctx_.draw,
                ctx_.target,
                *tiles_,
                ctx_.profile.gl.flush_denormals,
                ctx_.profile.gl.depth_rounding == Rounding::Nearest,
                sampler_ ? &*sampler_ : nullptr};
    }

    // A scanline draw in a render of the other family wrote a tile cache of its own: written
    // back at the draw's end.
    void finish_draw() {
        if (own_tiles_) own_tiles_->flush();
        if (own_lazy_) own_lazy_->flush();
    }

  private:
    friend class DrawModule<SoftpipeModel, ScanlineList>;

    template <class Observer>
    void triangles(VertexStage& stage, Observer& obs);
    template <class Observer>
    void triangle(const VertexStage& stage, const std::array<const StageVertex*, 3>& v,
                  bool clipped, bool sprite, Observer& obs,
                  const std::array<std::array<float, 2>, 3>* point_coords = nullptr);
    template <class Observer>
    void segment(const VertexStage& stage, const StageVertex& v1, const StageVertex& v2,
                 Observer& obs);
    template <class Observer>
    void wide_segment(const VertexStage& stage, const StageVertex& v0, const StageVertex& v1,
                      float width, Observer& obs);
    template <class Observer>
    void point(const VertexStage& stage, const StageVertex& v, Observer& obs);
    // Appends a primitive of `rows` with planes made by `plane(value_of_vertex)`.
    ScanlinePrimitive& add_primitive(std::span<const ScanlineRow> rows, ScanlineInterp interp);

    std::optional<SoftpipeTileCache> own_tiles_;
    SoftpipeTileCache* tiles_ = nullptr;         // the render's cache, or the draw's own
    std::optional<SoftpipeLazyTiles> own_lazy_;  // the same on the fast path
    SoftpipeLazyTiles* lazy_ = nullptr;
    std::optional<SoftpipeSampler> sampler_;  // of the draw's texture, if it samples one
    ScanlineTriangle triangle_;  // the triangle being set up (its rows' storage is reused)
    std::vector<ScanlineRow> rows_;
};

}  // namespace refraster::detail
